// `gazetrace eyescore`: the pupil detector scored on synthetic clips: its options and what it
// prints.
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "eye_commands.hpp"
#include "shared_options.hpp"

namespace gt::app {

namespace {

class EyescoreCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "eyescore", "Score the pupil detector on synthetic clips (detection, ROC area, speed)");
        mCommand->add_option("--preset", mOptions.preset, "eyesim preset: clean, hard or wild")
            ->capture_default_str();
        mCommand->add_option("--detector", mOptions.detector, "Pupil detector: starburst or blob")
            ->capture_default_str();
        mCommand->add_option("--seeds", mOptions.seeds, "Seed N or range A-B, one clip each")
            ->capture_default_str();
        mCommand->add_option("--frames", mOptions.frames, "Frames per clip")
            ->check(CLI::Range(1, 100000))
            ->capture_default_str();
        mCommand
            ->add_option(
                "--skip", mOptions.skip,
                "Frames to skip first (default: into free viewing, with blinks and pursuit)")
            ->check(CLI::Range(0, 1000000))
            ->capture_default_str();
        mCommand
            ->add_option("--radius", mOptions.radiusPx, "Right answers: within this many pixels")
            ->check(CLI::Range(0.001, 1000.0))
            ->capture_default_str();
        mCommand
            ->add_option("--threshold", mOptions.threshold,
                         "Confidence gate to report (default: the gaze filter's)")
            ->check(CLI::Range(0.0, 1.0));
        mCommand->add_option("--misses", mOptions.misses,
                             "CSV of the wrong answers and missed visible frames");
        mCommand->add_option(
            "--misses-sheet", mOptions.missesSheet,
            "PNG contact sheet of the missed frames (tile label: seed*100000+frame)");
        mCommand->add_option("--answers", mOptions.answers,
                             "CSV of every answer, right or not, with what its confidence weighed "
                             "(scripts/fit_answer_confidence.py)");
        mCommand->add_option("--sheet-every", mOptions.sheetEvery, "Misses between sheet tiles")
            ->check(CLI::Range(1, 1000000))
            ->capture_default_str();
        mCommand->add_flag("--cold", mOptions.cold,
                           "Forget the detector's history before every frame (single images)");
        mCommand->add_flag("--json", mJson, "Print JSON on one line");
    }

    int run() override {
        checkRunFiles({{"--misses", mOptions.misses},
                       {"--misses-sheet", mOptions.missesSheet},
                       {"--answers", mOptions.answers}},
                      {});
        const nlohmann::json result = runEyescore(mOptions);
        std::cout << (mJson ? result.dump() : result.dump(2)) << std::endl;
        return 0;
    }

private:
    EyescoreOptions mOptions;
    bool mJson = false;
};

} // namespace

std::unique_ptr<Command> makeEyescoreCommand() {
    return std::make_unique<EyescoreCommand>();
}

} // namespace gt::app
