// `render --integrator path --bounces N`: the path tracer through the command line, and its
// options' errors.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scene/image_io.hpp"
#include "support/cli_run.hpp"
#include "support/gpu_test_context.hpp"

namespace gt {
namespace {

using test::expectCleanFailure;
using test::Result;
using test::run;

// The mean absolute difference of green between horizontal neighbours in the central 40 x 40
// pixels: on a flat, evenly lit wall, the noise.

// Mean difference of horizontal neighbours (green) over the 40 x 40 block centred at (cx, cy).
double blockNoise(const image::DecodedImage& img, uint32_t cx, uint32_t cy) {
    double sum = 0.0;
    int n = 0;
    for (uint32_t y = cy - 20; y < cy + 20; ++y) {
        for (uint32_t x = cx - 20; x < cx + 20; ++x) {
            const std::size_t i = (static_cast<std::size_t>(y) * img.width + x) * 4 + 1;
            sum += std::abs(int(img.rgba[i]) - int(img.rgba[i + 4]));
            ++n;
        }
    }
    return sum / n;
}

double centreNoise(const image::DecodedImage& img) {
    return blockNoise(img, img.width / 2, img.height / 2);
}

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

// --denoise on: the reference's post chain runs pass `denoise` (its variance step and five
// levels) before TAA, its gaze placing the fovea. The foveated method filters its points
// (point_denoise: the temporal step, demodulation and three steps) with --denoise points, and
// its image too with both, as with on.
TEST(CliPath, DenoiseRunsTheDenoisePasses) {
    const auto dir = test::tempDir("cli_path_denoise");
    struct Case {
        const char* method;
        const char* denoise;
        bool image, points;
    };
    for (const Case& c : {Case{"reference --gaze 10,10", "on", true, false},
                          Case{"foveated --profile desktop", "points", false, true},
                          Case{"foveated --profile desktop", "both", true, true},
                          Case{"foveated --profile desktop", "on", true, true}}) {
        const Result r = run(std::string("render --scene builtin:cornell --method ") + c.method +
                             " --width 48 --height 32 --integrator path --bounces 2 --denoise " +
                             c.denoise + " --validate --json --cache " + (dir / "cache").string() +
                             " --out " + (dir / "d.png").string());
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["denoise"], c.denoise);
        EXPECT_EQ(j["gpu_ms"].contains("denoise.variance"), c.image) << c.method;
        EXPECT_EQ(j["gpu_ms"].contains("denoise.level4"), c.image) << c.method;
        EXPECT_EQ(j["gpu_ms"].contains("point_denoise.demodulate"), c.points) << c.method;
        EXPECT_EQ(j["gpu_ms"].contains("point_denoise.step2"), c.points) << c.method;
        EXPECT_EQ(j["gpu_ms"].contains("point_denoise.temporal"), c.points) << c.method;
    }
    const auto out = dir / "bad.png";
    expectCleanFailure(run("render --method layers --denoise on --out " + out.string()),
                       "--denoise", out);
    expectCleanFailure(run("render --denoise maybe --out " + out.string()), "--denoise", out);
}

// --fovea-rays F: the points within 5 degrees of the gaze trace F rays instead of R. The
// desktop screen (51 cm wide, 1920 px, seen from 59 cm) puts 5 degrees at
// 1920 * 59 / 51 * tan 5 = 194.3 px in any window on it; the rays grow by (F - R) for each
// point inside, and no more than the sampled points are inside. Those rays are traced: the
// centre of the image is less noisy (neighbouring pixels differ less on the flat back wall).
TEST(CliPath, FoveaRaysTraceMorePathsNearTheGaze) {
    const auto dir = test::tempDir("cli_path_fovea");
    uint64_t rays[2] = {0, 0};
    double noise[2] = {0.0, 0.0};
    uint64_t sampled = 0;
    for (const uint32_t fovea : {0u, 6u}) {
        const Result r = run("render --scene builtin:cornell --method foveated --profile desktop "
                             "--width 320 --height 240 --rays-per-point 2 --integrator path "
                             "--bounces 1 --validate --json --fovea-rays " +
                             std::to_string(fovea) + " --cache " + (dir / "cache").string() +
                             " --out " + (dir / "f.png").string());
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
        const auto j = nlohmann::json::parse(r.out);
        rays[fovea == 0 ? 0 : 1] = j["rays"].get<uint64_t>();
        noise[fovea == 0 ? 0 : 1] = centreNoise(image::readPng(dir / "f.png"));
        sampled = j["points_sampled"].get<uint64_t>();
        if (fovea > 0) {
            EXPECT_NEAR(j["fovea_radius_px"].get<double>(), 194.3, 0.2);
        }
    }
    EXPECT_EQ(rays[0], 2 * sampled);
    ASSERT_GT(rays[1], rays[0]);
    EXPECT_EQ((rays[1] - rays[0]) % 4, 0u);
    const uint64_t inside = (rays[1] - rays[0]) / 4;
    EXPECT_LE(inside, sampled);
    // A 194 px disc around the centre covers most of a 320 x 240 window.
    EXPECT_GT(inside, sampled / 2);
    // 8 paths against 2 per point: the noise's spread about halves.
    EXPECT_LT(noise[1], 0.75 * noise[0]) << noise[0] << " " << noise[1];
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
// eval's uniform frames are smaller than the window; the denoiser must leave their fovea where
// the eye looks, so their gaze is scaled with them. With the gaze near the bottom-right
// corner, the uniform baseline (upscaled) stays noisy there (within 5 degrees: 194 px on the
// desktop screen) and is smoothed in the far corner (18 degrees away). Taken at the window's
// pixel coordinates, the gaze fell outside the smaller frame and its fovea was smoothed too.
TEST(CliPath, EvalDenoisesSmallerFramesAroundTheSameGaze) {
    const auto dir = test::tempDir("cli_path_eval_gaze");
    const Result r = run("eval --scene builtin:cornell --profile desktop --width 640 --height 480 "
                         "--gaze 600,440 --integrator path --bounces 1 --rays-per-point 1 "
                         "--denoise on --taa off --frames 1 --reference-spp 2 --validate --json "
                         "--cache " +
                         (dir / "cache").string() + " --out " + (dir / "e").string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_LT(j["methods"]["uniform_bilinear"]["size"][0].get<uint32_t>(), 600u);
    const image::DecodedImage img = image::readPng(dir / "e" / "uniform_bilinear.png");
    const double nearGaze = blockNoise(img, 580, 420), far = blockNoise(img, 60, 60);
    std::printf("uniform baseline noise: %.2f near the gaze, %.2f far from it\n", nearGaze, far);
    EXPECT_GT(nearGaze, 2.0 * far);
}

// eval --match with the path integrator also checks the fovea against full resolution at the
// paths per display pixel the foveated frame spends within 5 degrees: here the whole 64 x 48
// window (5 degrees is 194 px on the desktop screen), its points (at most one per pixel, the
// set thinned for the coarse window) tracing 4 paths each. The uniform search may double its
// one path per pixel once: full size at 1 and 2 paths per pixel is all it renders.
TEST(CliPath, EvalChecksTheFoveaAgainstFullResolutionAtItsPathsPerPixel) {
    const auto dir = test::tempDir("cli_path_fovea_check");
    const Result r = run("eval --scene builtin:cornell --profile desktop --width 64 --height 48 "
                         "--integrator path --bounces 1 --rays-per-point 1 --fovea-rays 4 "
                         "--reference-spp 4 --frames 2 --match uniform --match-doublings 1 "
                         "--baseline none --validate --json --cache " +
                         (dir / "cache").string() + " --out " + (dir / "e").string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("fovea_check")) << r.out;
    const auto& f = j["fovea_check"];
    const double perPixel = f["paths_per_pixel_foveated"].get<double>();
    const double points = static_cast<double>(j["methods"]["foveated"]["rays"].get<uint64_t>()) /
                          4.0 / (64.0 * 48.0); // every sampled point is in the fovea
    EXPECT_NEAR(perPixel, 4.0 * points, 0.05 * perPixel);
    EXPECT_GT(perPixel, 1.5);
    EXPECT_EQ(f["full_resolution_rays_per_pixel"].get<uint32_t>(),
              static_cast<uint32_t>(std::lround(perPixel)));
    EXPECT_EQ(f["no_worse"].get<bool>(),
              f["flip_0_5_foveated"].get<double>() <= f["flip_0_5_full_resolution"].get<double>());

    // The fovea's 4 paths are more than full size at 1 path per pixel gives: the search doubles,
    // once and no more.
    const auto& m = j["match"];
    EXPECT_EQ(m["doublings"], 1);
    std::set<uint32_t> paths;
    for (const auto& e : m["tried"]) {
        paths.insert(e["rays_per_pixel"].get<uint32_t>());
    }
    EXPECT_EQ(paths, (std::set<uint32_t>{1, 2})) << m.dump();
}

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
