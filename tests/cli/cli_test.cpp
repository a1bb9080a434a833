// `gazetrace render` end to end: the JSON summary, and bad inputs that must give one clear
// line on stderr, a non-zero exit and no output file.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include "scene/image_io.hpp"
#include "support/cli_run.hpp"
#include "support/gltf_fixtures.hpp"
#include "support/gpu_test_context.hpp"

namespace gt {
namespace {

using test::expectCleanFailure;
using test::lines;
using test::Result;
using test::run;
using test::slurp;

TEST(Cli, RenderPrintsJsonAndWritesPng) {
    const auto dir = test::tempDir("cli");
    const auto png = dir / "c.png";
    const Result r = run(
        "render --scene builtin:cornell --width 48 --height 32 --spp 2 --validate --json --out " +
        png.string() + " --graph " + (dir / "g.dot").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    for (const char* key :
         {"device", "width", "height", "method", "rays", "gpu_ms", "total_ms", "output"}) {
        EXPECT_TRUE(j.contains(key)) << key;
    }
    EXPECT_EQ(j["width"], 48);
    EXPECT_EQ(j["height"], 32);
    EXPECT_EQ(j["rays"], 48 * 32 * 2);
    EXPECT_EQ(j["method"], "reference");
    EXPECT_TRUE(j["gpu_ms"].contains("reference.trace"));
    EXPECT_GT(j["total_ms"].get<double>(), 0.0);
    EXPECT_TRUE(std::filesystem::exists(png));
    EXPECT_NE(slurp(dir / "g.dot").find("reference.trace"), std::string::npos);
    EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
}

TEST(Cli, MissingSceneFile) {
    const auto dir = test::tempDir("cli_missing");
    const Result r = run("render --scene " + (dir / "nope.gltf").string() + " --out " +
                         (dir / "o.png").string());
    expectCleanFailure(r, "nope.gltf", dir / "o.png");
}

TEST(Cli, TruncatedGlb) {
    const auto dir = test::tempDir("cli_trunc");
    auto glb = test::quadGlb();
    test::writeFile(dir / "t.glb", glb.data(), glb.size() / 2);
    const Result r =
        run("render --scene " + (dir / "t.glb").string() + " --out " + (dir / "o.png").string());
    expectCleanFailure(r, "t.glb", dir / "o.png");
}

TEST(Cli, GltfWithMissingBuffer) {
    const auto dir = test::tempDir("cli_nobuf");
    test::writeQuadGltf(dir);
    std::filesystem::remove(dir / "quad.bin");
    const Result r = run("render --scene " + (dir / "quad.gltf").string() + " --out " +
                         (dir / "o.png").string());
    expectCleanFailure(r, "quad.gltf", dir / "o.png");
}

TEST(Cli, ZeroWidth) {
    const auto dir = test::tempDir("cli_width");
    const Result r = run("render --width 0 --out " + (dir / "o.png").string());
    expectCleanFailure(r, "--width", dir / "o.png");
}

TEST(Cli, BadValues) {
    const auto dir = test::tempDir("cli_values");
    expectCleanFailure(run("render --spp abc --out " + (dir / "o.png").string()), "--spp",
                       dir / "o.png");
    expectCleanFailure(run("render --scene builtin:nowhere --out " + (dir / "o.png").string()),
                       "builtin:nowhere", dir / "o.png");
    expectCleanFailure(run("render --method magic --out " + (dir / "o.png").string()), "--method",
                       dir / "o.png");
    // The file it would have written, not one elsewhere (this once checked dir / "o.png").
    expectCleanFailure(run("render --width 8 --height 8 --out /nonexistent-dir/o.png"),
                       "/nonexistent-dir", "/nonexistent-dir/o.png");
}

TEST(Cli, PointSetJsonAndBadValues) {
    const auto dir = test::tempDir("cli_pointset");
    const Result ok = run("pointset --profile desktop --scale 3 --json --cache " + dir.string() +
                          " --image " + (dir / "ps.png").string());
    ASSERT_EQ(ok.status, 0) << ok.err;
    const auto j = nlohmann::json::parse(ok.out);
    for (const char* key :
         {"total", "on_screen_centre", "on_screen_corner", "seconds", "viewing_distance"}) {
        EXPECT_TRUE(j.contains(key)) << key;
    }
    EXPECT_GT(j["total"].get<int>(), j["on_screen_centre"].get<int>());
    EXPECT_GT(j["on_screen_centre"].get<int>(), j["on_screen_corner"].get<int>());
    EXPECT_TRUE(std::filesystem::exists(dir / "ps.png"));
    expectCleanFailure(run("pointset --profile oculus --out " + (dir / "o.gtps").string()),
                       "--profile", dir / "o.gtps");
    expectCleanFailure(run("pointset --scale 0 --out " + (dir / "o.gtps").string()), "--scale",
                       dir / "o.gtps");
}

// RBF through the session both ways: per-pixel weights over the k-NN table, and rbf_solve
// over the neighbour lists; the summary says which was prepared and what it cost.
// The JSON contract of RBF's two neighbour indexes (the renderer's behaviour is tested in
// RendererTest.RbfThroughTableAndListsAgree): a small desktop window keeps this quick.
TEST(Cli, FoveatedRbfThroughTableAndLists) {
    const auto dir = test::tempDir("cli_rbf");
    for (const std::string knn : {"table", "lists"}) {
        const Result r = run("render --method foveated --profile desktop --width 160 --height 90 "
                             "--rays-per-point 1 --taa off --interp rbf --k 5 --knn " +
                             knn + " --validate --json --cache " + (dir / "cache").string() +
                             " --out " + (dir / (knn + ".png")).string());
        ASSERT_EQ(r.status, 0) << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j.at("knn"), knn);
        EXPECT_EQ(j.at("rbf_prepared"), knn == "table" ? "pixel_weights" : "inverses");
        EXPECT_GT(j.at("rbf_prepared_mb").get<double>(), 0.0);
        EXPECT_EQ(j.at("gpu_ms").contains("rbf_solve"), knn == "lists");
        EXPECT_TRUE(std::filesystem::exists(dir / (knn + ".png")));
    }
}

// A gaze trace moves the gaze frame by frame: the summary reports each frame's gaze and the
// points sampled around the last one; samples off the screen are clamped with a warning.
TEST(Cli, GazeTraceDrivesTheFrames) {
    const auto dir = test::tempDir("cli_trace");
    const auto trace = dir / "trace.csv";
    std::ofstream(trace) << "t_ms,x,y\n0,20,20\n10,300,150\n20,5000,150\n";
    // A 320 x 180 window of the desktop screen: the same checks as the full screen, quicker.
    const std::string common = "render --method foveated --profile desktop --width 320 "
                               "--height 180 --rays-per-point 1 --taa off --frame-ms 10 --json "
                               "--cache " +
                               (dir / "cache").string();
    const Result r =
        run(common + " --gaze-trace " + trace.string() + " --out " + (dir / "frames").string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("1 of 3 gaze samples lie outside the 320x180 screen"), std::string::npos)
        << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j.at("gaze_per_frame").size(), 3u);
    EXPECT_EQ(j.at("gaze_per_frame")[0], nlohmann::json::array({20.0, 20.0}));
    EXPECT_EQ(j.at("gaze_per_frame")[1], nlohmann::json::array({300.0, 150.0}));
    EXPECT_EQ(j.at("gaze_per_frame")[2], nlohmann::json::array({319.0, 150.0}));
    EXPECT_EQ(j.at("gaze"), j.at("gaze_per_frame")[2]);
    // Near the corner more of the canvas falls off the screen than with the gaze centred.
    const Result centred = run(common + " --out " + (dir / "centred.png").string());
    ASSERT_EQ(centred.status, 0) << centred.err;
    EXPECT_LT(j.at("points_sampled").get<int>(),
              nlohmann::json::parse(centred.out).at("points_sampled").get<int>());
    expectCleanFailure(run(common + " --gaze-trace " + trace.string() + " --gaze 10,10 --out " +
                           (dir / "both").string()),
                       "--gaze", dir / "both");
    expectCleanFailure(
        run("render --width 8 --height 8 --gaze 2,2 --out " + (dir / "ref.png").string()), "--gaze",
        dir / "ref.png");
}

// Mean absolute difference of two same-sized PNGs, in 8-bit steps over all channels.
double meanAbsDiff(const std::filesystem::path& a, const std::filesystem::path& b) {
    const image::DecodedImage x = image::readPng(a), y = image::readPng(b);
    EXPECT_EQ(x.rgba.size(), y.rgba.size());
    double sum = 0.0;
    for (std::size_t i = 0; i < std::min(x.rgba.size(), y.rgba.size()); ++i) {
        sum += std::abs(int(x.rgba[i]) - int(y.rgba[i]));
    }
    return sum / static_cast<double>(std::max<std::size_t>(1, x.rgba.size()));
}

// The JSON's camera as --camera takes it, every number at full precision.
std::string cameraArg(const nlohmann::json& c) {
    std::string s;
    for (const char* key : {"position", "target"}) {
        for (const auto& v : c.at(key)) {
            s += v.dump() + ",";
        }
    }
    return s + c.at("yfov_deg").dump();
}

TEST(Cli, CameraSetsTheView) {
    const auto dir = test::tempDir("cli_camera");
    const std::string common =
        "render --scene builtin:cornell --width 64 --height 48 --json --out ";
    const Result own = run(common + (dir / "own.png").string());
    ASSERT_EQ(own.status, 0) << own.err;
    const auto cam = nlohmann::json::parse(own.out).at("camera");
    // The camera the JSON reports, given back, frames the same picture.
    const Result back = run(common + (dir / "back.png").string() + " --camera " + cameraArg(cam));
    ASSERT_EQ(back.status, 0) << back.err;
    EXPECT_LT(meanAbsDiff(dir / "own.png", dir / "back.png"), 0.5);
    // Another eye and a wider view give another picture, and the JSON says so.
    const Result moved =
        run(common + (dir / "moved.png").string() + " --camera 0.8,1.2,2.5,0,0.8,0,70");
    ASSERT_EQ(moved.status, 0) << moved.err;
    const auto m = nlohmann::json::parse(moved.out).at("camera");
    EXPECT_NEAR(m.at("yfov_deg").get<double>(), 70.0, 1e-4);
    EXPECT_NEAR(m.at("position")[0].get<double>(), 0.8, 1e-6);
    EXPECT_GT(meanAbsDiff(dir / "own.png", dir / "moved.png"), 5.0);
    // Without a field of view the scene's own is kept.
    const Result keep = run(common + (dir / "keep.png").string() + " --camera 0,1,4,0,1,0");
    ASSERT_EQ(keep.status, 0) << keep.err;
    EXPECT_NEAR(nlohmann::json::parse(keep.out).at("camera").at("yfov_deg").get<double>(),
                cam.at("yfov_deg").get<double>(), 1e-4);
    for (const char* bad : {"1,2,3", "1,2,3,4,5,6,7,8", "a,b,c,d,e,f", "1,2,3,4,5,6,", "1,2,,4,5,6",
                            "1,1,1,1,1,1", "0,0,0,0,0,1,0", "0,0,0,0,0,1,180", "nan,0,0,0,0,1"}) {
        expectCleanFailure(run(common + (dir / "bad.png").string() + " --camera " + bad),
                           "--camera", dir / "bad.png");
    }
}

TEST(Cli, HelpOnEverySubcommand) {
    for (const char* sub : {"", "render ", "pointset ", "devices ", "scenes ", "eyesim ", "track ",
                            "calibrate ", "bench ", "demo ", "soak "}) {
        const Result r = run(std::string(sub) + "--help");
        EXPECT_EQ(r.status, 0) << sub;
        EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
    }
}

TEST(Cli, EyesimTrackCalibrateEndToEnd) {
    const auto dir = std::filesystem::temp_directory_path() / "gazetrace_cli_eye";
    std::filesystem::create_directories(dir);
    const std::string clip = (dir / "clip.mkv").string(), truth = (dir / "truth.csv").string();
    const Result sim = run("eyesim --seed 7 --frames 650 --target-ms 400 --size 160x120 --out " +
                           clip + " --truth " + truth + " --json");
    ASSERT_EQ(sim.status, 0) << sim.err;
    const Result track = run("track --source video:" + clip + " --truth " + truth + " --pupils " +
                             (dir / "pupils.csv").string() + " --contact-sheet " +
                             (dir / "sheet.png").string() + " --sheet-every 100 --json");
    ASSERT_EQ(track.status, 0) << track.err;
    const auto t = nlohmann::json::parse(track.out);
    EXPECT_EQ(t.at("frames"), 650);
    EXPECT_EQ(t.at("contact_sheet_tiles"), 7); // frames 0, 100, ..., 600
    // The PNG's IHDR: six 160x120 tiles a row, two rows.
    const std::string png = slurp(dir / "sheet.png");
    ASSERT_GT(png.size(), 24u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    auto be32 = [&png](std::size_t at) {
        std::uint32_t v = 0;
        for (std::size_t i = 0; i < 4; ++i)
            v = v << 8 | static_cast<unsigned char>(png[at + i]);
        return v;
    };
    EXPECT_EQ(be32(16), 6u * 160u);
    EXPECT_EQ(be32(20), 2u * 120u);
    EXPECT_GE(t.at("detection_rate_5px").get<double>(), 0.95);
    EXPECT_LE(t.at("median_error_px").get<double>(), 1.0);
    EXPECT_GT(t.at("fps").get<double>(), 0.0);
    EXPECT_EQ(
        slurp(dir / "pupils.csv").rfind("frame,t_ms,cx,cy,axis_a,axis_b,angle_deg,confidence\n", 0),
        0u);
    EXPECT_EQ(lines(slurp(dir / "pupils.csv")), 651);

    const std::string calib = (dir / "calib.json").string();
    const Result cal = run("calibrate --source video:" + clip + " --targets " + truth +
                           " --settle-ms 250 --out " + calib + " --json");
    ASSERT_EQ(cal.status, 0) << cal.err;
    const auto c = nlohmann::json::parse(cal.out);
    EXPECT_EQ(c.at("calibration_targets"), 9);
    EXPECT_GT(c.at("validation_samples").get<int>(), 0);
    EXPECT_LT(c.at("accuracy_deg").get<double>(), 1.5);

    const Result gaze = run("track --source video:" + clip + " --calibration " + calib + " --out " +
                            (dir / "gaze.csv").string() + " --json");
    ASSERT_EQ(gaze.status, 0) << gaze.err;
    EXPECT_EQ(slurp(dir / "gaze.csv").rfind("t_ms,x,y\n", 0), 0u);

    // The renderer following the tracker live (the recording played at its own pace).
    const Result live =
        run("render --method foveated --profile desktop --scale 3 --rays-per-point 1 --validate "
            "--frames 2 --cache " +
            (dir / "cache").string() + " --gaze-source video:" + clip + " --calibration " + calib +
            " --json --out " + (dir / "live").string());
    ASSERT_EQ(live.status, 0) << live.err;
    const auto l = nlohmann::json::parse(live.out);
    EXPECT_EQ(l.at("gaze_source"), "video:" + clip);
    EXPECT_GT(l.at("tracker_frames").get<int>(), 0);
    ASSERT_EQ(l.at("gaze_per_frame").size(), 2u);
    // Each frame's gaze is one of the tracker's own samples (gaze.csv, the same clip and
    // calibration) placed on the desktop screen: the render is the whole 1920 x 1080 screen, so
    // the angles land on the same pixel. Range checks alone could not fail here: the
    // render clamps the gaze to the screen first.
    std::vector<std::pair<double, double>> samples;
    {
        std::istringstream in(slurp(dir / "gaze.csv"));
        std::string row;
        std::getline(in, row); // header
        while (std::getline(in, row)) {
            double tMs = 0, x = 0, y = 0;
            if (std::sscanf(row.c_str(), "%lf,%lf,%lf", &tMs, &x, &y) == 3) {
                samples.emplace_back(std::clamp(x, 0.0, 1919.0), std::clamp(y, 0.0, 1079.0));
            }
        }
    }
    ASSERT_GT(samples.size(), 10u);
    for (const auto& g : l.at("gaze_per_frame")) {
        double nearest = 1e9;
        for (const auto& [x, y] : samples) {
            nearest = std::min(nearest, std::hypot(g[0].get<double>() - x, g[1].get<double>() - y));
        }
        EXPECT_LT(nearest, 1.0) << g;
    }
    EXPECT_TRUE(std::filesystem::exists(dir / "live" / "frame_0001.png"));
    // A multi-frame render following a clip that turns out truncated kept the frames
    // written before the tracker failed. The failure is one line and leaves no frame behind.
    {
        const std::string whole = slurp(clip);
        std::ofstream(dir / "cut.mkv", std::ios::binary) << whole.substr(0, whole.size() / 8);
    }
    expectCleanFailure(run("-q render --method foveated --profile desktop --scale 3 "
                           "--rays-per-point 1 --frames 40 --cache " +
                           (dir / "cache").string() +
                           " --gaze-source video:" + (dir / "cut.mkv").string() +
                           " --calibration " + calib + " --out " + (dir / "live_cut").string()),
                       "truncated", dir / "live_cut");
    expectCleanFailure(run("render --method foveated --profile desktop --scale 3 --gaze-source "
                           "video:" +
                           (dir / "nope.mkv").string() + " --calibration " + calib + " --out " +
                           (dir / "live_bad.png").string()),
                       "nope.mkv", dir / "live_bad.png");
    expectCleanFailure(run("render --method foveated --profile desktop --scale 3 --gaze-source "
                           "video:" +
                           clip + " --out " + (dir / "live_bad.png").string()),
                       "--calibration", dir / "live_bad.png");

    // Bad inputs: one line naming the thing, nothing half-written.
    const auto pupils = dir / "bad_pupils.csv";
    expectCleanFailure(
        run("track --source video:" + (dir / "nope.mkv").string() + " --pupils " + pupils.string()),
        "nope.mkv", pupils);
    const auto size = std::filesystem::file_size(clip);
    std::filesystem::copy_file(clip, dir / "cut.mkv",
                               std::filesystem::copy_options::overwrite_existing);
    std::filesystem::resize_file(dir / "cut.mkv", size / 3);
    expectCleanFailure(
        run("track --source video:" + (dir / "cut.mkv").string() + " --pupils " + pupils.string()),
        "cut.mkv", pupils);
    expectCleanFailure(run("track --source video:" + clip + " --contact-sheet " +
                           (dir / "no_such_dir" / "sheet.png").string()),
                       "no_such_dir", dir / "no_such_dir" / "sheet.png");
    expectCleanFailure(
        run("track --source video:" + clip + " --contact-sheet " + (dir / "sheet.jpg").string()),
        "sheet.jpg", dir / "sheet.jpg");
    std::ofstream(dir / "bad.json") << R"({"format":"gazetrace-calibration","version":1})";
    expectCleanFailure(run("track --source video:" + clip + " --calibration " +
                           (dir / "bad.json").string() + " --out " + (dir / "g2.csv").string()),
                       "bad.json", dir / "g2.csv");
    std::ofstream(dir / "targets.csv") << "t_ms,target_x\n0,1\n";
    expectCleanFailure(run("calibrate --source video:" + clip + " --targets " +
                           (dir / "targets.csv").string() + " --out " + (dir / "c2.json").string()),
                       "target_y", dir / "c2.json");
    expectCleanFailure(
        run("track --source v4l2:/dev/video_gazetrace_missing --pupils " + pupils.string()),
        "/dev/video_gazetrace_missing", pupils);
    std::filesystem::remove_all(dir);
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// render --camera-path: the camera follows the path, one frame per --frame-ms.
TEST(Cli, CameraPathMovesTheView) {
    const auto dir = test::tempDir("cli_path");
    const auto path = dir / "path.csv";
    {
        std::ofstream out(path);
        out << "t_ms,ex,ey,ez,tx,ty,tz\n0,0,1,3,0,1,0\n200,0.5,1,3,0.5,1,0\n";
    }
    const auto out = dir / "frames";
    const Result r = run("render --scene builtin:cornell --width 48 --height 32 --camera-path " +
                         path.string() + " --frame-ms 100 --validate --json --out " + out.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["frames"], 3);
    EXPECT_NEAR(j["camera"]["position"][0].get<double>(), 0.5, 1e-6); // the last row
    EXPECT_NE(slurp(out / "frame_0000.png"), slurp(out / "frame_0002.png"));
    const auto png = dir / "never.png";
    expectCleanFailure(
        run("render --camera-path " + (dir / "none.csv").string() + " --out " + png.string()),
        "none.csv", png);
    // 1e300 became an infinite float: a NaN camera and a flat image with exit 0.
    {
        std::ofstream far(dir / "far.csv");
        far << "t_ms,ex,ey,ez,tx,ty,tz\n0,1e300,1,3,0.5,1,0\n200,0,1,3,0,1,0\n";
    }
    expectCleanFailure(run("render --width 48 --height 32 --frames 1 --camera-path " +
                           (dir / "far.csv").string() + " --out " + png.string()),
                       "far.csv:2: ex 1e300", png);
    // A path of 11 days at --frame-ms 10 asked for 10^8 frames (the timeout turns that run into
    // a failure): refused as --frames past its range would be.
    {
        std::ofstream days(dir / "days.csv");
        days << "t_ms,ex,ey,ez,tx,ty,tz\n0,0,1,3,0,1,0\n1e9,0.5,1,3,0.5,1,0\n";
    }
    const auto folder = dir / "never";
    expectCleanFailure(test::runWith("timeout -k 5 60",
                                     "render --width 48 --height 32 --frame-ms 10 --camera-path " +
                                         (dir / "days.csv").string() + " --out " + folder.string()),
                       "days.csv: 1000000000 ms long", folder);
}

// The HMD path: a side-by-side frame of both eyes; bad profiles and sizes are one line.
TEST(Cli, HmdWritesBothEyesSideBySide) {
    const auto dir = test::tempDir("cli_hmd");
    const auto png = dir / "sbs.png";
    const Result r = run("render --hmd vive --scene builtin:cornell --spp 1 --validate --json "
                         "--out " +
                         png.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["width"], 2160);
    EXPECT_EQ(j["height"], 1200);
    for (const char* pass : {"left.reference.trace", "right.reference.trace", "left.lens",
                             "right.lens", "readback.composite"}) {
        EXPECT_TRUE(j["gpu_ms"].contains(pass)) << pass;
    }
    // Mirrored tangents: the left eye's gaze straight ahead sits right of its image centre.
    EXPECT_GT(j["eyes"][0]["tangents"][1].get<double>(), 0.0);
    const image::DecodedImage img = image::readPng(png);
    EXPECT_EQ(img.width, 2160u);
    const auto bad = dir / "bad.png";
    expectCleanFailure(run("render --hmd oculus-dk9 --out " + bad.string()), "oculus-dk9", bad);
    expectCleanFailure(run("render --hmd fove --width 100 --out " + bad.string()), "--hmd", bad);
    expectCleanFailure(run("demo --hmd oculus-dk9 --screenshot " + bad.string()), "oculus-dk9",
                       bad);
    // A broken calibration file for the tracker's gaze: one line naming it.
    const auto broken = dir / "broken.json";
    {
        std::ofstream out(broken);
        out << "{\"version\": 2, \"coefficients_x\": [1, 2";
    }
    expectCleanFailure(run("demo --gaze track:synthetic:1 --calibration " + broken.string() +
                           " --screenshot " + bad.string()),
                       "broken.json", bad);
}

// --hmd custom:WxH@HFOVxVFOV[,HZ] works wherever --hmd does: 64 x 48 pixels per eye at 90 x
// 73.7398 degrees has tangents tan 45 = 1 and tan 36.8699 = 0.75, and v = 1 / (2 tan 45) = 0.5.
TEST(Cli, CustomHeadsetRendersAndBadValuesAreOneLine) {
    const auto dir = test::tempDir("cli_custom_hmd");
    const std::string hmd = "custom:64x48@90x73.7398,72";
    const std::string cache = " --cache " + (dir / "cache").string();
    for (const char* method : {"reference", "foveated", "layers"}) {
        const auto png = dir / (std::string(method) + ".png");
        const Result r = run("render --hmd " + hmd + " --method " + method +
                             " --scene builtin:cornell --spp 1 --rays-per-point 1 --validate "
                             "--json --out " +
                             png.string() + cache);
        ASSERT_EQ(r.status, 0) << method << ": " << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["hmd"], hmd);
        EXPECT_EQ(j["width"], 128);
        EXPECT_EQ(j["height"], 48);
        EXPECT_GT(j["rays"].get<uint64_t>(), 0u) << method;
        const auto& t = j["eyes"][0]["tangents"];
        EXPECT_NEAR(t[0].get<double>(), -1.0, 1e-5);
        EXPECT_NEAR(t[1].get<double>(), 1.0, 1e-5);
        EXPECT_NEAR(t[2].get<double>(), 0.75, 1e-5);
        EXPECT_EQ(image::readPng(png).width, 128u);
    }
    const Result ps = run("pointset --json --hmd " + hmd + cache);
    ASSERT_EQ(ps.status, 0) << ps.err;
    const auto j = nlohmann::json::parse(ps.out);
    EXPECT_EQ(j["hmd"], hmd);
    EXPECT_EQ(j["width"], 64);
    EXPECT_NEAR(j["viewing_distance"].get<double>(), 0.5, 1e-9);
    const auto bad = dir / "bad.png";
    expectCleanFailure(run("render --hmd custom:64x48@90x170 --out " + bad.string()),
                       "vertical field of view 170 degrees", bad);
    expectCleanFailure(run("demo --hmd custom:64x48@90 --screenshot " + bad.string()),
                       "custom:WxH@HFOVxVFOV", bad);
    expectCleanFailure(run("bench --suite stereo --hmd custom:8x48@90x60 --json " + bad.string()),
                       "width 8 pixels", bad);
}

// `layers` prints the paper's optimisation; `render --method layers` traces the layers
// (alone and per HMD eye) and reports what it traced; bad values are one line.
TEST(Cli, LayersPlanAndRender) {
    const auto dir = test::tempDir("cli_layers");
    Result r = run("layers --profile paper --slope A --json");
    ASSERT_EQ(r.status, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_NEAR(j["e_star_deg"].get<double>(), 23.37, 0.01);
    EXPECT_NEAR(j["omega_star_deg"].get<double>(), 0.0516, 0.0001);
    ASSERT_EQ(j["layers"].size(), 3u);
    EXPECT_GT(j["speedup"].get<double>(), 5.0);
    r = run("layers --fov-table --slope B");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("Figure 12"), std::string::npos);
    EXPECT_EQ(lines(r.out), 13);

    const auto png = dir / "l.png";
    r = run("render --method layers --scene builtin:cornell --profile desktop --width 320 "
            "--height 180 --slope 0.02 --frames 3 --validate --json --out " +
            dir.string() + "/seq");
    ASSERT_EQ(r.status, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["method"], "layers");
    EXPECT_EQ(j["width"], 320);
    ASSERT_EQ(j["layers"]["layers"].size(), 3u);
    uint64_t traced = 0;
    for (const auto& l : j["layers"]["layers"]) {
        if (l["traced"].get<bool>()) {
            traced += l["width"].get<uint64_t>() * l["height"].get<uint64_t>();
        }
    }
    EXPECT_EQ(j["rays"].get<uint64_t>(), traced); // the last frame's rays: its traced layers
    EXPECT_TRUE(j["gpu_ms"].contains("layer1.layers.trace"));
    EXPECT_TRUE(j["gpu_ms"].contains("layers.compose"));
    EXPECT_FALSE(j["gpu_ms"].contains("taa")); // the layers keep their own histories
    EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;

    r = run("render --hmd vive --method layers --scene builtin:cornell --validate --json --out " +
            png.string());
    ASSERT_EQ(r.status, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    for (const char* pass : {"left.layer1.layers.trace", "right.layers.compose", "left.lens"}) {
        EXPECT_TRUE(j["gpu_ms"].contains(pass)) << pass;
    }
    EXPECT_EQ(j["eyes"][1]["layers"]["layers"].size(), 3u);

    const auto bad = dir / "bad.png";
    expectCleanFailure(run("render --method layers --slope C --out " + bad.string()), "--slope",
                       bad);
    expectCleanFailure(run("render --method layers --layers 5 --out " + bad.string()), "--layers",
                       bad);
    expectCleanFailure(run("render --method layers --slope -1 --out " + bad.string()), "--slope",
                       bad);
    r = run("layers --slope 0");
    EXPECT_NE(r.status, 0);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("--slope"), std::string::npos) << r.err;
    expectCleanFailure(run("demo --method layers --slope X --screenshot " + bad.string()),
                       "--slope", bad);
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// --json to a full disk exited 0 with the JSON lost, and `devices` printed nothing
// and exited 0 without a Vulkan driver. Both are failures with one line now.
TEST(Cli, LostStandardOutputAndNoDriverAreErrors) {
    const auto dir = test::tempDir("cli_stdout");
    const auto err = dir / "err.txt";
    auto status = [&](const std::string& cmd) {
        const int raw = std::system((cmd + " 2>" + err.string()).c_str());
        return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    };
    const std::string exe = GT_GAZETRACE_EXE;
    EXPECT_EQ(status(exe + " render --scene builtin:cornell --width 8 --height 8 --json --out " +
                     (dir / "a.png").string() + " >/dev/full"),
              1);
    EXPECT_NE(slurp(err).find("cannot write to standard output"), std::string::npos) << slurp(err);
    EXPECT_EQ(status(exe + " devices >/dev/full"), 1);
    EXPECT_EQ(status("VK_ICD_FILENAMES=/nonexistent.json " + exe + " devices >/dev/null"), 1);
    EXPECT_NE(slurp(err).find("vkCreateInstance"), std::string::npos) << slurp(err);
    EXPECT_EQ(lines(slurp(err)), 1);
    EXPECT_EQ(status(exe + " devices >/dev/null"), 0);
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// On a full disk render printed "wrote", exited 0 and replaced an existing PNG with a
// 0-byte file. Through the write-fault seam (GAZETRACE_WRITE_FAULT=enospc): one line, exit 1,
// the old file as it was.
TEST(Cli, FullDiskFailsAndKeepsTheOldFile) {
    const auto dir = test::tempDir("cli_full");
    const auto png = dir / "frame.png";
    const Result first =
        run("render --scene builtin:cornell --width 16 --height 16 --out " + png.string());
    ASSERT_EQ(first.status, 0) << first.err;
    const std::string before = slurp(png);
    ASSERT_FALSE(before.empty());
    const Result full = test::runWith("GAZETRACE_WRITE_FAULT=enospc",
                                      "render --scene builtin:cornell --width 16 --height 16 "
                                      "--seed 9 --out " +
                                          png.string());
    EXPECT_EQ(full.status, 1);
    EXPECT_NE(full.err.find("No space left"), std::string::npos) << full.err;
    // One error line (beside the device announcement).
    EXPECT_EQ(full.err.find("error:"), full.err.rfind("error:")) << full.err;
    EXPECT_EQ(slurp(png), before);
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        EXPECT_EQ(e.path().filename(), "frame.png") << "left behind: " << e.path();
    }
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// --out naming a folder (with --graph) exited 1 "cannot write ...: Success" and left
// the graph behind; --out r.PNG was taken for a folder; a run that failed at a later frame kept
// its earlier frames. A failed run now leaves none of its outputs.
TEST(Cli, FailedRunLeavesNoneOfItsOutputs) {
    const auto dir = test::tempDir("cli_outputs");
    std::filesystem::create_directories(dir / "X.png");
    const Result folder = run("render --scene builtin:cornell --width 8 --height 8 --out " +
                              (dir / "X.png").string() + " --graph " + (dir / "g.dot").string());
    expectCleanFailure(folder, "is a folder", dir / "g.dot");
    const Result upper = run("render --scene builtin:cornell --width 8 --height 8 --out " +
                             (dir / "r.PNG").string());
    ASSERT_EQ(upper.status, 0) << upper.err;
    EXPECT_TRUE(std::filesystem::is_regular_file(dir / "r.PNG"));
    const auto frames = dir / "frames";
    const Result full =
        test::runWith("GAZETRACE_WRITE_FAULT=enospc",
                      "render --scene builtin:cornell --width 8 --height 8 --frames 3 --graph " +
                          (dir / "g2.dot").string() + " --out " + frames.string());
    EXPECT_EQ(full.status, 1);
    EXPECT_FALSE(std::filesystem::exists(dir / "g2.dot"));
    EXPECT_FALSE(std::filesystem::exists(frames)); // the folder it made, removed again
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// Calibrate --distance-cm nan / --screen-width-cm nan exited 0 and wrote nulls, and
// --screen 99999999999x1 wrapped to 1215752191. Refused before any work now.
TEST(Cli, CalibrateRefusesNanAndOverflowingScreens) {
    const auto dir = test::tempDir("cli_calib_values");
    const auto out = dir / "c.json";
    const std::string base = "calibrate --source synthetic:1 --targets " +
                             (dir / "none.csv").string() + " --out " + out.string();
    expectCleanFailure(run(base + " --distance-cm nan"), "--distance-cm", out);
    expectCleanFailure(run(base + " --screen-width-cm nan"), "--screen-width-cm", out);
    expectCleanFailure(run(base + " --screen 99999999999x1"), "--screen", out);
    expectCleanFailure(run(base + " --screen 1920x-5"), "--screen", out);
    expectCleanFailure(run("render --scene '' --out " + (dir / "x.png").string()), "scene is empty",
                       dir / "x.png");
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// Values that CLI11's conversions and ranges alone let through (NaN passes every range check,
// "-3" wraps to 2^64 - 3, 1e30 makes a NaN camera, of two sources one would be ignored) are each
// one line naming the option or variable, never a run that exits 0 with a wrong result.
TEST(Cli, HostileNumbersAreOneLineNamingTheOption) {
    const auto dir = test::tempDir("cli_hostile_numbers");
    const auto png = dir / "o.png";
    const std::string render = "render --width 16 --height 16 --out " + png.string();
    const std::string track2 = " --source-left 'synthetic:2?frames=2' --source-right "
                               "'synthetic:3?frames=2'";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"soak --frames 1 --max-growth nan", "--max-growth"},
        {"demo --frames 1 --vergence-m nan", "--vergence-m"},
        {"render --vergence-m inf --hmd fove --width 16 --height 16 --out " + png.string(),
         "--vergence-m"},
        {render + " --rbf-c 1e400", "--rbf-c"},
        {render + " --camera 1e30,0,0,0,0,0", "--camera"},
        {"eyescore --frames 1 --sheet-every 0", "--sheet-every"},
        {"eyescore --frames 1 --threshold nan", "--threshold"},
        {"pointset --scale 8 --seed -2", "--seed"},
        {"pointset --scale 8 --sweep 1 nan", "--sweep"},
        {"eyesim --seed -3 --frames 1 --out " + (dir / "e.mkv").string() + " --truth " +
             (dir / "e.csv").string(),
         "--seed"},
        {"track --source 'synthetic:1?frames=2'" + track2, "--source"},
        {"track --source 'synthetic:1?fps=1e-300'", "fps=1e-300"},
        {"track --source 'synthetic:1?frames=2' --ipd-mm -63", "--ipd-mm"},
    };
    for (const auto& [args, mention] : cases) {
        SCOPED_TRACE(args);
        expectCleanFailure(run(args), mention, png);
    }
    expectCleanFailure(test::runWith("GAZETRACE_DEVICE=99999999999999999999", render),
                       "GAZETRACE_DEVICE", png);
}

// An unreadable video printed four OpenCV/GStreamer lines before gazetrace's own.
TEST(Cli, UnreadableVideoIsOneLine) {
    const auto dir = test::tempDir("cli_badvideo");
    const auto video = dir / "noise.mkv";
    {
        std::ofstream out(video, std::ios::binary);
        for (int i = 0; i < 4096; ++i) {
            out.put(static_cast<char>((i * 7919) & 0xFF));
        }
    }
    const Result r = run("track --source video:" + video.string());
    EXPECT_NE(r.status, 0);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("noise.mkv"), std::string::npos) << r.err;
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// The soak in small: 120 frames through all eight phases of settings (the seventh on the shipped
// animated sample, the eighth path traced), two saccades,
// readback, validation and synchronisation validation on. The 1,000-frame run at 1920 x 1080
// is for the closing note; this one keeps the command and its bookkeeping honest.
TEST(Cli, SoakRunsEveryPhaseWithoutValidationErrors) {
    const auto dir = test::tempDir("cli_soak");
    const Result r = run("soak --frames 120 --width 160 --height 90 --json --cache " +
                         (dir / "cache").string() + " --json-file " + (dir / "soak.json").string() +
                         " --animated-scene " GT_SOURCE_DIR "/content/animated/moving_parts.gltf");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["frames"], 120);
    EXPECT_EQ(j["validation_errors"], 0);
    EXPECT_EQ(j["validation"], "khronos + synchronization");
    EXPECT_EQ(j["phases"].size(), 8u);
    EXPECT_EQ(j["saccades"], 2);                       // frames 40 and 80
    EXPECT_EQ(j["readback_bytes"], 15 * 160 * 90 * 4); // the readback phase, frames 75-89
    EXPECT_GT(j["rays_total"].get<double>(), 120 * 1000.0);
    EXPECT_NEAR(j["rays"].get<double>(), j["rays_total"].get<double>() / 120, 1.0); // per frame
    EXPECT_TRUE(j["growth_percent"].is_null()); // measured only past frame 120
    ASSERT_EQ(j["resident_mib"].size(), 2u);    // frame 100 and the last, 120
    EXPECT_GT(j["resident_mib"][0]["resident_mib"].get<double>(), 10.0);
    EXPECT_EQ(nlohmann::json::parse(slurp(dir / "soak.json")), j);
    expectCleanFailure(run("soak --frames 0"), "--frames", dir / "none");
}

// The README's table of defaults is what `gazetrace options` prints from the CLI11 definitions
// that parse the command line: a default changed in code and not in the README fails here
// (scripts/options_table.sh rewrites the table).
TEST(Cli, ReadmeOptionsTableIsGeneratedFromTheOptions) {
    const Result r = run("options");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("| `render` | "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("`--scene builtin:market`"), std::string::npos) << r.out;
    const std::string readme = slurp(GT_SOURCE_DIR "/README.md");
    const std::string begin = "<!-- options-table -->\n";
    const std::size_t i = readme.find(begin);
    const std::size_t j = readme.find("<!-- /options-table -->");
    ASSERT_NE(i, std::string::npos);
    ASSERT_NE(j, std::string::npos);
    EXPECT_EQ(readme.substr(i + begin.size(), j - i - begin.size()), r.out)
        << "README.md's options table is stale: run scripts/options_table.sh";
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// A POSITION count of (2^64 + 2) / 3 wraps count x 3 to 2 floats, so an unchecked bounds test
// passes and the loader writes past them: render and eval refuse it with one line naming the
// accessor, and a GAZETRACE_MAX_TRIANGLES that is not a whole number with one naming it.
TEST(Cli, GltfSizesThatWrapAroundAndBadLimitsAreRefused) {
    const auto dir = test::tempDir("cli_wrap");
    std::string json = test::quadJsonBesideBin(dir);
    const std::string count = R"("count": 4, "type": "VEC3")";
    json.replace(json.find(count), count.size(), R"("count": 6148914691236517206, "type": "VEC3")");
    test::writeFile(dir / "wrap.gltf", json.data(), json.size());
    const std::string scene = " --scene " + (dir / "wrap.gltf").string();
    const Result r =
        run("render" + scene + " --width 16 --height 12 --out " + (dir / "o.png").string());
    expectCleanFailure(r, "wrap.gltf: accessors[0] (byteOffset 0, count 6148914691236517206",
                       dir / "o.png");
    const Result e = run("eval" + scene + " --out " + (dir / "e").string());
    expectCleanFailure(e, "wrap.gltf: accessors[0]", dir / "e" / "eval.json");
    const Result bad = test::runWith(
        "env GAZETRACE_MAX_TRIANGLES=1e99",
        "render --scene builtin:cornell --width 16 --height 12 --out " + (dir / "t.png").string());
    expectCleanFailure(bad, "GAZETRACE_MAX_TRIANGLES=1e99", dir / "t.png");
}

} // namespace
} // namespace gt
