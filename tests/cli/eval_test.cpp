// `gazetrace eval` end to end on a small window: every measure per band, the uniform baselines
// at equal rays, the temporal measures, the files it writes, and bad inputs as one line.
#include <algorithm>
#include <filesystem>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include "scene/image_io.hpp"
#include "support/cli_run.hpp"
#include "support/gpu_test_context.hpp"

namespace gt {
namespace {

using test::expectCleanFailure;
using test::Result;
using test::run;
using test::runWith;
using test::slurp;

const std::string kSource = GT_SOURCE_DIR;

TEST(Eval, MeasuresPerBandBesideTheUniformBaseline) {
    const auto dir = test::tempDir("cli_eval");
    const std::string out = (dir / "e").string();
    Result r = run("eval --scene builtin:market --profile fove --width 128 --height 144 "
                   "--reference-spp 8 --frames 3 --temporal --camera-path " +
                   kSource + "/content/camera/market_walk.csv --pursuit " + kSource +
                   "/content/gaze/pursuit.csv --sequence-frames 3 --validate --json --cache " +
                   (dir / "cache").string() + " --out " + out);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["width"], 128);
    EXPECT_EQ(j["height"], 144);
    const auto& m = j["methods"];
    const uint64_t rays = m["foveated"]["rays"].get<uint64_t>();
    EXPECT_GT(rays, 0u);
    for (const char* name :
         {"foveated", "uniform_bilinear", "uniform_catmull_rom", "full_resolution"}) {
        ASSERT_TRUE(m.contains(name)) << name;
        for (const char* band : {"0-5", "5-10", "10-20", "20+"}) {
            const auto& b = m[name]["bands"][band];
            EXPECT_GE(b["flip"].get<double>(), 0.0) << name << band;
            EXPECT_LE(b["flip"].get<double>(), 1.0) << name << band;
            EXPECT_GE(b["flip_ecc"].get<double>(), 0.0);
            EXPECT_LE(b["ssim"].get<double>(), 1.0 + 1e-9);
            EXPECT_GT(b["psnr_db"].get<double>(), 5.0);
        }
    }
    // The baseline spends the foveated frame's rays: as many pixels as it has rays per point.
    const auto& u = m["uniform_bilinear"];
    EXPECT_NEAR(static_cast<double>(u["rays"].get<uint64_t>()), static_cast<double>(rays),
                0.03 * static_cast<double>(rays));
    EXPECT_EQ(u["rays_per_pixel"], 4);
    EXPECT_NEAR(u["size"][0].get<double>() / u["size"][1].get<double>(), 128.0 / 144.0, 0.03);
    // The temporal measures, each per band.
    for (const char* seq : {"still", "pursuit"}) {
        ASSERT_TRUE(j["temporal"].contains(seq)) << seq;
        EXPECT_GE(j["temporal"][seq]["changed_percent"]["0-5"].get<double>(), 0.0);
    }
    EXPECT_TRUE(j["temporal"]["pursuit"].contains("changed_percent_all"));
    // The frame the pursuit ends on, scored around its own gaze (bands past this small
    // window's reach are empty: 0), and written.
    const auto& last = j["temporal"]["pursuit"]["flip_ecc_last"];
    EXPECT_GT(last["0-5"].get<double>(), 0.0);
    for (const char* band : {"0-5", "5-10", "10-20", "20+"}) {
        EXPECT_GE(last[band].get<double>(), 0.0) << band;
        EXPECT_LT(last[band].get<double>(), 1.0) << band;
    }
    EXPECT_EQ(image::readPng(dir / "e" / "pursuit_last.png").width, 128u);
    for (const char* who : {"foveated", "reference"}) {
        EXPECT_TRUE(j["temporal"]["moving"][who]["changed_percent"].contains("20+")) << who;
    }
    for (const char* f : {"eval.json", "reference.png", "foveated.png", "flip_foveated.png",
                          "uniform_bilinear.png", "flip_uniform_bilinear.png", "bands.png"}) {
        EXPECT_TRUE(std::filesystem::exists(dir / "e" / f)) << f;
    }
    EXPECT_EQ(nlohmann::json::parse(slurp(dir / "e" / "eval.json"))["methods"], m);
    const auto map = image::readPng(dir / "e" / "flip_foveated.png");
    EXPECT_EQ(map.width, 128u);

    // The same view against the reference it wrote: the same foveated scores, no baseline.
    r = run("eval --scene builtin:market --profile fove --width 128 --height 144 --frames 3 "
            "--reference " +
            out + "/reference.png --baseline none --json --cache " + (dir / "cache").string() +
            " --out " + (dir / "again").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto again = nlohmann::json::parse(r.out);
    EXPECT_FALSE(again["methods"].contains("uniform_bilinear"));
    EXPECT_DOUBLE_EQ(again["methods"]["foveated"]["flip_mean"].get<double>(),
                     m["foveated"]["flip_mean"].get<double>());
}

// Quality against rays: the point set at scales 1, 1.5, 2 and 3, each beside the uniform
// baseline at its rays; sparser sets trace fewer rays. (The window must reach past 7 deg: inside
// it the fove set is at full density, one point per pixel, whatever the scale.)
TEST(Eval, SweepTracesFewerRaysAtSparserScales) {
    const auto dir = test::tempDir("cli_eval_sweep");
    const Result r = run("eval --scene builtin:cornell --profile fove --width 400 --height 450 "
                         "--reference-spp 2 --frames 2 --sweep --json --cache " +
                         (dir / "cache").string() + " --out " + (dir / "e").string());
    ASSERT_EQ(r.status, 0) << r.err;
    // Progress on stderr, frame by frame: reference, 2 foveated, 2 baselines, then 4 scales of
    // 2 foveated and 2 baselines.
    EXPECT_NE(r.err.find("eval: frame 1/21 (reference)"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("eval: frame 21/21"), std::string::npos) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["sweep"].size(), 4u);
    uint64_t last = UINT64_MAX;
    for (const auto& s : j["sweep"]) {
        const uint64_t rays = s["rays"].get<uint64_t>();
        EXPECT_LT(rays, last) << "scale " << s["scale"];
        last = rays;
        const auto& u = s["uniform_bilinear"];
        EXPECT_NEAR(static_cast<double>(u["rays"].get<uint64_t>()), static_cast<double>(rays),
                    0.05 * static_cast<double>(rays) + 8.0);
    }
    EXPECT_TRUE(std::filesystem::exists(dir / "e" / "curves.png"));
}

// Equal picture quality: the cheapest uniform render whose flip_ecc is no higher in every band.
// Without TAA, one frame, and the reference's rays per pixel, the full-size candidate is the
// reference itself (flip_ecc 0), so a match always exists.
TEST(Eval, MatchNamesTheCheapestUniformRenderNoWorseInEveryBand) {
    const auto dir = test::tempDir("cli_eval_match");
    const std::string base = "eval --scene builtin:market --profile fove --width 96 --height 108 "
                             "--gaze 4,4 --reference-spp 4 --rays-per-point 4 --taa off "
                             "--frames 1 --baseline none --cache " +
                             (dir / "cache").string();
    Result r = run(base + " --match uniform --json --out " + (dir / "u").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    const auto& m = j["match"];
    EXPECT_EQ(m["against"], "uniform");
    EXPECT_EQ(m["upscale"], "bilinear");
    EXPECT_EQ(m["doublings"], 3); // by default up to 8x the rays per point
    const auto& fov = m["foveated"];
    EXPECT_EQ(fov["rays"], j["methods"]["foveated"]["rays"]);
    EXPECT_GT(fov["gpu_ms_median"].get<double>(), 0.0);
    ASSERT_FALSE(m["match"].is_null()) << m.dump();
    const auto noWorse = [&](const nlohmann::json& e) {
        bool all = true;
        for (const char* band : {"0-5", "5-10", "10-20", "20+"}) {
            all = all && e["flip_ecc"][band].get<double>() <= fov["flip_ecc"][band].get<double>();
        }
        return all;
    };
    // Every candidate says whether it matched; the first spends the foveated rays (or is the
    // full size, when those are more); at most 8 were rendered.
    ASSERT_GE(m["tried"].size(), 1u);
    EXPECT_LE(m["tried"].size(), 8u);
    for (const auto& e : m["tried"]) {
        EXPECT_EQ(e["matches"].get<bool>(), noWorse(e)) << e.dump();
        const uint32_t w = e["size"][0], h = e["size"][1];
        EXPECT_LE(w, 96u);
        EXPECT_EQ(e["rays"].get<uint64_t>(), 4ull * w * h);
        EXPECT_NEAR(static_cast<double>(w) / h, 96.0 / 108.0, 0.03);
    }
    const auto& first = m["tried"][0];
    EXPECT_NEAR(static_cast<double>(std::min(fov["rays"].get<uint64_t>(), uint64_t{4 * 96 * 108})),
                static_cast<double>(first["rays"].get<uint64_t>()),
                0.05 * static_cast<double>(first["rays"].get<uint64_t>()));
    const auto& match = m["match"];
    EXPECT_TRUE(noWorse(match));
    EXPECT_TRUE(match["matches"].get<bool>());
    EXPECT_DOUBLE_EQ(m["ray_ratio"].get<double>(),
                     static_cast<double>(match["rays"].get<uint64_t>()) /
                         static_cast<double>(fov["rays"].get<uint64_t>()));
    // The time ratio is the median of rounds that time both frames in turns.
    const auto& turns = m["timed_in_turns"];
    ASSERT_EQ(turns["round_ratios"].size(), 3u) << turns.dump();
    std::vector<double> ratios;
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_GT(turns["foveated_gpu_ms"][i].get<double>(), 0.0);
        EXPECT_NEAR(turns["round_ratios"][i].get<double>(),
                    turns["match_gpu_ms"][i].get<double>() /
                        turns["foveated_gpu_ms"][i].get<double>(),
                    1e-9);
        ratios.push_back(turns["round_ratios"][i].get<double>());
    }
    std::sort(ratios.begin(), ratios.end());
    EXPECT_DOUBLE_EQ(m["time_ratio"].get<double>(), ratios[1]);
    // The largest candidate under it, if any, was worse in some band and smaller.
    if (!m["below"].is_null()) {
        EXPECT_FALSE(noWorse(m["below"]));
        EXPECT_LT(m["below"]["size"][0].get<uint32_t>(), match["size"][0].get<uint32_t>());
    }
    EXPECT_TRUE(std::filesystem::exists(dir / "u" / "match_uniform.png"));
    EXPECT_EQ(nlohmann::json::parse(slurp(dir / "u" / "eval.json"))["match"], m);

    // Full size with fewer rays per pixel, as text: the candidates and the sentence.
    r = run(base + " --match full --out " + (dir / "f").string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("match full"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("96x108@"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" yes,"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("the foveated frame needs "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" x less time for the same picture"), std::string::npos) << r.out;
}

// --hmd: a headset's left eye (here one known only by its size and field of view): its eye
// image, its frustum's tangents and the viewing distance of its field of view, worked by hand:
// 120 x 105 degrees: tan 60 = 1.7321, tan 52.5 = 1.3032, v = 1 / (2 tan 60) = 0.2887.
TEST(Eval, HmdRendersTheHeadsetsEye) {
    const auto dir = test::tempDir("cli_eval_hmd");
    const Result r = run("eval --hmd custom:96x84@120x105 --reference-spp 2 --frames 2 "
                         "--baseline none --validate --json --cache " +
                         (dir / "cache").string() + " --out " + (dir / "e").string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["hmd"], "custom:96x84@120x105");
    EXPECT_FALSE(j.contains("profile"));
    EXPECT_EQ(j["width"], 96);
    EXPECT_EQ(j["height"], 84);
    EXPECT_NEAR(j["frustum_tangents"]["right"].get<double>(), 1.7321, 1e-3);
    EXPECT_NEAR(j["frustum_tangents"]["left"].get<double>(), -1.7321, 1e-3);
    EXPECT_NEAR(j["frustum_tangents"]["up"].get<double>(), 1.3032, 1e-3);
    EXPECT_NEAR(j["viewing_distance"].get<double>(), 0.2887, 1e-3);
    // Straight ahead: the symmetric frustum's centre.
    EXPECT_NEAR(j["gaze"][0].get<double>(), 48.0, 1e-3);
    EXPECT_NEAR(j["gaze"][1].get<double>(), 42.0, 1e-3);
    EXPECT_GT(j["methods"]["foveated"]["rays"].get<uint64_t>(), 0u);
    const auto out = dir / "bad";
    expectCleanFailure(run("eval --hmd custom:96x84@120x105 --width 64 --out " + out.string()),
                       "--width", out);
    expectCleanFailure(run("eval --hmd nosuch --out " + out.string()), "--hmd", out);
}

TEST(Eval, BadInputsAreOneLine) {
    const auto dir = test::tempDir("cli_eval_bad");
    const auto out = dir / "never";
    const std::string base = "eval --width 64 --height 64 --out " + out.string() + " ";
    expectCleanFailure(run(base + "--profile nonsense"), "--profile", out);
    expectCleanFailure(run(base + "--blend sideways"), "--blend", out);
    expectCleanFailure(run(base + "--baseline lanczos"), "--baseline", out);
    expectCleanFailure(run(base + "--match lower"), "--match", out);
    expectCleanFailure(run(base + "--match full --match-doublings 2"), "--match-doublings", out);
    expectCleanFailure(run(base + "--match uniform --match-doublings 7"), "--match-doublings", out);
    expectCleanFailure(run(base + "--method grid"), "--method", out);
    expectCleanFailure(run(base + "--method layers --sweep"), "--sweep", out);
    expectCleanFailure(run(base + "--gaze 500,5"), "--gaze", out);
    expectCleanFailure(run(base + "--camera-path " + (dir / "none.csv").string()), "none.csv", out);
    expectCleanFailure(run(base + "--pursuit " + (dir / "none.csv").string()), "none.csv", out);
    // A reference of another size.
    const std::vector<uint8_t> px(32 * 32 * 4, 128);
    image::writePngAtomic(dir / "small.png", 32, 32, px);
    expectCleanFailure(run(base + "--reference " + (dir / "small.png").string()), "small.png", out);
    // A FIFO as the reference blocked eval forever (the timeout turns a hang into a failure);
    // a device is refused by kind, not read.
    ASSERT_EQ(::mkfifo((dir / "ref.png").c_str(), 0600), 0);
    expectCleanFailure(
        runWith("timeout -k 5 120", base + "--reference " + (dir / "ref.png").string()),
        "ref.png: a FIFO", out);
    std::filesystem::create_symlink("/dev/zero", dir / "device.png");
    expectCleanFailure(run(base + "--reference " + (dir / "device.png").string()),
                       "device.png: a character device", out);
}

} // namespace
} // namespace gt
