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
        EXPECT_EQ(j["sequence"], "sobol");
        EXPECT_TRUE(std::filesystem::exists(dir / "p.png"));
        EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
    }
}

// --denoise on: the post chain runs pass `denoise` (its variance step and five levels) before
// TAA, for the reference (whose gaze then places the fovea) and the foveated method.
TEST(CliPath, DenoiseRunsTheDenoisePasses) {
    const auto dir = test::tempDir("cli_path_denoise");
    for (const char* method : {"reference --gaze 10,10", "foveated --profile desktop"}) {
        const Result r = run(std::string("render --scene builtin:cornell --method ") + method +
                             " --width 48 --height 32 --integrator path --bounces 2 --denoise on "
                             "--validate --json --cache " +
                             (dir / "cache").string() + " --out " + (dir / "d.png").string());
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["denoise"], "on");
        EXPECT_TRUE(j["gpu_ms"].contains("denoise.variance")) << method;
        EXPECT_TRUE(j["gpu_ms"].contains("denoise.level4")) << method;
    }
    const auto out = dir / "bad.png";
    expectCleanFailure(run("render --method layers --denoise on --out " + out.string()),
                       "--denoise", out);
    expectCleanFailure(run("render --denoise maybe --out " + out.string()), "--denoise", out);
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
    expectCleanFailure(run("render --integrator path --sequence halton --out " + out.string()),
                       "--sequence", out);
}

// eval traces the reference, the foveated frame and the uniform frames with the integrator it
// is given, and says so; layers refuse it.
TEST(CliPath, EvalTracesEveryFrameWithTheIntegrator) {
    const auto dir = test::tempDir("cli_path_eval");
    const Result r = run("eval --scene builtin:cornell --profile desktop --width 64 --height 48 "
                         "--integrator path --bounces 2 --reference-spp 8 --frames 2 --validate "
                         "--json --cache " +
                         (dir / "cache").string() + " --out " + (dir / "e").string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["integrator"]["integrator"], "path");
    EXPECT_EQ(j["integrator"]["bounces"], 2);
    EXPECT_GT(j["methods"]["foveated"]["rays"].get<uint64_t>(), 0u);
    const auto out = dir / "bad";
    expectCleanFailure(run("eval --method layers --integrator path --out " + out.string()),
                       "--integrator", out);
}

} // namespace
} // namespace gt
