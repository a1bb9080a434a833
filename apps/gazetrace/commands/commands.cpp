#include <CLI/CLI.hpp>

#include "command.hpp"

namespace gt::app {

// Defined in each command's own file.
std::unique_ptr<Command> makeRenderCommand();
std::unique_ptr<Command> makePointSetCommand();
std::unique_ptr<Command> makeLayersCommand();
std::unique_ptr<Command> makeEvalCommand();
std::unique_ptr<Command> makeBenchCommand();
std::unique_ptr<Command> makeSoakCommand(const bool& quiet);
std::unique_ptr<Command> makeEyesimCommand();
std::unique_ptr<Command> makeTrackCommand();
std::unique_ptr<Command> makeEyescoreCommand();
std::unique_ptr<Command> makeSlippageCommand();
std::unique_ptr<Command> makeCalibrateCommand();
std::unique_ptr<Command> makeDemoCommand();
std::unique_ptr<Command> makeXrCommand();
std::unique_ptr<Command> makeStudyCommand();
std::unique_ptr<Command> makeDevicesCommand();
std::unique_ptr<Command> makeScenesCommand();
std::unique_ptr<Command> makeOptionsCommand();

bool Command::given() const {
    return mCommand != nullptr && mCommand->parsed();
}

std::vector<std::unique_ptr<Command>> allCommands(const bool& quiet) {
    std::vector<std::unique_ptr<Command>> c;
    c.push_back(makeRenderCommand());
    c.push_back(makePointSetCommand());
    c.push_back(makeLayersCommand());
    c.push_back(makeEvalCommand());
    c.push_back(makeBenchCommand());
    c.push_back(makeSoakCommand(quiet));
    c.push_back(makeEyesimCommand());
    c.push_back(makeTrackCommand());
    c.push_back(makeEyescoreCommand());
    c.push_back(makeSlippageCommand());
    c.push_back(makeCalibrateCommand());
    c.push_back(makeDemoCommand());
    c.push_back(makeXrCommand());
    c.push_back(makeStudyCommand());
    c.push_back(makeDevicesCommand());
    c.push_back(makeScenesCommand());
    c.push_back(makeOptionsCommand());
    return c;
}

} // namespace gt::app
