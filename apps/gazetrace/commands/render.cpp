// `gazetrace render`: one frame or a sequence headless to PNGs: its options and what it prints.
#include <cctype>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "core/log.hpp"
#include "option_parsing.hpp"
#include "render_command.hpp"
#include "shared_options.hpp"
#include "trace/integrator.hpp"

namespace gt::app {

namespace {

class RenderCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand("render", "Render one frame headless to a PNG");
        mCommand
            ->add_option(
                "--scene", mOptions.scene,
                "builtin:market | builtin:cornell | builtin:gallery | FILE.gltf | FILE.glb | "
                "cubemap:FILE")
            ->capture_default_str();
        mCommand->add_option("--camera", mOptions.camera,
                             "Camera X,Y,Z,TX,TY,TZ[,FOV]: eye, look-at target (scene units), "
                             "vertical field of view in degrees (default: the scene's camera)");
        addSizeOptions(mCommand, mOptions.width, mOptions.height, 1u, "Image");
        addAnimationOptions(mCommand, mOptions.animation, mOptions.time);
        mCommand->add_option("--spp", mOptions.spp, "Rays per pixel (stratified, jittered)")
            ->check(CLI::Range(1u, 4096u))
            ->capture_default_str();
        mCommand->add_option("--seed", mOptions.seed, "Frame seed for the jitter")
            ->capture_default_str();
        mCommand->add_option("--method", mOptions.method, "reference | foveated | layers")
            ->capture_default_str();
        mCommand->add_option("--slope", mOptions.slope, "Layers: MAR slope A | B | VALUE")
            ->capture_default_str();
        mCommand->add_option("--layers", mOptions.layers, "Layers: number of eccentricity layers")
            ->check(CLI::Range(1u, 4u))
            ->capture_default_str();
        mCommand
            ->add_option("--half-rate", mHalfRate,
                         "Layers: outer layers at half the frame rate, staggered (on | off)")
            ->check(CLI::IsMember({"on", "off"}))
            ->capture_default_str();
        mCommand->add_option("--jitter", mJitter, "Layers: per-frame grid jitter (on | off)")
            ->check(CLI::IsMember({"on", "off"}))
            ->capture_default_str();
        mCommand
            ->add_option("--lod", mLod,
                         "Geometric LOD of subdivision cages by sampling pitch (on | off)")
            ->check(CLI::IsMember({"on", "off"}))
            ->capture_default_str();
        mCommand->add_option("--out", mOptions.out, "Output PNG, or a folder for frame_NNNN.png")
            ->capture_default_str();
        mCommand
            ->add_option("--profile", mOptions.profile,
                         "Foveated: display profile fove | vive | desktop")
            ->check(CLI::IsMember({"fove", "vive", "desktop"}))
            ->capture_default_str();
        mCommand->add_option("--interp", mOptions.interp, "Foveated: interpolation nn | msm | rbf")
            ->check(CLI::IsMember({"nn", "msm", "rbf"}))
            ->capture_default_str();
        mCommand
            ->add_option("--kernel", mOptions.kernel,
                         "Foveated RBF kernel: multiquadric | gaussian")
            ->check(CLI::IsMember({"multiquadric", "gaussian"}))
            ->capture_default_str();
        mCommand
            ->add_option(
                "--knn", mOptions.knn,
                "Foveated msm/rbf neighbours: table (the thesis's k nearest per canvas "
                "pixel; rbf adds per-pixel weights) | lists (nearest point + its neighbour "
                "list, rbf solved per point each frame: less memory, slower)")
            ->check(CLI::IsMember({"lists", "table"}))
            ->capture_default_str();
        mCommand
            ->add_option("--rbf-c", mOptions.rbfShape,
                         "Foveated RBF shape c, in units of the point spacing")
            ->check(CLI::Range(0.001, 1000.0))
            ->capture_default_str();
        addReconstructionOption(mCommand, mOptions.reconstruction);
        addIntegratorOptions(mCommand, mOptions.integrator, "Reference and foveated");
        mCommand->add_option("--k", mOptions.k, "Foveated: neighbours for msm and rbf (1-20)")
            ->check(CLI::Range(1u, 20u))
            ->capture_default_str();
        mCommand->add_option("--scale", mOptions.scale, "Foveated: point-set scaling value")
            ->check(CLI::Range(0.01, 100.0))
            ->capture_default_str();
        mCommand->add_option("--rays-per-point", mOptions.raysPerPoint, "Foveated: rays per point")
            ->check(CLI::Range(1u, 4096u))
            ->capture_default_str();
        mCommand->add_option("--gaze", mOptions.gaze,
                             "Foveated: gaze point X,Y in pixels (default: centre)");
        addSequenceOptions();
    }

    // The frames: how many, along what, from which gaze, and what else each writes.
    void addSequenceOptions() {
        mCommand->add_option("--frames", mOptions.frames, "Frames to render")
            ->check(CLI::Range(1u, 100000u))
            ->capture_default_str();
        mCommand->add_option("--cache", mOptions.cacheDir, "Point-set cache folder");
        mCommand->add_option(
            "--camera-path", mOptions.cameraPath,
            "Camera path CSV t_ms,ex,ey,ez,tx,ty,tz (demo's R records one): a frame "
            "every --frame-ms along it");
        mCommand->add_option("--hmd", mOptions.hmd,
                             "HMD path: " + hmdChoicesText() +
                                 " (both eyes, side by side, lens pre-distortion; --gaze is a "
                                 "pixel of the left eye's image)");
        mCommand->add_flag("--no-distortion", mNoDistortion,
                           "--hmd: the eyes as rendered, no lens");
        mCommand->add_flag("--display-space", mOptions.displaySpace,
                           "--hmd, foveated: lay the point set on the panel after the lens");
        mCommand
            ->add_option("--vergence-m", mOptions.vergenceM,
                         "--hmd: distance the eyes converge at in metres (0: infinity)")
            ->check(CLI::Range(0.0, 1e6));
        mCommand
            ->add_option("--gaze-trace", mOptions.gazeTrace, "Foveated: gaze trace CSV (t_ms,x,y)")
            ->check(CLI::ExistingFile);
        mCommand->add_option("--gaze-source", mOptions.gazeSource,
                             "Foveated: live gaze from the eye tracker on this source "
                             "(v4l2:/dev/videoN, video:FILE, ...); needs --calibration");
        mCommand->add_option("--calibration", mOptions.calibration,
                             "Calibration JSON for --gaze-source (gazetrace calibrate)");
        mCommand
            ->add_option("--frame-ms", mOptions.frameMs, "Time between frames along the gaze trace")
            ->check(CLI::Range(0.1, 10000.0))
            ->capture_default_str();
        mCommand
            ->add_option("--view", mOptions.view,
                         "Foveated debug view: points | cells | eccentricity | motion")
            ->check(CLI::IsMember({"points", "cells", "eccentricity", "motion"}));
        mCommand->add_option("--taa", mTaa, "Foveated: temporal anti-aliasing on | off")
            ->check(CLI::IsMember({"on", "off"}))
            ->capture_default_str();
        mCommand->add_option("--graph", mOptions.graphDot,
                             "Write the compiled render graph as Graphviz");
        mCommand->add_flag("--validate", mOptions.validate, "Enable the Khronos validation layer");
        mCommand->add_flag("--json", mJson, "Print a JSON summary on stdout");
    }

    int run() override {
        mOptions.taa = mTaa == "on";
        mOptions.halfRate = mHalfRate == "on";
        mOptions.jitter = mJitter == "on";
        mOptions.lod = mLod == "on";
        mOptions.distortion = !mNoDistortion;
        mOptions.framesGiven = mCommand->count("--frames") > 0;
        mOptions.sizeGiven = mCommand->count("--width") + mCommand->count("--height") > 0;
        // --out is one PNG, or else a folder of frames (which the run stages itself).
        std::string ext = std::filesystem::path(mOptions.out).extension().string();
        for (char& c : ext)
            c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        checkRunFiles(
            {{"--out", ext == ".png" ? mOptions.out : ""}, {"--graph", mOptions.graphDot}},
            {{"--scene", mOptions.scene},
             {"--camera-path", mOptions.cameraPath},
             {"--gaze-trace", mOptions.gazeTrace},
             {"--gaze-source", mOptions.gazeSource},
             {"--calibration", mOptions.calibration}});
        const nlohmann::json result = runRender(mOptions);
        if (mJson)
            std::cout << result.dump() << std::endl;
        else
            log::info("wrote " + mOptions.out);
        return 0;
    }

private:
    RenderOptions mOptions;
    bool mJson = false;
    std::string mHalfRate = "on";
    std::string mJitter = "on";
    std::string mLod = "on";
    bool mNoDistortion = false;
    std::string mTaa = "on";
};

} // namespace

std::unique_ptr<Command> makeRenderCommand() {
    return std::make_unique<RenderCommand>();
}

} // namespace gt::app
