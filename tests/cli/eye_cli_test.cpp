// The eye tracker's newer commands end to end: two eyes (binocular clips, per-eye calibration in
// one session, vergence, per-eye UDP datagrams), the 3D eye model against the 2D polynomial after
// the headset slips, eyescore, and their bad inputs.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli_run.hpp"

namespace gt {
namespace {

using test::expectCleanFailure;
using test::Result;
using test::run;
using test::slurp;

std::filesystem::path freshDir(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("gazetrace_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

TEST(EyeCli, TwoEyesInOneCameraVergenceAndUdp) {
    const auto dir = freshDir("bino");
    const std::string clip = (dir / "both.mkv").string();
    const std::string left = (dir / "l.csv").string(), right = (dir / "r.csv").string();
    // Targets of 400 ms, then free viewing converged at 40 cm (the screen is at 59 cm).
    const Result sim =
        run("eyesim --seed 4 --frames 1100 --target-ms 400 --size 160x120 --eye both "
            "--depth-cm 40 --out " +
            clip + " --truth " + left + " --truth-right " + right + " --json");
    ASSERT_EQ(sim.status, 0) << sim.err;
    const auto s = nlohmann::json::parse(sim.out);
    EXPECT_EQ(s.at("width"), 320);
    const std::string regions = s.at("regions").get<std::string>();
    EXPECT_EQ(regions, "0,0,160,120;160,0,160,120");

    const std::string calib = (dir / "cal.json").string();
    const Result cal = run("calibrate --source video:" + clip + " --regions '" + regions +
                           "' --targets " + left + " --settle-ms 250 --out " + calib + " --json");
    ASSERT_EQ(cal.status, 0) << cal.err;
    const auto c = nlohmann::json::parse(cal.out);
    for (const char* eye : {"left", "right"}) {
        EXPECT_LT(c.at("eyes").at(eye).at("accuracy_deg").get<double>(), 1.0) << eye;
    }
    const auto file = nlohmann::json::parse(slurp(calib));
    EXPECT_EQ(file.at("version"), 3);
    EXPECT_EQ(file.at("eyes").size(), 2u);

    // Listen for the datagrams.
    const int sock = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
    ASSERT_GE(sock, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(::bind(sock, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)), 0);
    socklen_t len = sizeof(addr);
    ASSERT_EQ(::getsockname(sock, reinterpret_cast<sockaddr*>(&addr), &len), 0);
    const int port = ntohs(addr.sin_port);
    int rcvbuf = 8 << 20;
    (void)::setsockopt(sock, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof(rcvbuf));

    const Result track =
        run("track --source video:" + clip + " --regions '" + regions + "' --calibration " + calib +
            " --truth " + left + " --truth-right " + right +
            " --max-frames 400 --emit udp://127.0.0.1:" + std::to_string(port) + " --out " +
            (dir / "gaze.csv").string() + " --json");
    ASSERT_EQ(track.status, 0) << track.err;
    const auto t = nlohmann::json::parse(track.out);
    EXPECT_EQ(t.at("frames_left"), 400);
    EXPECT_EQ(t.at("frames_right"), 400);
    EXPECT_GE(t.at("detection_rate_5px_left").get<double>(), 0.95);
    EXPECT_GE(t.at("detection_rate_5px_right").get<double>(), 0.95);
    EXPECT_GT(t.at("samples_with_vergence").get<int>(), 100);
    // The truth vergence at 40 cm is 9.0 deg, on the screen 6.1 deg: a wrong model misses by
    // degrees.
    EXPECT_LT(t.at("vergence_error_deg_median").get<double>(), 0.5);
    EXPECT_EQ(slurp(dir / "gaze.csv").rfind("t_ms,x,y,left_x,left_y,right_x,right_y,", 0), 0u);

    std::set<std::string> eyes;
    bool vergence = false;
    char buffer[2048];
    for (;;) {
        const ssize_t n = ::recv(sock, buffer, sizeof(buffer), 0);
        if (n <= 0) break;
        const auto j = nlohmann::json::parse(buffer, buffer + n);
        eyes.insert(j.at("eye").get<std::string>());
        if (j.contains("vergence_deg")) {
            vergence = true;
            EXPECT_EQ(j.at("eye"), "both");
        }
    }
    ::close(sock);
    EXPECT_EQ(eyes, (std::set<std::string>{"both", "left", "right"}));
    EXPECT_TRUE(vergence);
}

TEST(EyeCli, TheEyeModelStaysAccurateWhenTheHeadsetSlips) {
    const auto dir = freshDir("model3d");
    const std::string a = (dir / "a.mkv").string(), at = (dir / "a.csv").string();
    const std::string b = (dir / "b.mkv").string(), bt = (dir / "b.csv").string();
    const std::string cam = (dir / "cam.json").string(), calib = (dir / "cal.json").string();
    ASSERT_EQ(run("eyesim --seed 5 --frames 1600 --perspective --out " + a + " --truth " + at +
                  " --intrinsics-out " + cam)
                  .status,
              0);
    ASSERT_EQ(run("eyesim --seed 5 --frames 1600 --perspective --slip-mm 2,1,0.5 --slip-deg 2 "
                  "--out " +
                  b + " --truth " + bt)
                  .status,
              0);
    const Result cal = run("calibrate --source video:" + a + " --targets " + at + " --intrinsics " +
                           cam + " --out " + calib + " --json");
    ASSERT_EQ(cal.status, 0) << cal.err;
    const auto c = nlohmann::json::parse(cal.out);
    EXPECT_LT(c.at("accuracy_deg").get<double>(), 1.0);
    EXPECT_LT(c.at("model3d").at("accuracy_deg").get<double>(), 1.0);
    auto accuracy = [&](const std::string& clip, const std::string& truth, const char* model) {
        const Result r = run("track --source video:" + clip + " --calibration " + calib +
                             " --truth " + truth + " --model " + model + " --json");
        EXPECT_EQ(r.status, 0) << r.err;
        return nlohmann::json::parse(r.out).at("gaze_accuracy_deg").get<double>();
    };
    EXPECT_GT(accuracy(b, bt, "2d"), 5.0); // the polynomial cannot follow the moved eye
    EXPECT_LT(accuracy(b, bt, "3d"), 1.0);
    // Flags instead of the file: the same camera.
    const Result flags =
        run("track --source video:" + b + " --calibration " + calib + " --truth " + bt +
            " --model 3d --focal 318.5 --principal 159.5,119.5"
            " --json");
    ASSERT_EQ(flags.status, 0) << flags.err;
    EXPECT_LT(nlohmann::json::parse(flags.out).at("gaze_accuracy_deg").get<double>(), 1.0);
}

TEST(EyeCli, EyescoreReportsTheIssuesNumbers) {
    const Result r = run("eyescore --preset hard --seeds 3-4 --frames 60 --json");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    for (const char* key : {"detection_rate", "roc_auc", "wrong_rejected", "right_kept",
                            "median_fps", "threshold_sweep", "per_seed"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j.at("frames"), 120);
    EXPECT_EQ(j.at("per_seed").size(), 2u);
    EXPECT_GE(j.at("detection_rate").get<double>(), 0.9);
    const Result blob = run("eyescore --preset wild --detector blob --seeds 3 --frames 60 --json");
    ASSERT_EQ(blob.status, 0) << blob.err;
    EXPECT_EQ(nlohmann::json::parse(blob.out).at("detector"), "blob");
}

TEST(EyeCli, ColdScoringJudgesEveryFrameAsAFirstFrame) {
    // --cold forgets the detector's history before every frame: clean pupils are still found and
    // trusted on their own evidence.
    const Result r = run("eyescore --preset clean --seeds 2 --frames 20 --cold --json");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j.at("cold"), true);
    EXPECT_EQ(j.at("detection_rate").get<double>(), 1.0);
    EXPECT_EQ(j.at("right_kept").get<double>(), 1.0);
    const Result track = run("track --source synthetic:2 --max-frames 5 --cold --json");
    ASSERT_EQ(track.status, 0) << track.err;
    EXPECT_EQ(nlohmann::json::parse(track.out).at("cold"), true);
}

TEST(EyeCli, EyesimReportsWhatTheSeedDrew) {
    // The wild preset draws its variations per seed; the JSON summary says which, so a clip that
    // scores badly can be told apart by what it shows.
    const auto dir = freshDir("appearance");
    auto appearance = [&](const std::string& preset, int seed) {
        const Result r = run("eyesim --preset " + preset + " --seed " + std::to_string(seed) +
                             " --frames 1 --json --out " + (dir / "a.mkv").string() + " --truth " +
                             (dir / "a.csv").string());
        EXPECT_EQ(r.status, 0) << r.err;
        return nlohmann::json::parse(r.out).at("appearance");
    };
    const nlohmann::json clean = appearance("clean", 1);
    EXPECT_EQ(clean.at("glints"), 1);
    EXPECT_EQ(clean.at("camera_tilt_deg"), 0.0);
    EXPECT_EQ(clean.at("iris_contrast"), 0.0);
    // Wild seeds differ, and the same seed draws the same eye.
    std::set<std::string> drawn;
    for (int seed = 1; seed <= 4; ++seed) {
        const nlohmann::json a = appearance("wild", seed);
        EXPECT_GE(a.at("blur_sigma").get<double>(), 0.6);
        EXPECT_LE(a.at("blur_sigma").get<double>(), 2.0);
        drawn.insert(a.dump());
    }
    EXPECT_EQ(drawn.size(), 4U);
    EXPECT_EQ(appearance("wild", 3), appearance("wild", 3));
}

TEST(EyeCli, BadInputsAreOneLine) {
    const auto dir = freshDir("eye_bad");
    const auto none = dir / "none.json";
    expectCleanFailure(run("eyescore --seeds 9-3 --frames 10"), "--seeds", none);
    expectCleanFailure(run("eyescore --detector magic --seeds 1 --frames 10"), "magic", none);
    expectCleanFailure(run("slippage --slips-mm 1,x"), "--slips-mm", none);
    expectCleanFailure(run("track --source synthetic:1 --model 4d --calibration " + none.string()),
                       "--model", none);
    expectCleanFailure(
        run("track --source synthetic:1 --regions 0,0,10 --calibration " + none.string()),
        "--regions", none);
    expectCleanFailure(run("track --source-left synthetic:1"), "--source-right", none);
    expectCleanFailure(run("track --source synthetic:1 --regions \"0,0,160,240;160,0,160,240\" "
                           "--cold"),
                       "--cold", none);
    expectCleanFailure(run("eyesim --eye both --out " + (dir / "x.mkv").string() + " --truth " +
                           (dir / "x.csv").string()),
                       "--truth-right", dir / "x.mkv");
    // A one-eye calibration cannot drive two eyes; a broken intrinsics file is named.
    const std::string clip = (dir / "c.mkv").string(), truth = (dir / "c.csv").string();
    ASSERT_EQ(run("eyesim --seed 2 --frames 650 --target-ms 400 --size 160x120 --out " + clip +
                  " --truth " + truth)
                  .status,
              0);
    const std::string calib = (dir / "cal.json").string();
    ASSERT_EQ(run("calibrate --source video:" + clip + " --targets " + truth +
                  " --settle-ms 250 "
                  "--out " +
                  calib)
                  .status,
              0);
    expectCleanFailure(run("track --source-left video:" + clip + " --source-right video:" + clip +
                           " --calibration " + calib),
                       "left", none);
    expectCleanFailure(
        run("track --source video:" + clip + " --calibration " + calib + " --model 3d"), "3D model",
        none);
    { std::ofstream(dir / "cam.json") << "{\"fx\": -1, \"fy\": 2, \"cx\": 1, \"cy\": 1}"; }
    expectCleanFailure(run("calibrate --source video:" + clip + " --targets " + truth +
                           " --intrinsics " + (dir / "cam.json").string() + " --out " +
                           (dir / "cal2.json").string()),
                       "cam.json", dir / "cal2.json");
}

// Hostile files at the command line: each run ends in one line naming the file, a non-zero exit
// and no output file: a FIFO calibration must not block, a playlist named .mkv must not make
// FFmpeg read the files it lists, a clip cut by one frame must not end cleanly, and a damaged
// calibration or truth must not be read.
TEST(EyeCli, HostileFilesAreOneLine) {
    const auto dir = freshDir("eye_hostile");
    const std::string clip = (dir / "c.avi").string(), truth = (dir / "c.csv").string();
    ASSERT_EQ(
        run("eyesim --seed 4 --frames 40 --size 64x48 --out " + clip + " --truth " + truth).status,
        0);
    const nlohmann::json calibration = {
        {"format", "gazetrace-calibration"},
        {"version", 2},
        {"model", "poly4"},
        {"display",
         {{"width_px", 1920}, {"height_px", 1080}, {"width_cm", 53.0}, {"distance_cm", 60.0}}},
        {"pupil_mean", {32.0, 24.0}},
        {"pupil_scale", {5.0, 4.0}},
        {"coefficients_x", {0.0, 10.0, 0.0, 0.0}},
        {"coefficients_y", {0.0, 0.0, -8.0, 0.0}}};
    const std::string cal = (dir / "cal.json").string();
    std::ofstream(cal) << calibration.dump();
    const auto out = dir / "gaze.csv";
    const std::string track = "track --out " + out.string() + " ";
    ASSERT_EQ(run(track + "--source video:" + clip + " --calibration " + cal).status, 0);
    std::filesystem::remove(out);

    // The clip cut short: 40 frames declared, fewer read.
    std::filesystem::copy_file(clip, dir / "cut.avi");
    std::filesystem::resize_file(dir / "cut.avi", std::filesystem::file_size(clip) * 9 / 10);
    expectCleanFailure(
        run(track + "--source video:" + (dir / "cut.avi").string() + " --calibration " + cal),
        "of the 40 its container declares", out);
    std::ofstream(dir / "playlist.mkv") << "#EXTM3U\n#EXT-X-TARGETDURATION:1\n#EXTINF:1,\n"
                                        << clip << "\n#EXT-X-ENDLIST\n";
    expectCleanFailure(
        run(track + "--source video:" + (dir / "playlist.mkv").string() + " --calibration " + cal),
        "playlist.mkv: a playlist", out);
    ASSERT_EQ(::mkfifo((dir / "fifo.json").c_str(), 0600), 0);
    expectCleanFailure(
        run(track + "--source video:" + clip + " --calibration " + (dir / "fifo.json").string()),
        "fifo.json: a FIFO", out);
    std::ofstream(dir / "trailing.json") << calibration.dump() << "}garbage";
    expectCleanFailure(run(track + "--source video:" + clip + " --calibration " +
                           (dir / "trailing.json").string()),
                       "trailing.json: not valid JSON", out);
    nlohmann::json mistyped = calibration;
    mistyped["display"]["distance_cm"] = "60";
    std::ofstream(dir / "mistyped.json") << mistyped.dump();
    expectCleanFailure(run(track + "--source video:" + clip + " --calibration " +
                           (dir / "mistyped.json").string()),
                       "\"display.distance_cm\" is not a number", out);
    // Truth with a NaN, then with two rows swapped.
    std::string rows = slurp(truth);
    std::string nan = rows; // the first row's t_ms, a column track does not score
    const auto firstComma = nan.find(',', nan.find('\n'));
    nan.replace(firstComma + 1, nan.find(',', firstComma + 1) - firstComma - 1, "nan");
    std::ofstream(dir / "nan.csv") << nan;
    expectCleanFailure(run(track + "--source video:" + clip + " --calibration " + cal +
                           " --truth " + (dir / "nan.csv").string()),
                       "nan.csv:2: t_ms 'nan'", out);
    const auto second = rows.find('\n') + 1, third = rows.find('\n', second) + 1,
               fourth = rows.find('\n', third) + 1;
    const std::string swapped = rows.substr(0, second) + rows.substr(third, fourth - third) +
                                rows.substr(second, third - second) + rows.substr(fourth);
    std::ofstream(dir / "swapped.csv") << swapped;
    expectCleanFailure(run(track + "--source video:" + clip + " --calibration " + cal +
                           " --truth " + (dir / "swapped.csv").string()),
                       "swapped.csv:3: frame 0 does not follow 1", out);
    expectCleanFailure(run("calibrate --source video:" + clip + " --targets " +
                           (dir / "swapped.csv").string() + " --out " + out.string()),
                       "swapped.csv:3: t_ms", out);
    // An image folder whose frame claims 100000 x 100000 pixels.
    std::filesystem::create_directories(dir / "frames");
    std::string png("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\x01\x86\xa0\0\x01\x86\xa0\x08\0\0\0\0"
                    "\x8d\x39\x54\x14\0\0\0\0IEND\xae\x42\x60\x82",
                    45);
    std::ofstream(dir / "frames" / "a.png", std::ios::binary) << png;
    expectCleanFailure(
        run(track + "--source images:" + (dir / "frames").string() + " --calibration " + cal),
        "a.png: 100000 x 100000 pixels", out);
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// eyesim's clip is written by OpenCV, not by gazetrace's writer: it must still appear only
// whole. A run that fails at the end (a full disk, through the write-fault seam) replaced an
// existing clip with the new one; now it leaves the old clip, no new file under the final name
// and no temporary behind.
TEST(EyeCli, EyesimClipAppearsOnlyWhenTheRunSucceeds) {
    const auto dir = freshDir("eyesim_whole");
    const auto clip = dir / "clip.mkv", truth = dir / "truth.csv";
    const std::string args = "eyesim --seed 3 --frames 30 --size 64x48 --out " + clip.string() +
                             " --truth " + truth.string();
    const Result first = run(args);
    ASSERT_EQ(first.status, 0) << first.err;
    const std::string clipBefore = slurp(clip), truthBefore = slurp(truth);
    ASSERT_FALSE(clipBefore.empty());
    auto onlyTheOutputs = [&](std::size_t expected) {
        std::size_t n = 0;
        for (const auto& e : std::filesystem::directory_iterator(dir)) {
            const auto name = e.path().filename();
            EXPECT_TRUE(name == "clip.mkv" || name == "truth.csv") << "left behind: " << e.path();
            ++n;
        }
        EXPECT_EQ(n, expected);
    };
    onlyTheOutputs(2);
    const Result full = test::runWith("GAZETRACE_WRITE_FAULT=enospc",
                                      "eyesim --seed 8 --frames 30 --size 64x48 --out " +
                                          clip.string() + " --truth " + truth.string());
    EXPECT_EQ(full.status, 1);
    EXPECT_NE(full.err.find("No space left"), std::string::npos) << full.err;
    EXPECT_TRUE(slurp(clip) == clipBefore) << "the old clip was replaced"; // (no binary dump)
    EXPECT_EQ(slurp(truth), truthBefore);
    onlyTheOutputs(2);
    // With no clip there before, a failed run leaves none under the final name.
    std::filesystem::remove(clip);
    std::filesystem::remove(truth);
    EXPECT_EQ(test::runWith("GAZETRACE_WRITE_FAULT=enospc", args).status, 1);
    EXPECT_FALSE(std::filesystem::exists(clip));
    onlyTheOutputs(0);
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// The detector on the real near-infrared recording in ../shared/eyedata, against the pupil
// centres labelled by hand (content/eyedata/real_nir_part1.labels.csv, 60 frames with a pupil).
TEST(EyeCli, RealRecordingAgainstHandLabels) {
    const std::filesystem::path clip = std::filesystem::path(GT_SHARED_CONTENT_DIR).parent_path() /
                                       "eyedata" / "real_nir_part1.mp4";
    if (!std::filesystem::exists(clip)) GTEST_SKIP() << clip << " is absent";
    const std::string labels =
        (std::filesystem::path(GT_SOURCE_DIR) / "content/eyedata/real_nir_part1.labels.csv")
            .string();
    const Result r =
        run("track --source video:" + clip.string() + " --truth " + labels + " --json");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j.at("visible_frames"), 60);
    EXPECT_EQ(j.at("certain_visible_frames"), 29);
    // Every clearly visible pupil within 5 px; the misses are pupils cut off by the frame's edge,
    // where the label itself extrapolates.
    EXPECT_EQ(j.at("detection_rate_5px_certain").get<double>(), 1.0);
    EXPECT_GE(j.at("detection_rate_5px").get<double>(), 0.9);
    EXPECT_LT(j.at("median_error_px").get<double>(), 1.5);
}

} // namespace
} // namespace gt
