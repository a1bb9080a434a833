// `gazetrace bench`: the benchmark suites: its options and what it prints.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench_command.hpp"
#include "command.hpp"
#include "core/error.hpp"
#include "eye_commands.hpp"
#include "option_parsing.hpp"
#include "shared_options.hpp"

namespace gt::app {

namespace {

class BenchCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "bench", "Table 1, Table 2 and foveated vs reference on the market (Google Benchmark)");
        mCommand->add_option("--json", mOptions.json,
                             "Also write the results as JSON to this file");
        mCommand->add_flag("--quick", mOptions.quick, "Smoke test: fewer frames, no 32-ray frames");
        mCommand->add_option("--scene", mOptions.scene, "Scene for the headline comparison")
            ->capture_default_str();
        mCommand->add_option("--cache", mOptions.cacheDir, "Point-set cache folder");
        mCommand
            ->add_option("--suite", mSuite,
                         "render (thesis tables, headline, layers) | eye (pupil detection speed) | "
                         "stereo | layers (Guenter et al. 2012 only)")
            ->check(CLI::IsMember({"render", "eye", "stereo", "layers"}))
            ->capture_default_str();
        mCommand
            ->add_option("--hmd", mOptions.hmd, "--suite stereo: the headset, " + hmdChoicesText())
            ->capture_default_str();
    }

    int run() override {
        checkRunFiles({{"--json", mOptions.json}}, {{"--scene", mOptions.scene}});
        if (mSuite != "stereo" && mCommand->count("--hmd") > 0) {
            throw ArgumentError("--hmd: only --suite stereo measures a headset");
        }
        if (mSuite == "eye") {
            (void)runEyeBench();
        } else if (mSuite == "layers") {
            (void)runLayersBench(mOptions);
        } else if (mSuite == "stereo") {
            (void)runStereoBench(mOptions);
        } else {
            (void)runBench(mOptions);
        }
        return 0;
    }

private:
    BenchOptions mOptions;
    std::string mSuite = "render";
};

} // namespace

std::unique_ptr<Command> makeBenchCommand() {
    return std::make_unique<BenchCommand>();
}

} // namespace gt::app
