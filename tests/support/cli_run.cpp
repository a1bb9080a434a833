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
