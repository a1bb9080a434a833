// `gazetrace devices`: the Vulkan devices, one a line.
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "command.hpp"
#include "vk/context.hpp"

namespace gt::app {

namespace {

class DevicesCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand("devices", "List the Vulkan devices");
    }
    int run() override {
        for (const std::string& line : vk::Context::listDevices())
            std::cout << line << "\n";
        return 0;
    }
};

} // namespace

std::unique_ptr<Command> makeDevicesCommand() {
    return std::make_unique<DevicesCommand>();
}

} // namespace gt::app
