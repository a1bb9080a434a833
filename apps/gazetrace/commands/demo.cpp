// `gazetrace demo`: the real-time window: its options and what it prints.
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "demo_command.hpp"
#include "option_parsing.hpp"
#include "shared_options.hpp"

namespace gt::app {

namespace {

class DemoCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "demo",
            "Real-time window: foveated rendering driven by the mouse, a trace or the tracker");
        mCommand
            ->add_option("--scene", mOptions.scene,
                         "builtin:NAME | FILE.gltf | FILE.glb | cubemap:FILE")
            ->capture_default_str();
        addAnimationOptions(mCommand, mOptions.animation, mOptions.time);
        mCommand->add_option("--width", mOptions.width, "Window width at start")
            ->check(CLI::Range(16u, 8192u))
            ->capture_default_str();
        mCommand->add_option("--height", mOptions.height, "Window height at start")
            ->check(CLI::Range(16u, 8192u))
            ->capture_default_str();
        addLiveMethodOptions(mCommand, mOptions.method, mOptions.interp, mOptions.k, mOptions.scale,
                             mOptions.raysPerPoint, mOptions.spp, mTaa, mOptions.slope,
                             mOptions.layers);
        mCommand->add_option("--view", mOptions.view,
                             "Debug view: points | cells | eccentricity | motion");
        addIntegratorOptions(mCommand, mOptions.integrator, "Foveated and reference");
        mCommand
            ->add_option("--gaze", mOptions.gaze,
                         "mouse | fixed:X,Y | trace:FILE.csv | track:SOURCE | udp:PORT")
            ->capture_default_str();
        mCommand->add_option("--calibration", mOptions.calibration,
                             "Calibration file for --gaze track: (written by --calibrate)");
        mCommand->add_flag(
            "--calibrate", mOptions.calibrate,
            "Show 3x3 calibration and 4 validation targets, fit --gaze track:SOURCE, "
            "write --calibration");
        mCommand
            ->add_option("--frame-ms", mOptions.frameMs,
                         "Advance trace and camera-path time this much per frame (default: "
                         "wall clock)")
            ->check(CLI::Range(0.0, 10000.0));
        mCommand->add_option("--frames", mOptions.frames, "Render this many frames, then exit")
            ->check(CLI::Range(0u, 10000000u));
        mCommand->add_option("--screenshot", mOptions.screenshot,
                             "Save the last presented frame (PNG)");
        mCommand->add_option("--camera", mOptions.camera, "Start camera X,Y,Z,TX,TY,TZ[,FOV]");
        mCommand->add_option("--camera-path", mOptions.cameraPath,
                             "Play a camera path CSV t_ms,ex,ey,ez,tx,ty,tz (R records one)");
        mCommand->add_option("--present", mOptions.present, "fifo | mailbox | immediate")
            ->capture_default_str();
        mCommand
            ->add_option("--frames-in-flight", mOptions.framesInFlight,
                         "1..4; 0 = automatic (1 on a CPU driver, 2 on a GPU)")
            ->check(CLI::Range(0u, 4u))
            ->capture_default_str();
        mCommand->add_flag("--validate", mOptions.validate, "Khronos validation layer");
        mCommand->add_option("--overlay", mOverlay, "on | off: the settings and timings overlay")
            ->check(CLI::IsMember({"on", "off"}))
            ->capture_default_str();
        mCommand->add_option("--log", mOptions.log, "Per-frame CSV: GPU time, gaze, latency");
        mCommand->add_option("--cache", mOptions.cacheDir, "Point-set cache folder");
        mCommand->add_flag("--json", mJson, "Print a JSON summary");
        mCommand->add_option("--resize", mOptions.resize,
                             "FRAME:WxH: resize the window then (tests)");
        mCommand->add_option("--hmd", mOptions.hmd,
                             "HMD path: " + hmdChoicesText() +
                                 ", both eyes side by side in the window");
        mCommand->add_flag("--no-distortion", mNoDistortion, "--hmd: no lens pre-distortion");
        mCommand->add_flag("--display-space", mOptions.displaySpace,
                           "--hmd: lay the point set on the panel after the lens");
        mCommand
            ->add_option("--vergence-m", mOptions.vergenceM,
                         "--hmd: distance the eyes converge at in metres (0: infinity)")
            ->check(CLI::Range(0.0, 1e6));
    }

    int run() override {
        mOptions.taa = mTaa == "on";
        mOptions.distortion = !mNoDistortion;
        mOptions.overlay = mOverlay == "on";
        mOptions.given = {mCommand->count("--interp") > 0, mCommand->count("--k") > 0,
                          mCommand->count("--scale") > 0, mCommand->count("--rays-per-point") > 0};
        // --calibrate writes --calibration; otherwise the run reads it.
        const std::string written = mOptions.calibrate ? mOptions.calibration : "";
        const std::string read = mOptions.calibrate ? "" : mOptions.calibration;
        checkRunFiles({{"--screenshot", mOptions.screenshot},
                       {"--log", mOptions.log},
                       {"--calibration", written}},
                      {{"--scene", mOptions.scene},
                       {"--gaze", mOptions.gaze},
                       {"--calibration", read},
                       {"--camera-path", mOptions.cameraPath}});
        const nlohmann::json result = runDemo(mOptions);
        if (mJson) std::cout << result.dump() << std::endl;
        return 0;
    }

private:
    DemoOptions mOptions;
    std::string mTaa = "on";
    bool mJson = false;
    std::string mOverlay = "on";
    bool mNoDistortion = false;
};

} // namespace

std::unique_ptr<Command> makeDemoCommand() {
    return std::make_unique<DemoCommand>();
}

} // namespace gt::app
