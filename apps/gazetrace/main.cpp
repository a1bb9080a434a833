// The `gazetrace` command line. Every error reaches the user as one line on stderr and a
// non-zero exit status; stdout carries only what was asked for (--json).
#include <cstdio>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "commands/command.hpp"
#include "commands/shared_options.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "stop_request.hpp"
#include "vulkan_failure.hpp"

namespace {

int fail(const std::string& message) {
    std::fprintf(stderr, "gazetrace: error: %s\n", message.c_str());
    return 1;
}

// A fixed-length run stopped by SIGINT or SIGTERM: what it wrote was removed while the exception
// unwound, as after any failure.
int interrupted(const CLI::App& app, const gt::app::Interrupted& e) {
    const auto given = app.get_subcommands();
    const std::string command = given.empty() ? "gazetrace" : given.front()->get_name();
    std::fprintf(stderr, "gazetrace: %s: %s; nothing written\n", command.c_str(), e.what());
    return e.exitStatus();
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"gazetrace — foveated ray tracing with eye tracking"};
    app.require_subcommand(1);
    bool quiet = false;
    app.add_flag("-q,--quiet", quiet, "Only print errors");
    app.fallthrough(); // -q works after the subcommand too
    const auto commands = gt::app::allCommands(quiet);
    for (const auto& command : commands) {
        command->registerOptions(app);
    }
    gt::app::addNumberChecks(app);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        return fail(e.what());
    }
    if (quiet) gt::log::setLevel(gt::log::Level::Error);

    // From here on SIGINT and SIGTERM are requests the commands' loops act on.
    gt::app::installStopHandlers();
    int status = 0;
    try {
        for (const auto& command : commands) {
            if (command->given()) status = command->run();
        }
    } catch (const gt::app::Interrupted& e) {
        return interrupted(app, e);
    } catch (const gt::VulkanError& e) {
        return fail(gt::app::vulkanFailureMessage(e));
    } catch (const gt::Error& e) {
        return fail(e.what());
    } catch (const std::exception& e) {
        return fail(e.what());
    }
    // What was asked for on standard output (--json, a listing) must have got there: a full
    // disk or a closed pipe is a failed run, not a silent success.
    std::cout.flush();
    if (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout)) {
        return fail("cannot write to standard output (disk full or pipe closed?)");
    }
    return status;
}
