// `render --integrator path --bounces N`: the path tracer through the command line, and its
// options' errors.
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli_run.hpp"
#include "support/gpu_test_context.hpp"

namespace gt {
namespace {

using test::expectCleanFailure;
using test::Result;
using test::run;

TEST(CliPath, ReferenceAndFoveatedTracePaths) {
    const auto dir = test::tempDir("cli_path");
    for (const char* method : {"reference", "foveated --profile desktop --rays-per-point 1"}) {
        const Result r = run(std::string("render --scene builtin:cornell --method ") + method +
                             " --width 48 --height 32 --integrator path --bounces 3 --validate "
                             "--json --cache " +
                             (dir / "cache").string() + " --out " + (dir / "p.png").string());
        ASSERT_EQ(r.status, 0) << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["integrator"], "path");
        EXPECT_EQ(j["bounces"], 3);
        EXPECT_TRUE(std::filesystem::exists(dir / "p.png"));
        EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
    }
}

TEST(CliPath, BadIntegratorAndBouncesAreOneLineErrors) {
    const auto dir = test::tempDir("cli_path_bad");
    const auto out = dir / "o.png";
    expectCleanFailure(run("render --integrator photon --out " + out.string()), "--integrator",
                       out);
    expectCleanFailure(run("render --integrator path --bounces 0 --out " + out.string()),
                       "--bounces", out);
    expectCleanFailure(run("render --integrator path --bounces 65 --out " + out.string()),
                       "--bounces", out);
    expectCleanFailure(run("render --method layers --integrator path --out " + out.string()),
                       "--integrator", out);
}

} // namespace
} // namespace gt
