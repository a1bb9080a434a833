// `gazetrace calibrate`: the pupil-to-screen calibration from a recording: its options and what it
// prints.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <utility>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "core/error.hpp"
#include "eye_commands.hpp"
#include "shared_options.hpp"

namespace gt::app {

namespace {

class CalibrateCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "calibrate", "Fit pupil-to-screen calibration from a recording with known targets");
        CLI::Option* left = mCommand->add_option("--source-left", mOptions.sourceLeft,
                                                 "Two eyes: the left eye's recording");
        CLI::Option* right = mCommand->add_option("--source-right", mOptions.sourceRight,
                                                  "Two eyes: the right eye's recording");
        mCommand
            ->add_option("--regions", mOptions.regions,
                         "Two eyes in one --source: X,Y,W,H;X,Y,W,H (left eye; right eye)")
            ->excludes(left)
            ->excludes(right);
        mCommand->add_option("--source", mOptions.source, "Frame source of the recording")
            ->excludes(left)
            ->excludes(right);
        mCommand->add_option("--detector", mOptions.detector, "Pupil detector: starburst or blob")
            ->capture_default_str();
        mCommand
            ->add_option("--targets", mOptions.targets,
                         "Target schedule CSV (t_ms,target_x,target_y[,phase,target_index])")
            ->required();
        mCommand->add_option("--out", mOptions.out, "Calibration JSON to write")->required();
        mCommand->add_option("--intrinsics", mOptions.camera.intrinsics,
                             "Eye camera intrinsics JSON: also calibrate the 3D eye model");
        mCommand->add_option("--focal", mOptions.camera.focal, "Eye camera focal length, pixels");
        mCommand->add_option("--principal", mOptions.camera.principal,
                             "Eye camera principal point X,Y");
        mCommand
            ->add_option("--settle-ms", mOptions.settleMs,
                         "Ignore this long after each target appears")
            ->check(CLI::Range(0.0, 10000.0))
            ->capture_default_str();
        mCommand->add_option("--screen", mScreen, "Screen size in pixels WxH")
            ->capture_default_str();
        mCommand->add_option("--screen-width-cm", mOptions.display.widthCm, "Screen width in cm")
            ->check(CLI::Range(1.0, 1000.0))
            ->capture_default_str();
        mCommand->add_option("--distance-cm", mOptions.display.distanceCm, "Viewing distance in cm")
            ->check(CLI::Range(1.0, 1000.0))
            ->capture_default_str();
        mCommand->add_flag("--json", mJson, "Print a JSON summary on stdout");
    }

    int run() override {
        // Range checks let NaN through (every comparison with it is false), and %d wrapped
        // 99999999999 to 1215752191: both are refused here.
        unsigned long w = 0, h = 0;
        char x = 0, extra = 0;
        if (std::sscanf(mScreen.c_str(), "%lu%c%lu%c", &w, &x, &h, &extra) != 3 || x != 'x' ||
            w == 0 || h == 0 || w > 32768 || h > 32768 || mScreen.find('-') != std::string::npos)
            throw ArgumentError("--screen " + mScreen + ": expected WxH, each 1..32768 pixels");
        mOptions.display.widthPx = static_cast<int>(w);
        mOptions.display.heightPx = static_cast<int>(h);
        for (const auto& [name, value] :
             {std::pair{"--screen-width-cm", mOptions.display.widthCm},
              std::pair{"--distance-cm", mOptions.display.distanceCm}}) {
            if (!std::isfinite(value) || value < 1.0 || value > 1000.0)
                throw ArgumentError(std::string(name) + ": expected 1..1000 cm, got " +
                                    std::to_string(value));
        }
        checkRunFiles({{"--out", mOptions.out}}, {{"--source", mOptions.source},
                                                  {"--source-left", mOptions.sourceLeft},
                                                  {"--source-right", mOptions.sourceRight},
                                                  {"--targets", mOptions.targets},
                                                  {"--intrinsics", mOptions.camera.intrinsics}});
        const nlohmann::json result = runCalibrate(mOptions);
        std::cout << (mJson ? result.dump() : result.dump(2)) << std::endl;
        return 0;
    }

private:
    CalibrateOptions mOptions;
    bool mJson = false;
    std::string mScreen = "1920x1080";
};

} // namespace

std::unique_ptr<Command> makeCalibrateCommand() {
    return std::make_unique<CalibrateCommand>();
}

} // namespace gt::app
