#pragma once
// A `gazetrace` subcommand: its options, registered on its own CLI11 subcommand, and what it
// runs once the command line parsed. main() only registers the commands, in the order --help
// lists them, runs the one given and maps its errors to an exit status.
#include <memory>
#include <vector>

namespace CLI {
class App;
}

namespace gt::app {

class Command {
public:
    Command() = default;
    Command(const Command&) = delete;
    Command& operator=(const Command&) = delete;
    virtual ~Command() = default;

    // Adds the subcommand and its options (with their defaults and help texts) to `app`.
    virtual void registerOptions(CLI::App& app) = 0;
    // The command's work, after a successful parse; returns the exit status. Throws gt::Error
    // (or any std::exception) on failure, which main() reports as one line on stderr.
    virtual int run() = 0;
    // Whether this command was the one on the command line.
    [[nodiscard]] bool given() const;

protected:
    CLI::App* mCommand = nullptr; // set by registerOptions
};

// Every subcommand, in --help's order. `quiet` is the global -q, read when a command runs.
[[nodiscard]] std::vector<std::unique_ptr<Command>> allCommands(const bool& quiet);

} // namespace gt::app
