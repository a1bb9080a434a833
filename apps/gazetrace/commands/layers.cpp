// `gazetrace layers`: the eccentricity-layer optimisation: its options and what it prints.
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "layers_command.hpp"

namespace gt::app {

namespace {

class LayersCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "layers", "Eccentricity-layer optimisation and predicted speed-up (Guenter 2012, 4.3)");
        mCommand->add_option("--profile", mOptions.profile, "desktop | fove | vive | paper")
            ->check(CLI::IsMember({"desktop", "fove", "vive", "paper"}))
            ->capture_default_str();
        mCommand
            ->add_option("--slope", mOptions.slope, "MAR slope: A (0.0275) | B (0.0220) | VALUE")
            ->capture_default_str();
        mCommand->add_option("--layers", mOptions.layers, "Number of layers")
            ->check(CLI::Range(1u, 4u))
            ->capture_default_str();
        mCommand->add_option("--weights", mOptions.weights, "unit | half-rate (eq. 5's w_i)")
            ->check(CLI::IsMember({"unit", "half-rate"}))
            ->capture_default_str();
        mCommand->add_option("--steps", mOptions.steps, "Brute-force grid divisions of (0, e*)")
            ->check(CLI::Range(8u, 4000u))
            ->capture_default_str();
        mCommand->add_flag("--fov-table", mOptions.fovTable,
                           "Figure 12: speed-up for 20..120 degrees at foveal sharpness");
        mCommand->add_flag("--json", mJson, "Print JSON instead of a table");
    }

    int run() override {
        const nlohmann::json result = runLayers(mOptions);
        std::cout << (mJson ? result.dump() : layersText(result)) << std::flush;
        return 0;
    }

private:
    LayersOptions mOptions;
    bool mJson = false;
};

} // namespace

std::unique_ptr<Command> makeLayersCommand() {
    return std::make_unique<LayersCommand>();
}

} // namespace gt::app
