// SIGINT and SIGTERM at the command line: a fixed-length run (render, eyesim) stopped while it
// writes fails in one line with 128 + the signal's number and leaves every folder as it found it
// (no frames, no temporaries, an existing output unchanged); a live run (demo) ends as if its
// window were closed, exit 0, its log and summary complete.
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli_run.hpp"
#include "support/gpu_test_context.hpp"

extern char** environ;

namespace gt {
namespace {

using namespace std::chrono_literals;

// `gazetrace ARGS` (behind `prefix`, e.g. xvfb-run) in the background, its stdout and stderr in
// files beside each other, signalled by the test while it runs.
class BackgroundRun {
public:
    BackgroundRun(const std::filesystem::path& logs, std::vector<std::string> args,
                  std::vector<std::string> prefix = {})
        : mOut(logs / "stdout.txt"), mErr(logs / "stderr.txt") {
        std::vector<std::string> argv = std::move(prefix);
        argv.push_back(GT_GAZETRACE_EXE);
        argv.insert(argv.end(), args.begin(), args.end());
        std::vector<char*> raw;
        for (std::string& a : argv)
            raw.push_back(a.data());
        raw.push_back(nullptr);
        posix_spawn_file_actions_t files;
        posix_spawn_file_actions_init(&files);
        posix_spawn_file_actions_addopen(&files, 1, mOut.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                         0644);
        posix_spawn_file_actions_addopen(&files, 2, mErr.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                         0644);
        // SIGINT and SIGTERM as a terminal delivers them, even when this test runs as a
        // background job (which a shell starts with SIGINT ignored, and gazetrace keeps so).
        posix_spawnattr_t attributes;
        posix_spawnattr_init(&attributes);
        sigset_t defaults;
        sigemptyset(&defaults);
        sigaddset(&defaults, SIGINT);
        sigaddset(&defaults, SIGTERM);
        posix_spawnattr_setsigdefault(&attributes, &defaults);
        posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);
        const int rc = posix_spawnp(&mPid, raw[0], &files, &attributes, raw.data(), environ);
        posix_spawnattr_destroy(&attributes);
        posix_spawn_file_actions_destroy(&files);
        if (rc != 0) ADD_FAILURE() << "cannot start " << raw[0] << ": " << rc;
        if (rc != 0) mPid = -1;
    }
    BackgroundRun(const BackgroundRun&) = delete;
    BackgroundRun& operator=(const BackgroundRun&) = delete;
    ~BackgroundRun() {
        if (mPid <= 0) return;
        if (mInner > 0) ::kill(mInner, SIGKILL);
        ::kill(mPid, SIGKILL);
        (void)::waitpid(mPid, nullptr, 0);
    }

    // Polls `ready` until it holds (true), the run ends or `limit` passes (false).
    bool waitFor(const std::function<bool()>& ready, std::chrono::seconds limit) {
        const auto end = std::chrono::steady_clock::now() + limit;
        while (std::chrono::steady_clock::now() < end) {
            if (ready()) return true;
            if (exited()) return false;
            std::this_thread::sleep_for(20ms);
        }
        return false;
    }

    // The exit status, or minus the signal that ended the run; the run is killed after `limit`.
    test::Result finish(std::chrono::seconds limit) {
        const auto end = std::chrono::steady_clock::now() + limit;
        while (!exited() && std::chrono::steady_clock::now() < end)
            std::this_thread::sleep_for(20ms);
        if (!exited()) {
            ADD_FAILURE() << "the run did not end within " << limit.count() << " s";
            ::kill(mPid, SIGKILL);
            (void)::waitpid(mPid, &mStatus, 0);
            mPid = -1;
        }
        test::Result r;
        r.status = WIFEXITED(mStatus) ? WEXITSTATUS(mStatus) : -WTERMSIG(mStatus);
        r.out = test::slurp(mOut);
        r.err = test::slurp(mErr);
        return r;
    }

    // Signals gazetrace: the process started, or the one behind the prefix (setInner).
    void signal(int signal) const {
        const pid_t target = mInner > 0 ? mInner : mPid;
        ASSERT_GT(target, 0);
        ASSERT_EQ(::kill(target, signal), 0);
    }
    // gazetrace's process when a prefix (xvfb-run) started it; killed too if the test fails.
    void setInner(pid_t inner) { mInner = inner; }
    [[nodiscard]] std::string err() const { return test::slurp(mErr); }

private:
    bool exited() {
        if (mPid <= 0) return true;
        if (::waitpid(mPid, &mStatus, WNOHANG) != mPid) return false;
        mPid = -1;
        return true;
    }

    std::filesystem::path mOut, mErr;
    pid_t mPid = -1, mInner = -1;
    int mStatus = 0;
};

// Every file under `dir` with its size and a hash of its bytes: what a folder held, to compare
// before and after a run.
std::map<std::string, std::string> contents(const std::filesystem::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
        const std::string name = std::filesystem::relative(e.path(), dir).string();
        if (!e.is_regular_file()) {
            files[name] = "folder";
            continue;
        }
        const std::string bytes = test::slurp(e.path());
        files[name] = std::to_string(bytes.size()) + " bytes, hash " +
                      std::to_string(std::hash<std::string>{}(bytes));
    }
    return files;
}

// Whether a file under `dir` that is not one of `before`, and whose name contains `part`, has
// some bytes in it: the run is writing, whatever it names its temporaries.
bool written(const std::filesystem::path& dir, const std::string& part,
             const std::map<std::string, std::string>& before = {}) {
    std::error_code ec;
    for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
         it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
        if (ec) return false;
        if (before.contains(std::filesystem::relative(it->path(), dir).string())) continue;
        if (it->path().filename().string().find(part) != std::string::npos &&
            it->is_regular_file(ec) && it->file_size(ec) > 0)
            return true;
    }
    return false;
}

void expectInterrupted(const test::Result& r, const std::string& command, int signal) {
    const std::string name = signal == SIGINT ? "SIGINT" : "SIGTERM";
    EXPECT_EQ(r.status, 128 + signal) << r.err;
    EXPECT_EQ(test::lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(command + ": interrupted (" + name + ")"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
}

// SIGINT in the middle of a folder of frames must leave none of them.
TEST(Signals, RenderInterruptedLeavesNoFramesAndKeepsWhatWasThere) {
    const auto dir = test::tempDir("signal_render");
    const auto work = dir / "work", logs = dir / "logs";
    std::filesystem::create_directories(work);
    std::filesystem::create_directories(logs);
    std::ofstream(work / "keep.png") << "an earlier image";
    const auto before = contents(work);
    BackgroundRun run(logs, {"-q", "render", "--scene", "builtin:cornell", "--method", "reference",
                             "--width", "48", "--height", "32", "--frames", "100000", "--cache",
                             (dir / "cache").string(), "--out", (work / "frames").string()});
    // Two frames on disk: the run is writing.
    ASSERT_TRUE(run.waitFor([&] { return written(work, "frame_0001"); }, 120s)) << run.err();
    run.signal(SIGINT);
    expectInterrupted(run.finish(60s), "render", SIGINT);
    EXPECT_EQ(contents(work), before); // no frames, no folder, no temporaries
}

// A clip and its truth stopped half way: the clip's temporary goes, the earlier clip stays.
TEST(Signals, EyesimTerminatedKeepsTheEarlierClipAndTruth) {
    const auto dir = test::tempDir("signal_eyesim");
    const auto work = dir / "work", logs = dir / "logs";
    std::filesystem::create_directories(work);
    std::filesystem::create_directories(logs);
    std::ofstream(work / "clip.mkv") << "an earlier clip";
    std::ofstream(work / "truth.csv") << "an earlier truth\n";
    const auto before = contents(work);
    BackgroundRun run(logs, {"eyesim", "--frames", "1000000", "--out", (work / "clip.mkv").string(),
                             "--truth", (work / "truth.csv").string()});
    // The clip's temporary has frames in it.
    ASSERT_TRUE(run.waitFor([&] { return written(work, "clip", before); }, 60s)) << run.err();
    run.signal(SIGTERM);
    expectInterrupted(run.finish(60s), "eyesim", SIGTERM);
    EXPECT_EQ(contents(work), before);
}

// The demo is live: SIGINT closes it as its window's close button does, and what it was asked
// to write is written whole.
TEST(Signals, DemoInterruptedEndsNormallyWithItsLogComplete) {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        GTEST_SKIP() << "xvfb-run is not installed";
    }
    const auto dir = test::tempDir("signal_demo");
    const auto log = dir / "frames.csv";
    // The shell between xvfb-run and gazetrace tells the test gazetrace's process id.
    const auto pidFile = dir / "pid";
    BackgroundRun run(dir,
                      {"demo", "--scene", "builtin:cornell", "--width", "160", "--height", "96",
                       "--gaze", "fixed:80,48", "--overlay", "off", "--json", "--log", log.string(),
                       "--cache", (dir / "cache").string()},
                      {"xvfb-run", "-a", "-s", "-screen 0 640x480x24", "sh", "-c",
                       "echo $$ > \"$0\"; exec \"$@\"", pidFile.string()});
    ASSERT_TRUE(run.waitFor([&] { return test::slurp(pidFile).ends_with("\n"); }, 60s));
    run.setInner(std::stoi(test::slurp(pidFile)));
    // The renderer is up; a few more seconds show some frames.
    ASSERT_TRUE(run.waitFor([&] { return run.err().find("device:") != std::string::npos; }, 120s))
        << run.err();
    std::this_thread::sleep_for(3s);
    run.signal(SIGINT);
    const test::Result r = run.finish(60s);
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json summary = nlohmann::json::parse(r.out);
    // One row per frame the demo rendered under the header: the log was written whole.
    std::istringstream rows(test::slurp(log));
    std::string header, row;
    ASSERT_TRUE(std::getline(rows, header));
    EXPECT_EQ(header.rfind("frame,t_ms,", 0), 0u) << header;
    int n = 0;
    while (std::getline(rows, row))
        ++n;
    EXPECT_EQ(n, summary["frames"].get<int>());
    EXPECT_FALSE(std::filesystem::exists(dir / "frames.csv.tmp")) << "a temporary was left";
}

} // namespace
} // namespace gt
