// `gazetrace eval`: picture quality against a reference: its options and what it prints.
#include <filesystem>
#include <iostream>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "eval_command.hpp"
#include "option_parsing.hpp"
#include "shared_options.hpp"

namespace gt::app {

namespace {

class EvalCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "eval",
            "Picture quality: a foveated frame against a many-ray reference, per "
            "eccentricity band (FLIP, PSNR, SSIM), beside the uniform baseline at equal rays");
        mCommand
            ->add_option("--scene", mOptions.scene,
                         "builtin:NAME | FILE.gltf | FILE.glb | cubemap:FILE")
            ->capture_default_str();
        addAnimationOptions(mCommand, mOptions.animation, mOptions.time);
        mCommand->add_option("--camera", mOptions.camera, "X,Y,Z,TX,TY,TZ[,FOV]");
        mCommand
            ->add_option("--profile", mOptions.profile, "Display geometry: fove | vive | desktop")
            ->capture_default_str();
        mCommand
            ->add_option("--width", mOptions.width, "A window this wide on the profile's screen")
            ->check(CLI::Range(16u, 16384u));
        mCommand
            ->add_option("--height", mOptions.height, "A window this high on the profile's screen")
            ->check(CLI::Range(16u, 16384u));
        mCommand->add_option("--hmd", mOptions.hmd,
                             "A headset's left eye instead of --profile: " + hmdChoicesText());
        mCommand->add_option("--gaze", mOptions.gaze,
                             "X,Y in pixels (default: the centre; --hmd: straight ahead)");
        mCommand
            ->add_option("--method", mOptions.method,
                         "Foveated: points (the thesis's point set) | layers (Guenter et al. "
                         "2012, slope A, 3 layers)")
            ->capture_default_str();
        mCommand->add_option("--interp", mOptions.interp, "Foveated: nn | msm | rbf")
            ->capture_default_str();
        mCommand->add_option("--k", mOptions.k, "Foveated: neighbours for msm and rbf (1-20)")
            ->check(CLI::Range(1u, 20u))
            ->capture_default_str();
        mCommand->add_option("--scale", mOptions.scale, "Foveated: point-set scaling value")
            ->check(CLI::Range(0.25, 8.0))
            ->capture_default_str();
        mCommand
            ->add_option("--rays-per-point", mOptions.raysPerPoint,
                         "Foveated: rays per point (the baseline: rays per pixel)")
            ->check(CLI::Range(1u, 1024u))
            ->capture_default_str();
        addIntegratorOptions(mCommand, mOptions.integrator,
                             "Every traced frame (reference, foveated points, uniform)");
        mCommand->add_option("--taa", mTaa, "Foveated: on | off")
            ->check(CLI::IsMember({"on", "off"}))
            ->capture_default_str();
        mCommand
            ->add_option(
                "--reconstruction", mOptions.reconstruction,
                "Foveated: gazetrace (the options below) | thesis (the thesis as published)")
            ->capture_default_str();
        mCommand
            ->add_option("--blend", mOptions.blend,
                         "Foveated: interpolate display | linear radiance")
            ->capture_default_str();
        mCommand
            ->add_option("--edge-tolerance", mOptions.edgeTolerance,
                         "Foveated msm: geometry-aware weights, relative depth tolerance (0: off)")
            ->check(CLI::Range(0.0, 100.0))
            ->capture_default_str();
        mCommand
            ->add_option("--range-sigma", mOptions.rangeSigma,
                         "Foveated msm: colour-guided weights, display luminance sigma (0: off; "
                         "default 0.1, with --integrator path 0)")
            ->check(CLI::Range(0.0, 100.0));
        mCommand
            ->add_option("--shepard-power", mOptions.shepardPower,
                         "Foveated msm: q of eq. (6) (default 2, with --integrator path 1)")
            ->check(CLI::Range(0.5, 8.0));
        mCommand
            ->add_option("--still-clip", mOptions.stillClipGamma,
                         "TAA: clipping box in standard deviations with the camera still")
            ->check(CLI::Range(0.1, 100.0))
            ->capture_default_str();
        mCommand
            ->add_option("--eccentric-radius", mOptions.eccentricRadius,
                         "TAA: share of the width beyond which a moving gaze leans on the history")
            ->check(CLI::Range(0.0, 10.0))
            ->capture_default_str();
        mCommand->add_option("--jitter", mJitter, "Foveated: rotate ray positions every frame")
            ->check(CLI::IsMember({"on", "off"}))
            ->capture_default_str();
        mCommand
            ->add_option("--frames", mOptions.frames,
                         "Frames of the still view before the measured one")
            ->check(CLI::Range(1u, 1000u))
            ->capture_default_str();
        mCommand
            ->add_option("--reference-spp", mOptions.referenceSpp,
                         "Rays per pixel of the reference")
            ->check(CLI::Range(1u, 4096u))
            ->capture_default_str();
        mCommand->add_option(
            "--reference", mOptions.reference,
            "A reference PNG of the same view rendered before (skips rendering it)");
        registerComparisonOptions();
    }

    int run() override {
        mOptions.taa = mTaa == "on";
        mOptions.jitter = mJitter == "on";
        // What the run writes into --out (reference.png only when it renders the reference):
        // none of them may be one of its inputs.
        std::vector<io::RunFile> written;
        for (const char* name :
             {"eval.json", "foveated.png", "flip_foveated.png", "bands.png", "curves.png",
              "uniform_bilinear.png", "flip_uniform_bilinear.png", "uniform_catmull_rom.png",
              "flip_uniform_catmull_rom.png", "full_resolution.png", "flip_full_resolution.png",
              "match_uniform.png", "match_full.png"}) {
            written.push_back({"--out", std::filesystem::path(mOptions.out) / name});
        }
        if (mOptions.reference.empty()) {
            written.push_back({"--out", std::filesystem::path(mOptions.out) / "reference.png"});
        }
        io::refuseOutputThatIsInput(
            written, std::vector<io::RunFile>{inputFile("--scene", mOptions.scene),
                                              inputFile("--reference", mOptions.reference),
                                              inputFile("--camera-path", mOptions.cameraPath),
                                              inputFile("--pursuit", mOptions.pursuit)});
        const nlohmann::json result = runEval(mOptions);
        std::cout << (mJson ? result.dump() : evalText(result)) << std::flush;
        return 0;
    }

private:
    // What the foveated frame is compared with, and where the results go.
    void registerComparisonOptions() {
        mCommand->add_option("--baseline", mOptions.baseline, "uniform | none")
            ->capture_default_str();
        mCommand->add_flag(
            "--temporal", mOptions.temporal,
            "Also the frame-to-frame change of a still view, and an animated scene's "
            "moving error against a reference at each instant");
        mCommand->add_option(
            "--camera-path", mOptions.cameraPath,
            "A moving camera (CSV t_ms,ex,ey,ez,tx,ty,tz): change after reprojection");
        mCommand->add_option("--pursuit", mOptions.pursuit,
                             "A gaze trace in pixels (CSV t_ms,x,y) followed over the still scene");
        mCommand
            ->add_option("--sequence-frames", mOptions.sequenceFrames, "Frames of each sequence")
            ->check(CLI::Range(2u, 10000u))
            ->capture_default_str();
        mCommand->add_flag("--sweep", mOptions.sweep,
                           "Quality against rays: point-set scales 1, 1.5, 2, 3");
        mCommand->add_option("--match", mOptions.match,
                             "Equal picture quality: the cheapest uniform render whose flip_ecc is "
                             "no higher in every band: uniform (lowest resolution, upscaled) | "
                             "full (fewest rays per pixel at full size)");
        mCommand
            ->add_option("--match-doublings", mOptions.matchDoublings,
                         "--match uniform: times the search may double the rays per pixel where "
                         "even full size does not match (default 3: up to 8x the rays per point)")
            ->check(CLI::Range(0u, 6u));
        mCommand->add_option("--out", mOptions.out, "Folder for eval.json and the PNGs")
            ->capture_default_str();
        mCommand->add_option("--cache", mOptions.cacheDir, "Point-set cache folder");
        mCommand->add_flag("--validate", mOptions.validate, "Enable the Khronos validation layer");
        mCommand->add_flag("--json", mJson, "Print the JSON summary instead of the table");
    }

    EvalOptions mOptions;
    bool mJson = false;
    std::string mTaa = "on";
    std::string mJitter = "on";
};

} // namespace

std::unique_ptr<Command> makeEvalCommand() {
    return std::make_unique<EvalCommand>();
}

} // namespace gt::app
