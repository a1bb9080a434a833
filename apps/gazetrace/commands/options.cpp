// `gazetrace options`: every command's options that have a default, as the Markdown table the
// README shows between its `options-table` markers. Generated from the same CLI11 definitions
// that parse the command line, so the documented defaults cannot drift from the real ones (a
// test compares the README with this output).
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "command.hpp"

namespace gt::app {

namespace {

// "`--scene builtin:market` `--width 1280` ...": the options of `sub` that take a value and have
// a default, in the order --help lists them.
std::string defaultsOf(const CLI::App& sub) {
    std::string row;
    for (const CLI::Option* opt : sub.get_options()) {
        if (opt->get_expected_min() == 0 || opt->get_default_str().empty()) continue;
        if (!row.empty()) row += ' ';
        row += "`" + opt->get_name() + " " + opt->get_default_str() + "`";
    }
    return row;
}

class OptionsCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "options", "Print every command's option defaults as a Markdown table (the README's)");
    }
    int run() override {
        std::cout << "| command | defaults |\n|---|---|\n";
        for (const CLI::App* sub : mCommand->get_parent()->get_subcommands({})) {
            if (sub == mCommand) continue;
            const std::string row = defaultsOf(*sub);
            std::cout << "| `" << sub->get_name() << "` | " << (row.empty() ? "—" : row) << " |\n";
        }
        return 0;
    }
};

} // namespace

std::unique_ptr<Command> makeOptionsCommand() {
    return std::make_unique<OptionsCommand>();
}

} // namespace gt::app
