// `gazetrace eyesim`: synthetic infrared eye clips: its options and what it prints.
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "eye_commands.hpp"
#include "shared_options.hpp"

namespace gt::app {

namespace {

class EyesimCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand =
            app.add_subcommand("eyesim", "Render a synthetic infrared eye clip with ground truth");
        mCommand->add_option("--seed", mOptions.seed, "Random seed (eye, schedule, noise)")
            ->capture_default_str();
        mCommand->add_option("--frames", mOptions.frames, "Frames to render")
            ->check(CLI::Range(1, 1000000))
            ->capture_default_str();
        mCommand->add_option("--size", mOptions.size, "Image size WxH")->capture_default_str();
        mCommand->add_option("--fps", mOptions.fps, "Camera frame rate")
            ->check(CLI::Range(1.0, 2000.0))
            ->capture_default_str();
        mCommand
            ->add_option("--preset", mOptions.preset,
                         "clean | hard (lid occlusion, 4 glints, blur, noise, blinks) | wild "
                         "(perspective camera, mascara, shadows, low contrast... drawn per seed)")
            ->check(CLI::IsMember({"clean", "hard", "wild"}))
            ->capture_default_str();
        mCommand->add_option("--grid", mOptions.grid, "Calibration targets: 5, 9 or 13")
            ->check(CLI::IsMember({5, 9, 13}))
            ->capture_default_str();
        mCommand
            ->add_option("--target-ms", mOptions.targetMs,
                         "Time on each calibration / validation target")
            ->check(CLI::Range(100.0, 10000.0))
            ->capture_default_str();
        mCommand->add_option("--out", mOptions.out, "Video file (.mkv or .avi, lossless FFV1)")
            ->required();
        mCommand->add_option("--truth", mOptions.truth, "Per-frame truth CSV")->required();
        mCommand->add_flag("--perspective", mOptions.perspective,
                           "Pinhole camera (the wild preset always has one)");
        mCommand->add_option("--intrinsics-out", mOptions.intrinsicsOut,
                             "Write the eye camera's intrinsics (JSON) for --model 3d");
        mCommand->add_option("--slip-mm", mOptions.slipMm,
                             "Headset slippage X,Y,Z in mm (camera frame), from --slip-at-ms on");
        mCommand
            ->add_option("--slip-deg", mOptions.slipDeg, "Headset turn with the slippage (degrees)")
            ->check(CLI::Range(-20.0, 20.0));
        mCommand
            ->add_option("--slip-at-ms", mOptions.slipAtMs, "When the headset slips (default 0)")
            ->check(CLI::Range(0.0, 1e9));
        mCommand->add_option("--eye", mOptions.eye,
                             "left or right (binocular clips, one camera per eye), or both (one "
                             "frame with both eyes side by side; --truth-right for the right's)");
        mCommand->add_option("--ipd-mm", mOptions.ipdMm, "Interpupillary distance")
            ->check(CLI::Range(40.0, 80.0))
            ->capture_default_str();
        mCommand->add_option("--depth-cm", mOptions.depthCm,
                             "Free viewing converges at this distance (0: on the screen)");
        mCommand->add_option("--truth-right", mOptions.truthRight,
                             "--eye both: the right eye's truth");
        mCommand->add_flag("--json", mJson, "Print a JSON summary on stdout");
    }

    int run() override {
        checkRunFiles({{"--out", mOptions.out},
                       {"--truth", mOptions.truth},
                       {"--truth-right", mOptions.truthRight},
                       {"--intrinsics-out", mOptions.intrinsicsOut}},
                      {});
        const nlohmann::json result = runEyesim(mOptions);
        if (mJson) std::cout << result.dump() << std::endl;
        return 0;
    }

private:
    EyesimOptions mOptions;
    bool mJson = false;
};

} // namespace

std::unique_ptr<Command> makeEyesimCommand() {
    return std::make_unique<EyesimCommand>();
}

} // namespace gt::app
