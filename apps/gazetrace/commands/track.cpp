// `gazetrace track`: pupil and gaze from a frame source: its options and what it prints.
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "core/error.hpp"
#include "eye_commands.hpp"
#include "shared_options.hpp"

namespace gt::app {

namespace {

class TrackCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "track", "Track the pupil (and gaze, when calibrated) from a frame source");
        CLI::Option* source = mCommand->add_option(
            "--source", mOptions.source,
            "v4l2:/dev/videoN[?...] | video:FILE | images:DIR | synthetic:SEED[?...]");
        CLI::Option* left = mCommand->add_option("--source-left", mOptions.sourceLeft,
                                                 "Two eyes: the left eye's camera");
        CLI::Option* right = mCommand->add_option("--source-right", mOptions.sourceRight,
                                                  "Two eyes: the right eye's camera");
        mCommand
            ->add_option("--regions", mOptions.regions,
                         "Two eyes in one --source: X,Y,W,H;X,Y,W,H (left eye; right eye)")
            ->excludes(left)
            ->excludes(right);
        source->excludes(left)->excludes(right);
        mCommand->add_option("--truth-right", mOptions.truthRight,
                             "Two eyes: the right eye's truth (--truth: the left's)");
        mCommand->add_option("--ipd-mm", mOptions.ipdMm, "Two eyes: interpupillary distance")
            ->check(CLI::Range(40.0, 80.0))
            ->capture_default_str();
        mCommand->add_option("--detector", mOptions.detector, "Pupil detector: starburst or blob")
            ->capture_default_str();
        mCommand->add_option("--calibration", mOptions.calibration,
                             "Calibration JSON (gazetrace calibrate)");
        mCommand->add_option("--truth", mOptions.truth,
                             "Truth CSV (gazetrace eyesim) to score the detector");
        mCommand->add_option("--out", mOptions.out,
                             "Gaze CSV t_ms,x,y (replays with render --gaze-trace)");
        mCommand->add_option("--pupils", mOptions.pupils, "Per-frame pupil CSV");
        mCommand->add_option("--emit", mOptions.emit,
                             "Send each gaze sample as JSON to udp://HOST:PORT");
        mCommand->add_option(
            "--contact-sheet", mOptions.contactSheet,
            "PNG of every --sheet-every-th frame (up to 48) with the fitted pupil");
        mCommand
            ->add_option("--sheet-every", mOptions.sheetEvery, "Frames between contact-sheet tiles")
            ->check(CLI::Range(1, 1000000));
        mCommand->add_option("--max-frames", mOptions.maxFrames, "Stop after this many frames")
            ->check(CLI::Range(0, 100000000));
        mCommand
            ->add_option("--model", mOptions.model, "Gaze model: 2d (polynomial) or 3d (eye model)")
            ->capture_default_str();
        mCommand
            ->add_option("--eye", mOptions.eye, "Eye of the calibration file: both, left or right")
            ->capture_default_str();
        mCommand->add_option(
            "--intrinsics", mOptions.camera.intrinsics,
            "Eye camera intrinsics JSON for --model 3d (default: the calibration's)");
        mCommand->add_option("--focal", mOptions.camera.focal, "Eye camera focal length, pixels");
        mCommand->add_option("--principal", mOptions.camera.principal,
                             "Eye camera principal point X,Y");
        mCommand->add_flag("--cold", mOptions.cold,
                           "Forget the detector's history before every frame (single images)");
        mCommand->add_flag("--json", mJson, "Print a JSON summary on stdout");
    }

    int run() override {
        if (mOptions.source.empty() && mOptions.sourceLeft.empty() && mOptions.sourceRight.empty())
            throw ArgumentError("track: --source (or --source-left and --source-right)");
        checkRunFiles({{"--out", mOptions.out},
                       {"--pupils", mOptions.pupils},
                       {"--contact-sheet", mOptions.contactSheet}},
                      {{"--source", mOptions.source},
                       {"--source-left", mOptions.sourceLeft},
                       {"--source-right", mOptions.sourceRight},
                       {"--calibration", mOptions.calibration},
                       {"--truth", mOptions.truth},
                       {"--truth-right", mOptions.truthRight},
                       {"--intrinsics", mOptions.camera.intrinsics}});
        const nlohmann::json result = runTrack(mOptions);
        std::cout << (mJson ? result.dump() : result.dump(2)) << std::endl;
        return 0;
    }

private:
    TrackOptions mOptions;
    bool mJson = false;
};

} // namespace

std::unique_ptr<Command> makeTrackCommand() {
    return std::make_unique<TrackCommand>();
}

} // namespace gt::app
