// `gazetrace slippage`: the gaze models before and after headset slippage: its options and what it
// prints.
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "eye_commands.hpp"

namespace gt::app {

namespace {

class SlippageCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "slippage", "Accuracy of the 2D and 3D gaze models before and after the headset slips");
        mCommand->add_option("--seeds", mOptions.seeds, "eyesim seeds N or A-B")
            ->capture_default_str();
        mCommand->add_option("--preset", mOptions.preset, "eyesim preset")->capture_default_str();
        mCommand->add_option("--slips-mm", mOptions.slipsMm, "Slippage magnitudes in mm, A,B,..")
            ->capture_default_str();
        mCommand->add_option("--slip-deg", mOptions.slipDeg, "Headset turn with each slip")
            ->check(CLI::Range(-20.0, 20.0))
            ->capture_default_str();
        mCommand->add_option("--detector", mOptions.detector, "Pupil detector")
            ->capture_default_str();
        mCommand->add_flag("--json", mJson, "Print JSON on one line");
    }

    int run() override {
        const nlohmann::json result = runSlippage(mOptions);
        std::cout << (mJson ? result.dump() : result.dump(2)) << std::endl;
        return 0;
    }

private:
    SlippageOptions mOptions;
    bool mJson = false;
};

} // namespace

std::unique_ptr<Command> makeSlippageCommand() {
    return std::make_unique<SlippageCommand>();
}

} // namespace gt::app
