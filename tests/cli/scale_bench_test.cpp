// `gazetrace bench --suite scale` end to end on one small eye: a narrow field at many pixels per
// degree (128 x 144 pixels, v = 50 eye widths), where the thesis's point set is sparser than the
// pixels, one timed frame per case, so the suite runs in seconds on lavapipe.
#include <map>
#include <set>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scene/image_io.hpp"
#include "support/cli_run.hpp"
#include "support/gpu_test_context.hpp"

namespace gt {
namespace {

using test::Result;
using test::run;

constexpr uint32_t kW = 128, kH = 144;

std::string smallEye(const std::filesystem::path& dir) {
    return "bench --suite scale --profiles fove --eye-size " + std::to_string(kW) + "x" +
           std::to_string(kH) + " --eye-distance 50 --frames 1 --cache " + (dir / "cache").string();
}

void expectFields(const nlohmann::json& j, std::initializer_list<const char*> keys) {
    for (const char* k : keys) {
        EXPECT_TRUE(j.contains(k)) << k << " missing from " << j.dump();
    }
}

// A row's memory: the view's images at the eye's size, and the method's own beyond them.
void expectMemory(const nlohmann::json& row, const std::string& method) {
    const double images = row["images_mb"].get<double>();
    const double own = row["method_mb"].get<double>();
    EXPECT_LE(images, row["gpu_mb"].get<double>());
    // The eye-sized radiance (RGBA32F) and tonemapped output (RGBA8) every method has, give or
    // take the driver's padding: 20 bytes a pixel.
    const double twoImages = kW * kH * 20 / 1e6;
    if (method == "reference") {
        EXPECT_NEAR(images, twoImages, 0.05 * twoImages); // no TAA
        EXPECT_EQ(own, 0.0);                              // nothing beyond its images
        return;
    }
    EXPECT_GT(own, 0.0);
    if (method == "layers") {
        // Its layers' grids and their histories are its own; at the eye's size it holds the two
        // images the reference does.
        EXPECT_NEAR(images, twoImages, 0.05 * twoImages);
        EXPECT_NEAR(own, row["gpu_mb"].get<double>() - images, 1e-9);
        return;
    }
    // Beyond the reference's two images, the TAA history at least (two RGBA32F).
    EXPECT_GE(images, twoImages + kW * kH * 32 / 1e6);
    const double parts = row["set_mb"].get<double>() + row["neighbour_index_mb"].get<double>() +
                         (method == "msm" ? row["knn_table_mb"].get<double>() : 0.0) +
                         row["gpu_mb"].get<double>() - images;
    EXPECT_NEAR(own, parts, 1e-6);
}

TEST(CliScaleBench, EveryMethodAtBothRayCountsWithItsFigures) {
    const auto dir = test::tempDir("cli_scale");
    const Result r = run(smallEye(dir) + " --json " + (dir / "scale.json").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(test::slurp(dir / "scale.json"));
    expectFields(j, {"suite", "device", "device_type", "scene", "gaze", "reconstruction", "frames",
                     "profiles", "plot", "wall_s"});
    EXPECT_EQ(j["suite"], "scale");
    EXPECT_EQ(j["frames"], 1);
    ASSERT_EQ(j["profiles"].size(), 1u);
    const auto& p = j["profiles"][0];
    expectFields(p, {"profile", "eye", "pixels_per_eye", "viewing_distance", "build", "rows",
                     "peak_rss_mb", "wall_s"});
    EXPECT_EQ(p["profile"], "fove");
    EXPECT_EQ(p["eye"], nlohmann::json({kW, kH}));
    EXPECT_EQ(p["pixels_per_eye"].get<double>(), kW * kH);
    EXPECT_GT(p["peak_rss_mb"].get<double>(), 0.0);
    const auto& b = p["build"];
    expectFields(b, {"point_set_ms", "point_set_from_cache", "points", "neighbour_index_ms",
                     "neighbour_index_mb", "knn_table_k", "knn_table_ms", "knn_table_mb"});
    EXPECT_FALSE(b["point_set_from_cache"].get<bool>()); // a fresh cache folder
    EXPECT_GT(b["point_set_ms"].get<double>(), 0.0);
    EXPECT_GT(b["knn_table_ms"].get<double>(), 0.0);
    EXPECT_GT(b["knn_table_mb"].get<double>(), 0.0);
    EXPECT_EQ(b["knn_table_k"], 10);

    std::set<std::pair<std::string, uint32_t>> seen;
    std::map<uint32_t, double> foveatedPoints; // nn and msm trace the same points
    for (const auto& row : p["rows"]) {
        expectFields(row, {"method", "k", "rays_per_sample", "points", "rays", "ray_ratio",
                           "gpu_ms", "wall_ms", "time_ratio", "wall_time_ratio", "efficiency",
                           "frames", "frames_per_sample", "set_mb", "neighbour_index_mb",
                           "knn_table_mb", "gpu_mb", "images_mb", "method_mb"});
        const std::string method = row["method"];
        const auto rays = row["rays_per_sample"].get<uint32_t>();
        SCOPED_TRACE(method + " " + std::to_string(rays));
        seen.insert({method, rays});
        EXPECT_EQ(row["rays"].get<double>(), row["points"].get<double>() * rays);
        EXPECT_GT(row["gpu_ms"].get<double>(), 0.0);
        EXPECT_GT(row["time_ratio"].get<double>(), 0.0);
        EXPECT_EQ(row["frames"], 1);
        const double ratio = row["ray_ratio"].get<double>();
        EXPECT_NEAR(ratio, kW * kH * rays / row["rays"].get<double>(), 1e-9 * ratio);
        expectMemory(row, method);
        if (method == "reference") {
            EXPECT_EQ(row["rays"].get<double>(), kW * kH * rays);
            EXPECT_EQ(row["time_ratio"].get<double>(), 1.0);
            continue;
        }
        // Never more rays than the reference at the same rays per pixel.
        EXPECT_GE(ratio, 1.0);
        EXPECT_NEAR(row["efficiency"].get<double>(), row["time_ratio"].get<double>() / ratio, 1e-9);
        if (method == "layers") {
            EXPECT_EQ(row["frames_per_sample"], 2); // half-rate layers: two frames a sample
            EXPECT_TRUE(row["set_mb"].is_null());
            continue;
        }
        if (method == "msm") {
            EXPECT_EQ(row["knn_table_mb"].get<double>(), b["knn_table_mb"].get<double>());
        } else {
            EXPECT_TRUE(row["knn_table_mb"].is_null());
        }
        const double points = row["points"].get<double>();
        EXPECT_LT(points, b["points"].get<double>()); // the on-screen share of the set
        if (const auto it = foveatedPoints.find(rays); it != foveatedPoints.end()) {
            EXPECT_EQ(points, it->second);
        }
        foveatedPoints[rays] = points;
    }
    const std::set<std::pair<std::string, uint32_t>> expected{
        {"reference", 1}, {"nn", 1}, {"msm", 1}, {"layers", 1},
        {"reference", 8}, {"nn", 8}, {"msm", 8}, {"layers", 8}};
    EXPECT_EQ(seen, expected);
    EXPECT_EQ(p["rows"].size(), expected.size());

    // The plot beside the JSON: time ratio above ray ratio, one series per method and rays.
    EXPECT_EQ(j["plot"]["file"], (dir / "scale.png").string());
    EXPECT_EQ(j["plot"]["series"].size(), 6u);
    const image::DecodedImage png = image::readPng(dir / "scale.png");
    EXPECT_EQ(png.width, 880u);
    EXPECT_EQ(png.height, 860u);
    // The console table names every method.
    for (const char* m : {"reference", "nn", "msm", "layers"}) {
        EXPECT_NE(r.out.find(m), std::string::npos) << m;
    }
}

TEST(CliScaleBench, ScaleOptionsBelongToTheScaleSuite) {
    const auto dir = test::tempDir("cli_scale_options");
    const auto out = dir / "b.json";
    const Result r = run("bench --suite layers --frames 2 --json " + out.string());
    test::expectCleanFailure(r, "--frames", out);
    const Result p = run("bench --suite scale --profiles fove,nope --json " + out.string());
    test::expectCleanFailure(p, "nope", out);
}

// bench --suite animation: the per-frame CPU work of 100 animated instances and a 10k-vertex
// skin, each step measured, and refitting's cost against fresh builds.
TEST(BenchAnimation, ReportsEachPerFrameStepOfAMovingScene) {
    const auto dir = test::tempDir("bench_animation");
    const auto out = dir / "animation.json";
    const Result r = run("bench --suite animation --quick --json " + out.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(test::slurp(out));
    EXPECT_EQ(j["scene"]["rigid_instances"], 100);
    EXPECT_GE(j["scene"]["skinned_vertices"].get<int>(), 10000);
    const auto& m = j["median_ms"];
    for (const char* k : {"pose", "deform", "refit", "rebuild", "top_level", "update"}) {
        ASSERT_TRUE(m.contains(k)) << k;
        EXPECT_GE(m[k].get<double>(), 0.0) << k;
    }
    EXPECT_GT(m["deform"].get<double>(), 0.0); // the skin is deformed every frame
    EXPECT_GT(m["refit"].get<double>(), 0.0);
    EXPECT_GE(m["update"].get<double>(), m["deform"].get<double>());
    EXPECT_FALSE(j["refit_quality"].empty());
    // The tube's refit on the GPU beside the CPU's, on the same tree.
    ASSERT_TRUE(j.contains("refit_gpu"));
    const auto& g = j["refit_gpu"];
    EXPECT_GT(g["levels"].get<int>(), 1);
    EXPECT_GT(g["gpu_ms"].get<double>(), 0.0);
    EXPECT_GE(g["gpu_wall_ms"].get<double>(), g["gpu_ms"].get<double>());
    EXPECT_GT(g["cpu_ms"].get<double>(), 0.0);
}

} // namespace
} // namespace gt
