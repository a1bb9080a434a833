#include "support/cli_run.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <sys/wait.h>

namespace gt::test {

std::string slurp(const std::filesystem::path& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

Result runWith(const std::string& prefix, const std::string& args) {
    // Per-test names: ctest runs the CLI tests in parallel.
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const auto dir = std::filesystem::temp_directory_path();
    const std::string tag = info ? info->name() : "x";
    const auto out = dir / ("gazetrace_cli_" + tag + ".out"),
               err = dir / ("gazetrace_cli_" + tag + ".err");
    const std::string cmd = prefix + (prefix.empty() ? "" : " ") + std::string(GT_GAZETRACE_EXE) +
                            " " + args + " >" + out.string() + " 2>" + err.string();
    const int raw = std::system(cmd.c_str());
    Result r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

Result runInterruptedWhen(const std::string& prefix, const std::string& args,
                          const std::filesystem::path& watched, const std::string& needle,
                          int maxSeconds) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string tag = info ? info->name() : "x";
    const auto script = std::filesystem::temp_directory_path() / ("gazetrace_cli_" + tag + ".sh");
    {
        std::ofstream f(script);
        // The needle goes through a file, not the shell's quoting. gazetrace replaces the shell
        // (exec: same pid, in the foreground) so SIGINT is not ignored as it is for a
        // background job of a non-interactive shell; the watcher runs beside it.
        f << "needle=$(cat '" << script.string() << ".needle')\n"
          << "pid=$$\n"
          << "( i=0\n"
          << "  while [ $i -lt " << maxSeconds * 10 << " ] && kill -0 $pid 2>/dev/null && "
          << "! grep -qF \"$needle\" '" << watched.string() << "' 2>/dev/null; do\n"
          << "    sleep 0.1; i=$((i+1))\n"
          << "  done\n"
          << "  kill -INT $pid 2>/dev/null ) &\n"
          << "exec " << GT_GAZETRACE_EXE << " " << args << "\n";
        std::ofstream(script.string() + ".needle") << needle;
    }
    const auto out = std::filesystem::temp_directory_path() / ("gazetrace_cli_" + tag + ".out"),
               err = std::filesystem::temp_directory_path() / ("gazetrace_cli_" + tag + ".err");
    const std::string cmd = prefix + (prefix.empty() ? "" : " ") + "sh " + script.string() + " >" +
                            out.string() + " 2>" + err.string();
    const int raw = std::system(cmd.c_str());
    Result r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

Result run(const std::string& args) {
    return runWith("", args);
}

int lines(const std::string& s) {
    int n = 0;
    for (char c : s)
        n += c == '\n';
    return n;
}

void expectCleanFailure(const Result& r, const std::string& mention,
                        const std::filesystem::path& out) {
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("error"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(mention), std::string::npos) << r.err;
    EXPECT_EQ(lines(r.err), 1) << "expected one line, got: " << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << out << " was left behind";
    if (!std::filesystem::is_directory(out.parent_path())) return;
    for (const auto& e : std::filesystem::directory_iterator(out.parent_path())) {
        const std::string name = e.path().filename().string();
        // io/atomic_write's temporaries
        EXPECT_EQ(name.find(".tmp"), std::string::npos) << e.path();
    }
}

} // namespace gt::test
