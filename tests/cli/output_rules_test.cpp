// The one rule for every output (io/atomic_write.hpp) at the command line: an output that names
// an input, two outputs naming one file, a device node at the output, a folder run that fails
// and a folder that cannot be written are each one line, exit 1, and leave every file as it was.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include "support/cli_run.hpp"
#include "support/gltf_fixtures.hpp"
#include "support/gpu_test_context.hpp"

namespace gt {
namespace {

using test::Result;
using test::run;
using test::slurp;

// One line naming both options, exit 1, and `kept` as it was.
void expectRefused(const Result& r, const std::string& output, const std::string& input,
                   const std::filesystem::path& kept, const std::string& before) {
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find(output), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(input), std::string::npos) << r.err;
    EXPECT_EQ(test::lines(r.err), 1) << r.err;
    EXPECT_EQ(slurp(kept), before) << kept << " was overwritten";
}

// `track --pupils SRC` destroyed the recording, `calibrate --out TARGETS.csv` its targets, and
// `eyesim --out X --truth X` exited 0 with the truth where the video was.
TEST(OutputRules, AnOutputThatIsAnInputIsRefused) {
    const auto dir = test::tempDir("cli_out_is_in");
    const std::string clip = (dir / "clip.mkv").string(), truth = (dir / "truth.csv").string();
    ASSERT_EQ(
        run("eyesim --seed 3 --frames 30 --size 64x48 --out " + clip + " --truth " + truth).status,
        0);
    const std::string video = slurp(clip), rows = slurp(truth);
    ASSERT_FALSE(video.empty());
    const std::string other = (dir / "." / "clip.mkv").string(); // another spelling
    expectRefused(run("track --source video:" + clip + " --pupils " + other), "--pupils",
                  "--source", clip, video);
    expectRefused(run("track --source video:" + clip + " --truth " + truth + " --pupils " + truth),
                  "--pupils", "--truth", truth, rows);
    expectRefused(
        run("calibrate --source video:" + clip + " --targets " + truth + " --out " + truth),
        "--out", "--targets", truth, rows);
    expectRefused(run("eyesim --frames 5 --out " + clip + " --truth " + other), "--out", "--truth",
                  clip, video);
    std::filesystem::create_symlink(dir / "truth.csv", dir / "link.csv");
    expectRefused(run("render --gaze-trace " + truth + " --graph " + (dir / "link.csv").string() +
                      " --out " + (dir / "x.png").string()),
                  "--graph", "--gaze-trace", truth, rows);
    expectRefused(run("pointset --out " + truth + " --image " + truth), "--out", "--image", truth,
                  rows);
    expectRefused(run("eyescore --seeds 1 --frames 5 --misses " + truth + " --answers " + truth),
                  "--misses", "--answers", truth, rows);
    // eval writes foveated.png into --out: a --reference of that name there is refused.
    test::writeFile(dir / "foveated.png", "reference", 9);
    expectRefused(
        run("eval --reference " + (dir / "foveated.png").string() + " --out " + dir.string()),
        "--out", "--reference", dir / "foveated.png", "reference");
    expectRefused(run("bench --json " + truth + " --scene " + truth), "--json", "--scene", truth,
                  rows);
    expectRefused(run("soak --json-file " + truth + " --scene " + truth), "--json-file", "--scene",
                  truth, rows);
    expectRefused(run("demo --camera-path " + truth + " --log " + truth), "--log", "--camera-path",
                  truth, rows);
    expectRefused(run("xr --gaze trace:" + truth + " --screenshot-eye left " + truth),
                  "--screenshot", "--gaze", truth, rows);
}

// As root, `--out /dev/null` turned the device node into a regular file. A device, a FIFO or a
// folder at any output is refused before any work (bench wrote its --json only at its end).
TEST(OutputRules, ADeviceNodeOutputIsRefused) {
    const auto dir = test::tempDir("cli_out_device");
    const auto null = dir / "null.csv";
    const bool device = ::mknod(null.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0;
    if (!device) {
        ASSERT_EQ(::mkfifo(null.c_str(), 0666), 0); // not root: a FIFO
    }
    const std::string kind = device ? "a character device" : "a FIFO";
    for (const std::string& args :
         {"eyesim --frames 5 --out " + (dir / "c.mkv").string() + " --truth " + null.string(),
          "bench --quick --json " + null.string(),
          "track --source 'synthetic:1?frames=5' --pupils " + null.string()}) {
        const Result r = run(args);
        EXPECT_EQ(r.status, 1) << args;
        EXPECT_NE(r.err.find(null.string() + ": it is " + kind), std::string::npos) << r.err;
        EXPECT_EQ(test::lines(r.err), 1) << r.err;
    }
    struct stat st {};
    ASSERT_EQ(::lstat(null.c_str(), &st), 0);
    EXPECT_TRUE(device ? S_ISCHR(st.st_mode) : S_ISFIFO(st.st_mode));
    EXPECT_FALSE(std::filesystem::exists(dir / "c.mkv"));
}

// A render into a frame folder that fails at frame 1 (a folder in the way) must not lose the
// earlier run's frame 0: the run writes into a folder of its own beside the target, so the
// earlier frames stay as they were and nothing of the run is left.
TEST(OutputRules, AFailedFolderRunKeepsTheEarlierFrames) {
    const auto dir = test::tempDir("cli_folder_run");
    const auto frames = dir / "frames";
    const std::string render =
        "render --scene builtin:cornell --width 8 --height 8 --out " + frames.string();
    ASSERT_EQ(run(render + " --frames 1").status, 0);
    const std::string first = slurp(frames / "frame_0000.png");
    ASSERT_FALSE(first.empty());
    std::filesystem::create_directory(frames / "frame_0001.png");
    const Result r = run(render + " --frames 2 --seed 9");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("frame_0001.png"), std::string::npos) << r.err;
    EXPECT_EQ(slurp(frames / "frame_0000.png"), first);
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        EXPECT_EQ(e.path().filename(), "frames") << "left behind: " << e.path();
    }
}

// Names of 255 bytes failed: the temporary's ".tmp<pid>_<n>" pushed them past NAME_MAX.
TEST(OutputRules, NamesOfNameMaxBytesAreWritten) {
    const auto dir = test::tempDir("cli_long_names");
    const auto clip = dir / (std::string(251, 'c') + ".mkv");
    const auto truth = dir / (std::string(251, 't') + ".csv");
    const Result r =
        run("eyesim --frames 5 --size 64x48 --out " + clip.string() + " --truth " + truth.string());
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_GT(std::filesystem::file_size(clip), 0u);
    EXPECT_GT(std::filesystem::file_size(truth), 0u);
}

// A read-only folder is named as such, not reported as "cannot open a lossless FFV1 writer".
// Root writes anywhere, so the run is made as nobody.
TEST(OutputRules, AReadOnlyFolderIsNamed) {
    const auto dir = test::tempDir("cli_read_only");
    const auto ro = dir / "ro";
    std::filesystem::create_directory(ro);
    ::chmod(ro.c_str(), 0555);
    const std::string as =
        ::geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups" : "";
    const Result r = test::runWith(as, "eyesim --frames 5 --out " + (ro / "c.mkv").string() +
                                           " --truth " + (dir / "t.csv").string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("folder " + ro.string() + " is not writable"), std::string::npos) << r.err;
    EXPECT_EQ(test::lines(r.err), 1) << r.err;
}

} // namespace
} // namespace gt
