// `gazetrace demo` end to end under Xvfb (lavapipe, validation on): the window shows what the
// headless path renders, survives a resize, and fails cleanly without a display or with a bad
// gaze source.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gaze_mapping.hpp"
#include "scene/image_io.hpp"
#include "support/cli_run.hpp"
#include "support/gpu_test_context.hpp"

namespace gt {
namespace {

using test::Result;

bool haveXvfb() {
    return std::system("command -v xvfb-run >/dev/null 2>&1") == 0;
}

constexpr const char* kXvfb = "xvfb-run -a -s '-screen 0 1280x720x24'";

// A gaze trace for a 320 x 180 window: a fixation, a saccade, a fixation.
std::filesystem::path writeTrace(const std::filesystem::path& dir) {
    const auto file = dir / "gaze.csv";
    std::ofstream out(file);
    out << "t_ms,x,y\n0,100,60\n400,100,60\n450,220,120\n2000,220,120\n";
    return file;
}

TEST(Demo, WindowMatchesHeadlessRenderInTheFovea) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    const auto dir = test::tempDir("demo_fovea");
    const auto trace = writeTrace(dir);
    // The market, not the Cornell box: its flat walls hide a wrong gaze (0.07/255 against 3.5/255).
    const std::string common = "--scene builtin:market --scale 2 --interp nn --rays-per-point 1 "
                               "--frame-ms 50 --frames 30 --cache " +
                               (dir / "cache").string();
    const auto shot = dir / "window.png";
    const Result demo = test::runWith(
        kXvfb, "demo --width 320 --height 180 --gaze trace:" + trace.string() +
                   " --overlay off --validate --json --screenshot " + shot.string() + " " + common);
    ASSERT_EQ(demo.status, 0) << demo.err;
    const auto j = nlohmann::json::parse(demo.out);
    EXPECT_EQ(j["frames"], 30);
    EXPECT_EQ(j["window"][0], 320);
    const Result headless = test::run(
        "render --method foveated --profile desktop --width 320 --height 180 --gaze-trace " +
        trace.string() + " --validate --out " + (dir / "frames").string() + " " + common);
    ASSERT_EQ(headless.status, 0) << headless.err;
    const image::DecodedImage a = image::readPng(shot);
    const image::DecodedImage b = image::readPng(dir / "frames" / "frame_0029.png");
    ASSERT_EQ(a.width, 320u);
    ASSERT_EQ(b.width, 320u);
    ASSERT_EQ(a.height, b.height);
    // The fovea: 5 degrees around the last gaze (220, 120) at the desktop screen's 38.8 pixels
    // per degree (51 cm wide, 1920 pixels, seen from 59 cm).
    const double radius = 5.0 * 59.0 * std::tan(M_PI / 180.0) / (51.0 / 1920.0);
    double diff = 0.0;
    std::size_t n = 0;
    for (uint32_t y = 0; y < a.height; ++y) {
        for (uint32_t x = 0; x < a.width; ++x) {
            if (std::hypot(x - 220.0, y - 120.0) > radius) continue;
            for (int c = 0; c < 3; ++c) {
                const std::size_t i = (static_cast<std::size_t>(y) * a.width + x) * 4 + c;
                diff += std::abs(static_cast<int>(a.rgba[i]) - static_cast<int>(b.rgba[i]));
                ++n;
            }
        }
    }
    ASSERT_GT(n, 1000u);
    EXPECT_LE(diff / static_cast<double>(n), 2.0);
}

// The demo shows layered foveation, the same as `render --method layers` where the eye
// looks, and both eyes of the HMD path take their own layers.
TEST(Demo, LayersInTheWindowMatchHeadless) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    const auto dir = test::tempDir("demo_layers");
    const auto trace = writeTrace(dir);
    const std::string common =
        "--scene builtin:market --method layers --slope 0.05 --frame-ms 50 --frames 12";
    const auto shot = dir / "window.png";
    Result r = test::runWith(kXvfb, "demo --width 320 --height 180 --gaze trace:" + trace.string() +
                                        " --overlay off --validate --json "
                                        "--screenshot " +
                                        shot.string() + " " + common);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["method"], "layers");
    r = test::run("render --profile desktop --width 320 --height 180 --gaze-trace " +
                  trace.string() + " --validate --out " + (dir / "frames").string() + " " + common);
    ASSERT_EQ(r.status, 0) << r.err;
    const image::DecodedImage a = image::readPng(shot);
    const image::DecodedImage b = image::readPng(dir / "frames" / "frame_0011.png");
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    double diff = 0.0;
    std::size_t n = 0;
    for (uint32_t y = 0; y < a.height; ++y) {
        for (uint32_t x = 0; x < a.width; ++x) {
            if (std::hypot(x - 220.0, y - 120.0) > 60.0) continue;
            for (int c = 0; c < 3; ++c) {
                const std::size_t i = (static_cast<std::size_t>(y) * a.width + x) * 4 + c;
                diff += std::abs(static_cast<int>(a.rgba[i]) - static_cast<int>(b.rgba[i]));
                ++n;
            }
        }
    }
    EXPECT_LE(diff / static_cast<double>(n), 2.0);
    r = test::runWith(kXvfb, "demo --hmd vive --method layers --frames 3 --overlay off "
                             "--validate --json --screenshot " +
                                 (dir / "hmd.png").string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "hmd.png"));
}

TEST(Demo, ResizeMidRunIsValidationClean) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    const auto dir = test::tempDir("demo_resize");
    const auto shot = dir / "after.png";
    const Result r = test::runWith(
        kXvfb, "demo --scene builtin:cornell --width 200 --height 120 --resize 3:240x160 "
               "--gaze fixed:100,60 --frames 8 --validate --json --cache " +
                   (dir / "cache").string() + " --screenshot " + shot.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["window"][0], 240); // the view followed the window
    EXPECT_EQ(j["window"][1], 160);
    EXPECT_EQ(image::readPng(shot).width, 240u);
}

// A trace in pixels of a larger screen (the FOVE's 1280 x 1440) in a small window: the gaze is
// clamped to the window's edge, and the demo says so once, as `render` does for such a trace.
// The run also starts from its device's defaults, with --scale given winning over them.
TEST(Demo, GazeOutsideTheWindowWarnsOnce) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    const auto dir = test::tempDir("demo_offscreen");
    const auto trace = dir / "fove.csv";
    std::ofstream(trace) << "t_ms,x,y\n0,100,60\n100,900,1200\n400,1100,1300\n";
    const Result r = test::runWith(
        kXvfb,
        "demo --scene builtin:cornell --width 320 --height 180 --gaze trace:" + trace.string() +
            " --frame-ms 50 --frames 8 --overlay off --scale 1.5 --json --cache " +
            (dir / "cache").string());
    ASSERT_EQ(r.status, 0) << r.err;
    // The device's defaults, and a method option given on the command line over them.
    const auto j = nlohmann::json::parse(r.out);
    const bool cpu = j["device"].get<std::string>().find("llvmpipe") != std::string::npos;
    EXPECT_EQ(j["defaults"], cpu ? "CPU fast" : "GPU quality");
    EXPECT_NE(r.err.find("at scale 1.500000"), std::string::npos) << r.err;
    const std::string warning = "outside the 320x180 window; the gaze is clamped to its edge";
    const auto first = r.err.find(warning);
    ASSERT_NE(first, std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(warning, first + 1), std::string::npos) << r.err; // once
    EXPECT_NE(r.err.find("trace:"), std::string::npos) << r.err;           // names the source
}

TEST(Demo, NoDisplayIsOneLineAndNoFile) {
    const auto dir = test::tempDir("demo_nodisplay");
    const auto shot = dir / "never.png";
    const Result r = test::runWith("env -u DISPLAY -u WAYLAND_DISPLAY",
                                   "demo --frames 2 --screenshot " + shot.string());
    test::expectCleanFailure(r, "cannot open a window", shot);
}

TEST(Demo, BadGazeSourceIsOneLine) {
    const auto dir = test::tempDir("demo_badgaze");
    const auto shot = dir / "never.png";
    test::expectCleanFailure(test::run("demo --gaze nonsense --screenshot " + shot.string()),
                             "--gaze", shot);
    test::expectCleanFailure(test::run("demo --gaze udp:99999 --screenshot " + shot.string()),
                             "port", shot);
    test::expectCleanFailure(test::run("demo --gaze trace:" + (dir / "missing.csv").string() +
                                       " --screenshot " + shot.string()),
                             "missing.csv", shot);
    test::expectCleanFailure(
        test::run("demo --gaze track:synthetic:1 --screenshot " + shot.string()), "--calibration",
        shot);
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// `gazetrace track --emit`'s datagrams drive the demo: a sender on this side sends numbered
// samples, and every frame the demo logs shows the gaze of the sample it says it had received
// last (its sequence), mapped from angles onto the desktop screen.
TEST(Demo, UdpSenderAndDemoAgreeOnTheSamples) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    const auto dir = test::tempDir("demo_udp");
    const int tx = ::socket(AF_INET, SOCK_DGRAM, 0);
    ASSERT_GE(tx, 0);
    // A free port: bind, read it back, close (the demo binds it a moment later).
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    {
        const int probe = ::socket(AF_INET, SOCK_DGRAM, 0);
        ASSERT_EQ(::bind(probe, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)), 0);
        socklen_t len = sizeof(addr);
        ASSERT_EQ(::getsockname(probe, reinterpret_cast<sockaddr*>(&addr), &len), 0);
        ::close(probe);
    }
    const int port = ntohs(addr.sin_port);
    // Sample i looks 20 degrees left and 12.5 - i/100 degrees up: with the window (320 x 180)
    // at the screen's top-left, that lands inside it, and its height says which sample it is.
    // Between the samples, hostile datagrams (the first three each once stopped the demo with
    // nlohmann's type_error): they are dropped, and the session goes on.
    const std::string hostile[] = {
        R"({"x":100,"y":100,"saccade_onset":1})", R"({"x":100,"y":100,"saccade_onset":"yes"})",
        R"({"x":100,"y":100,"saccade_onset":null})", R"({"x":1e400,"y":100})", "\xff\xfe"};
    std::atomic<bool> stop{false};
    std::thread sender([&] {
        // Until the demo is done, however long its start takes (a sanitizer build is slower).
        for (int i = 1; !stop; ++i) {
            const std::string& bad = hostile[static_cast<std::size_t>(i) % std::size(hostile)];
            (void)::sendto(tx, bad.data(), bad.size(), 0, reinterpret_cast<sockaddr*>(&addr),
                           sizeof(addr));
            const std::string msg = "{\"t_ms\":" + std::to_string(i) +
                                    ",\"eye\":\"both\",\"yaw_deg\":-20,\"pitch_deg\":" +
                                    std::to_string(12.5 - 0.01 * i) + "}";
            (void)::sendto(tx, msg.data(), msg.size(), 0, reinterpret_cast<sockaddr*>(&addr),
                           sizeof(addr));
            std::this_thread::sleep_for(std::chrono::milliseconds(15));
        }
    });
    const auto log = dir / "frames.csv";
    const Result r = test::runWith(kXvfb, "demo --scene builtin:cornell --width 320 --height 180 "
                                          "--overlay off --frames 25 --gaze udp:" +
                                              std::to_string(port) + " --log " + log.string() +
                                              " --cache " + (dir / "cache").string());
    stop = true;
    sender.join();
    ::close(tx);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("gaze udp:127.0.0.1:" + std::to_string(port) + ": dropped "),
              std::string::npos)
        << r.err;
    std::ifstream in(log);
    std::string line;
    std::getline(in, line);
    ASSERT_EQ(line, "frame,t_ms,frame_ms,gpu_ms,gaze_x,gaze_y,gaze_sequence,gaze_t_ms,latency_ms");
    const render::ScreenGeometry screen;
    int matched = 0;
    while (std::getline(in, line)) {
        std::vector<double> v;
        std::stringstream ss(line);
        for (std::string f; std::getline(ss, f, ',');)
            v.push_back(std::stod(f));
        ASSERT_EQ(v.size(), 9u) << line;
        if (v[6] == 0) continue; // no sample yet
        // The sample the frame used, by its own t_ms (= the sender's i): its gaze must be where
        // that sample's angles land.
        const double i = v[7];
        const glm::vec2 expected =
            screen.pixelOfAngles({-20.0f, static_cast<float>(12.5 - 0.01 * i)});
        EXPECT_NEAR(v[4], expected.x, 0.01) << line;
        EXPECT_NEAR(v[5], std::clamp(expected.y, 0.0f, 179.0f), 0.01) << line;
        ++matched;
    }
    EXPECT_GT(matched, 5);
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// demo --calibrate with a synthetic eye that is handed the demo's schedule: 9 calibration and 4
// validation targets, an accuracy well under a degree, and a file the tracker then loads.
TEST(Demo, CalibratesASyntheticEyeThatLooksAtItsTargets) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    const auto dir = test::tempDir("demo_calibrate");
    const auto file = dir / "calibration.json";
    const std::string common = "--scene builtin:cornell --width 320 --height 180 --overlay off "
                               "--cache " +
                               (dir / "cache").string();
    const Result r = test::runWith(kXvfb, "demo --calibrate --gaze track:synthetic:7 "
                                          "--calibration " +
                                              file.string() + " --frame-ms 500 --json " + common);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    const auto& c = j.at("calibration");
    EXPECT_EQ(c.at("calibration_targets"), 9);
    EXPECT_EQ(c.at("validation_targets"), 4);
    EXPECT_LT(c.at("accuracy_deg").get<double>(), 1.0);
    EXPECT_GT(c.at("validation_samples").get<int>(), 100);
    ASSERT_TRUE(std::filesystem::exists(file));
    // The tracker drives the demo with it.
    const Result use = test::runWith(kXvfb, "demo --gaze track:synthetic:7 --calibration " +
                                                file.string() + " --frames 3 " + common);
    EXPECT_EQ(use.status, 0) << use.err;
    // Without a camera to calibrate, or a file to write: one line each.
    test::expectCleanFailure(
        test::run("demo --calibrate --gaze mouse --calibration " + (dir / "x.json").string()),
        "track:", dir / "x.json");
    test::expectCleanFailure(test::run("demo --calibrate --gaze track:synthetic:1"),
                             "--calibration", dir / "y.json");
}

} // namespace
} // namespace gt
