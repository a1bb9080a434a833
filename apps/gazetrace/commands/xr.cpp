// `gazetrace xr`: the OpenXR application: its options and what it prints.
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "shared_options.hpp"
#include "xr_command.hpp"

namespace gt::app {

namespace {

class XrCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "xr", "OpenXR application: both eyes foveated into the runtime's swapchains, eye gaze "
                  "from the runtime or gazetrace's own sources");
        mCommand
            ->add_option("--scene", mOptions.scene,
                         "builtin:NAME | FILE.gltf | FILE.glb | cubemap:FILE")
            ->capture_default_str();
        addAnimationOptions(mCommand, mOptions.animation, mOptions.time);
        mCommand->add_option(
            "--camera", mOptions.camera,
            "Start view X,Y,Z,TX,TY,TZ[,FOV]: the viewer stands at X,Y,Z facing the "
            "target (default: the scene's camera, or a view inside it)");
        mCommand->add_option("--xr-origin", mOptions.origin,
                             "X,Y,Z: the scene point at the reference space's origin (default: the "
                             "start view's eye; with --xr-space stage, 1.6 m below it)");
        mCommand->add_option(
            "--xr-yaw", mOptions.yawDeg,
            "Degrees: the scene direction the viewer faces (default: the start view's)");
        mCommand
            ->add_option("--xr-scale", mOptions.worldScale, "Scene units per metre the head moves")
            ->check(CLI::Range(1e-6, 1e6))
            ->capture_default_str();
        mCommand
            ->add_option("--xr-space", mOptions.space,
                         "local | stage (floor-level; LOCAL if not offered)")
            ->capture_default_str();
        mCommand
            ->add_option("--resolution-scale", mOptions.resolutionScale,
                         "Eye image size as a share of the runtime's recommended size")
            ->check(CLI::Range(0.05, 4.0))
            ->capture_default_str();
        addLiveMethodOptions(mCommand, mOptions.method, mOptions.interp, mOptions.k,
                             mOptions.pointScale, mOptions.raysPerPoint, mOptions.spp, mTaa,
                             mOptions.slope, mOptions.layers);
        addReconstructionOption(mCommand, mOptions.reconstruction);
        addIntegratorOptions(mCommand, mOptions.integrator, "Foveated and reference");
        mCommand
            ->add_option("--gaze", mOptions.gaze,
                         "Gaze when the runtime gives none: ahead | fixed:X,Y (left eye pixels) | "
                         "trace:FILE.csv | track:SOURCE | udp:PORT")
            ->capture_default_str();
        mCommand->add_option("--calibration", mOptions.calibration,
                             "Calibration file for --gaze track:");
        mCommand
            ->add_option("--vergence-m", mOptions.vergenceM,
                         "Distance the eyes converge at in metres (0: infinity)")
            ->check(CLI::Range(0.0, 1e6))
            ->capture_default_str();
        mCommand->add_flag("--no-runtime-gaze", mNoRuntimeGaze,
                           "Ignore XR_EXT_eye_gaze_interaction; use --gaze only");
        mCommand
            ->add_option("--frames", mOptions.frames,
                         "Render this many frames, then end the session")
            ->check(CLI::Range(0u, 10000000u))
            ->capture_default_str();
        mCommand
            ->add_option("--screenshot-eye", mScreenshotEye,
                         "left|right FILE.png: that eye's last image")
            ->expected(2);
        mCommand
            ->add_option("--start-timeout", mOptions.startTimeoutS,
                         "Seconds the session may take to start running")
            ->check(CLI::Range(0.001, 86400.0))
            ->capture_default_str();
        mCommand->add_flag("--validate", mOptions.validate, "Khronos validation layer");
        mCommand->add_option("--cache", mOptions.cacheDir, "Point-set cache folder");
        mCommand->add_flag("--json", mJson, "Print a JSON summary");
    }

    int run() override {
        mOptions.taa = mTaa == "on";
        mOptions.runtimeGaze = !mNoRuntimeGaze;
        if (mScreenshotEye.size() == 2) {
            mOptions.screenshotEye = mScreenshotEye[0];
            mOptions.screenshot = mScreenshotEye[1];
        }
        checkRunFiles({{"--screenshot-eye", mOptions.screenshot}},
                      {{"--scene", mOptions.scene},
                       {"--gaze", mOptions.gaze},
                       {"--calibration", mOptions.calibration}});
        const nlohmann::json result = runXr(mOptions);
        if (mJson) std::cout << result.dump() << std::endl;
        return 0;
    }

private:
    XrOptions mOptions;
    bool mJson = false;
    std::string mTaa = "on";
    bool mNoRuntimeGaze = false;
    std::vector<std::string> mScreenshotEye{};
};

} // namespace

std::unique_ptr<Command> makeXrCommand() {
    return std::make_unique<XrCommand>();
}

} // namespace gt::app
