// `gazetrace pointset`: the perceptual point set: its options and what it prints.
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "option_parsing.hpp"
#include "pointset_command.hpp"
#include "shared_options.hpp"

namespace gt::app {

namespace {

class PointSetCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand("pointset",
                                      "Generate the perceptual point set (thesis 4.1, Table 1)");
        mCommand->add_option("--profile", mOptions.profile, "fove | vive | desktop")
            ->check(CLI::IsMember({"fove", "vive", "desktop"}))
            ->capture_default_str();
        mCommand->add_option("--scale", mOptions.scale, "Eccentricity scaling value (thesis 4.1)")
            ->check(CLI::Range(0.01, 100.0))
            ->capture_default_str();
        mCommand->add_option("--seed", mOptions.seed, "Dart-throwing seed")->capture_default_str();
        mCommand->add_option("--out", mOptions.out, "Also write the point set to this file");
        mCommand->add_option("--image", mOptions.image,
                             "Draw every point into this PNG (Figure 12)");
        mCommand->add_option("--cache", mOptions.cacheDir,
                             "Cache folder (default $GAZETRACE_CACHE or ~/.cache/gazetrace)");
        mCommand
            ->add_option("--sweep", mOptions.sweep,
                         "Scales to sweep, e.g. 1 1.5 2 2.5 3 (Figure 14)")
            ->check(CLI::Range(0.01, 100.0));
        mCommand->add_flag("--json", mJson, "Print a JSON summary on stdout");
        mCommand->add_option("--hmd", mOptions.hmd,
                             hmdChoicesText() +
                                 ": the headset's point set, and where the rays go with the set "
                                 "laid in the eye's image and laid on the panel after the lens");
    }

    int run() override {
        checkRunFiles({{"--out", mOptions.out}, {"--image", mOptions.image}}, {});
        const nlohmann::json result = runPointSet(mOptions);
        std::cout << (mJson ? result.dump() : result.dump(2)) << std::endl;
        return 0;
    }

private:
    PointSetOptions mOptions;
    bool mJson = false;
};

} // namespace

std::unique_ptr<Command> makePointSetCommand() {
    return std::make_unique<PointSetCommand>();
}

} // namespace gt::app
