// `gazetrace soak`: many frames under validation: its options and what it prints.
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "shared_options.hpp"
#include "soak_command.hpp"

namespace gt::app {

namespace {

class SoakCommand final : public Command {
public:
    explicit SoakCommand(const bool& quiet) : mQuiet(quiet) {}
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "soak", "Many frames with changing gaze and settings under validation; fails on any "
                    "validation error or resident memory growth");
        mCommand->add_option("--scene", mOptions.scene, "Scene")->capture_default_str();
        mAnimatedScene = mCommand
                             ->add_option("--animated-scene", mOptions.animatedScene,
                                          "Scene of the animated phase (an animated glTF)")
                             ->capture_default_str();
        mCommand->add_option("--frames", mOptions.frames, "Frames to render")
            ->check(CLI::Range(1u, 1000000u))
            ->capture_default_str();
        addSizeOptions(mCommand, mOptions.width, mOptions.height, 16u,
                       "Frame (default: the desktop screen's)");
        mCommand
            ->add_option("--max-growth", mOptions.maxGrowthPercent,
                         "Resident memory growth allowed from frame 100 to the last, in percent")
            ->check(CLI::Range(0.0, 1000.0))
            ->capture_default_str();
        mCommand->add_option("--cache", mOptions.cacheDir, "Point-set cache folder");
        mCommand->add_option("--json-file", mOptions.json,
                             "Also write the results as JSON to this file");
        mCommand->add_flag("--json", mJson, "Print the results as JSON on stdout");
    }

    int run() override {
        mOptions.quiet = mQuiet;
        mOptions.animatedSceneGiven = mAnimatedScene->count() > 0;
        checkRunFiles({{"--json-file", mOptions.json}}, {{"--scene", mOptions.scene}});
        const nlohmann::json result = runSoak(mOptions);
        if (mJson) std::cout << result.dump() << std::endl;
        return 0;
    }

private:
    const bool& mQuiet; // -q: soak prints its progress unless quiet
    SoakOptions mOptions;
    bool mJson = false;
    CLI::Option* mAnimatedScene = nullptr;
};

} // namespace

std::unique_ptr<Command> makeSoakCommand(const bool& quiet) {
    return std::make_unique<SoakCommand>(quiet);
}

} // namespace gt::app
