#pragma once
// Running the `gazetrace` executable from tests: exit status, stdout and stderr, and the check
// every bad input must pass (one line on stderr, non-zero exit, nothing left behind).
#include <filesystem>
#include <string>

namespace gt::test {

struct Result {
    int status = -1;
    std::string out, err;
};

std::string slurp(const std::filesystem::path& p);
// Runs `gazetrace ARGS` (through the shell: ARGS may hold redirections and variables).
Result run(const std::string& args);
// Runs `PREFIX gazetrace ARGS`, e.g. PREFIX = "xvfb-run -a" or "env -u DISPLAY".
Result runWith(const std::string& prefix, const std::string& args);
// Runs `PREFIX sh SCRIPT`, where SCRIPT runs `gazetrace ARGS` while a watcher beside it waits
// until WATCHED holds a line containing NEEDLE (at most MAX_SECONDS), then sends it SIGINT;
// returns its exit status. A signal tied to progress, not to a clock: a slow build (sanitisers, a
// loaded machine) reaches the same point before it is interrupted.
Result runInterruptedWhen(const std::string& prefix, const std::string& args,
                          const std::filesystem::path& watched, const std::string& needle,
                          int maxSeconds);
int lines(const std::string& s);
void expectCleanFailure(const Result& r, const std::string& mention,
                        const std::filesystem::path& out);

} // namespace gt::test
