// `gazetrace scenes`: the built-in scenes, one a line.
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "command.hpp"
#include "scene/builtin_scenes.hpp"

namespace gt::app {

namespace {

class ScenesCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand("scenes", "List the built-in scenes");
    }
    int run() override {
        for (const std::string& s : scene::builtinSceneNames())
            std::cout << s << "\n";
        return 0;
    }
};

} // namespace

std::unique_ptr<Command> makeScenesCommand() {
    return std::make_unique<ScenesCommand>();
}

} // namespace gt::app
