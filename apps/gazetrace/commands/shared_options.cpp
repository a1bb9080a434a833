#include "shared_options.hpp"

#include <vector>

#include <CLI/CLI.hpp>

#include "option_parsing.hpp"

namespace gt::app {

void addSizeOptions(CLI::App* cmd, uint32_t& width, uint32_t& height, uint32_t min,
                    const std::string& what) {
    cmd->add_option("--width", width, what + " width in pixels")
        ->check(CLI::Range(min, 16384u))
        ->capture_default_str();
    cmd->add_option("--height", height, what + " height in pixels")
        ->check(CLI::Range(min, 16384u))
        ->capture_default_str();
}

void addAnimationOptions(CLI::App* cmd, std::string& animation, double& startSeconds) {
    cmd->add_option("--animation", animation,
                    "Animated glTF: the animation that plays (NAME | INDEX | all | none)")
        ->capture_default_str();
    cmd->add_option("--time", startSeconds, "Animated glTF: scene time of the first frame (s)")
        ->check(CLI::Range(0.0, 1e9))
        ->capture_default_str();
}

void addLiveMethodOptions(CLI::App* cmd, std::string& method, std::string& interp, uint32_t& k,
                          double& scale, uint32_t& raysPerPoint, uint32_t& spp, std::string& taa,
                          std::string& slope, uint32_t& layers) {
    cmd->add_option("--method", method, "foveated | layers | reference")->capture_default_str();
    cmd->add_option("--slope", slope, "Layers: MAR slope A | B | VALUE")->capture_default_str();
    cmd->add_option("--layers", layers, "Layers: number of eccentricity layers")
        ->check(CLI::Range(1u, 4u))
        ->capture_default_str();
    cmd->add_option("--interp", interp, "nn | msm | rbf")->capture_default_str();
    cmd->add_option("--k", k, "Neighbours for msm / rbf")
        ->check(CLI::Range(1u, 20u))
        ->capture_default_str();
    cmd->add_option("--scale", scale, "Point-set scaling value (sparser above 1)")
        ->check(CLI::Range(0.25, 8.0))
        ->capture_default_str();
    cmd->add_option("--rays-per-point", raysPerPoint, "Rays traced per point")
        ->check(CLI::Range(1u, 1024u))
        ->capture_default_str();
    cmd->add_option("--spp", spp, "Rays per pixel (reference) or per layer pixel (layers)")
        ->check(CLI::Range(1u, 1024u))
        ->capture_default_str();
    cmd->add_option("--taa", taa, "on | off")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
}

void addReconstructionOption(CLI::App* cmd, std::string& reconstruction) {
    cmd->add_option(
           "--reconstruction", reconstruction,
           "Foveated: gazetrace | thesis (the thesis's interpolation and TAA as published)")
        ->check(CLI::IsMember({"gazetrace", "thesis"}))
        ->capture_default_str();
}

void addIntegratorOptions(CLI::App* cmd, IntegratorArgs& args, const std::string& who) {
    cmd->add_option("--integrator", args.integrator,
                    who + ": direct (direct light, one mirror bounce) | path (path tracing, "
                          "docs/path-tracing.md)")
        ->check(CLI::IsMember({"direct", "path"}))
        ->capture_default_str();
    cmd->add_option("--bounces", args.bounces,
                    "--integrator path: scattering vertices per path (1: direct light only)")
        ->check(CLI::Range(1u, trace::kMaxBounces))
        ->capture_default_str();
    cmd->add_option("--sequence", args.sequence,
                    "--integrator path: what the paths' random decisions draw from: sobol "
                    "(Owen-scrambled, stratified over rays and frames) | independent")
        ->check(CLI::IsMember({"sobol", "independent"}))
        ->capture_default_str();
    cmd->add_option("--fovea-rays", args.foveaRays,
                    "Foveated: rays per point within 5 degrees of the gaze (paths per point by "
                    "eccentricity; 0: --rays-per-point)")
        ->check(CLI::Range(0u, 4096u))
        ->capture_default_str();
    cmd->add_option("--denoise", args.denoise,
                    "The spatial denoiser before TAA, stronger with eccentricity, none within 5 "
                    "degrees of the gaze (docs/path-tracing.md): off | on | image | points | "
                    "both (a point set's samples before interpolation, the image, or both; on: "
                    "both)")
        ->check(CLI::IsMember({"off", "on", "image", "points", "both"}))
        ->capture_default_str();
}

void addNumberChecks(CLI::App& app) {
    // No description: --help and the README's options table stay as they were.
    const CLI::Validator finite([](std::string& text) { return finiteNumberProblem(text); }, "",
                                "FINITE");
    const CLI::Validator notNegative(
        [](std::string& text) { return nonNegativeIntegerProblem(text); }, "", "NOT_NEGATIVE");
    for (CLI::Option* opt : app.get_options()) {
        const std::string type = opt->get_type_name();
        if (type.rfind("FLOAT", 0) == 0) opt->check(finite);
        if (type.rfind("UINT", 0) == 0) opt->check(notNegative);
    }
    for (CLI::App* sub : app.get_subcommands({})) {
        addNumberChecks(*sub);
    }
}

io::RunFile inputFile(const std::string& option, const std::string& value) {
    std::string v = value;
    for (bool stripped = true; stripped;) {
        stripped = false;
        for (const char* scheme : {"track:", "trace:", "video:", "images:"}) {
            if (v.rfind(scheme, 0) == 0) {
                v.erase(0, std::string(scheme).size());
                stripped = true;
            }
        }
    }
    for (const char* none : {"builtin:", "synthetic:", "v4l2:", "udp:", "fixed:"}) {
        if (v.rfind(none, 0) == 0) return {option, {}};
    }
    return {option, v};
}

void checkRunFiles(const std::vector<io::RunFile>& outputs,
                   std::initializer_list<std::pair<const char*, std::string>> inputs) {
    std::vector<io::RunFile> in;
    for (const auto& [option, value] : inputs)
        in.push_back(inputFile(option, value));
    io::refuseOutputThatIsInput(outputs, in);
    for (const io::RunFile& out : outputs) {
        if (!out.path.empty()) io::checkOutputFile(out.path);
    }
}

} // namespace gt::app
