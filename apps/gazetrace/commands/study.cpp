// `gazetrace study`: a perception study's run, and its `analyse` and `simulate` subcommands.
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "shared_options.hpp"
#include "study_analyse_command.hpp"
#include "study_command.hpp"

namespace gt::app {

namespace {

class StudyCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "study", "Run a perception study (2IFC, yes/no, the thesis's series, Guenter et al. "
                     "2012's pair, ramp and slider tests) in the window, in OpenXR or headless");
        mCommand->require_subcommand(0, 1);
        registerRun();
        registerAnalyse();
        registerSimulate();
    }

    int run() override {
        if (mAnalyse->parsed()) {
            print(runStudyAnalyse(mAnalyseOptions));
        } else if (mSimulate->parsed()) {
            print(runStudySimulate(mSimulateOptions));
        } else {
            if (mRun.design.empty()) {
                throw CLI::RequiredError("--design");
            }
            print(runStudy(mRun));
        }
        return 0;
    }

private:
    void registerRun() {
        CLI::App& c = *mCommand;
        c.add_option("--design", mRun.design, "The study design (JSON; docs/study.md)");
        c.add_option("--participant", mRun.participant,
                     "The participant's code (letters, digits, - and _; nothing personal)");
        c.add_option("--journal", mRun.journal,
                     "The run's journal (JSON lines; default NAME_PARTICIPANT.jsonl)");
        c.add_flag("--resume", mRun.resume, "Continue the journal of an interrupted run");
        c.add_option("--display", mRun.display, "window | xr | headless")
            ->check(CLI::IsMember({"window", "xr", "headless"}))
            ->capture_default_str();
        c.add_option("--gaze", mRun.gaze, "The gaze source, as demo --gaze takes it")
            ->capture_default_str();
        c.add_option("--calibration", mRun.calibration, "The eye tracker's calibration file");
        c.add_option("--observer", mRun.observer,
                     "A simulated observer answers: level:T[,SLOPE[,LAPSE]] or "
                     "flip:T[,SLOPE[,LAPSE]]");
        c.add_option("--hmd", mRun.hmd, "The headset profile (overrides the design's)");
        c.add_option("--width", mRun.width, "View width (0: the design's)");
        c.add_option("--height", mRun.height, "View height (0: the design's)");
        c.add_option("--frame-ms", mRun.frameMs, "Headless: time per frame (0: the refresh's)")
            ->check(CLI::Range(0.0, 1000.0));
        c.add_option("--max-trials", mRun.maxTrials, "End after this many trials (0: all)");
        c.add_option("--cache", mRun.cacheDir, "Point-set cache folder");
        c.add_flag("--validate", mRun.validate, "Enable the Vulkan validation layers");
    }

    void registerAnalyse() {
        mAnalyse = mCommand->add_subcommand(
            "analyse", "Fit psychometric functions to study journals and pool participants");
        mAnalyse->add_option("journals", mAnalyseOptions.journals, "Journals (JSON lines)")
            ->required();
        mAnalyse
            ->add_option("--out", mAnalyseOptions.out,
                         "Folder for thresholds.json, thresholds.csv, psychometric.png")
            ->capture_default_str();
        mAnalyse->add_flag("--exclude-flagged", mAnalyseOptions.excludeFlagged,
                           "Leave out trials with dropped frames or lost gaze");
        mAnalyse->add_option("--bootstrap", mAnalyseOptions.bootstrap, "Bootstrap resamples")
            ->check(CLI::Range(10u, 100000u))
            ->capture_default_str();
        mAnalyse->add_option("--seed", mAnalyseOptions.seed, "Bootstrap seed")
            ->capture_default_str();
    }

    void registerSimulate() {
        mSimulate = mCommand->add_subcommand(
            "simulate", "Run a design with simulated observers, no rendering (planning, checks)");
        mSimulate->add_option("--design", mSimulateOptions.design, "The study design")->required();
        mSimulate->add_option("--observers", mSimulateOptions.observers, "Simulated observers")
            ->check(CLI::Range(1u, 100000u))
            ->capture_default_str();
        mSimulate->add_option("--threshold", mSimulateOptions.threshold,
                              "The observers' threshold (0: mid-grid)");
        mSimulate->add_option("--slope", mSimulateOptions.slope,
                              "The observers' psychometric slope (0: from the grid)");
        mSimulate->add_option("--lapse", mSimulateOptions.lapse, "The observers' lapse rate")
            ->check(CLI::Range(0.0, 0.5))
            ->capture_default_str();
        mSimulate->add_option("--journals", mSimulateOptions.journals,
                              "Write each simulated participant's journal into this folder");
        mSimulate->add_option("--json", mSimulateOptions.json, "Also write the summary here");
        mSimulate->add_option("--seed", mSimulateOptions.seed, "Simulation seed")
            ->capture_default_str();
    }

    static void print(const nlohmann::json& j) { std::cout << j.dump(2) << std::endl; }

    StudyOptions mRun;
    StudyAnalyseOptions mAnalyseOptions;
    StudySimulateOptions mSimulateOptions;
    CLI::App* mAnalyse = nullptr;
    CLI::App* mSimulate = nullptr;
};

} // namespace

std::unique_ptr<Command> makeStudyCommand() {
    return std::make_unique<StudyCommand>();
}

} // namespace gt::app
