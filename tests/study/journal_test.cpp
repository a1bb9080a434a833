#include <gtest/gtest.h>

#include "journal.hpp"

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace gt::study {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class JournalTest : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = fs::temp_directory_path() /
               ("gt-journal-" + std::to_string(::getpid()) + "-" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(mDir);
        fs::create_directories(mDir);
    }
    void TearDown() override {
        testing::clearJournalFaults();
        fs::remove_all(mDir);
    }
    [[nodiscard]] std::string text(const fs::path& p) const {
        std::ifstream in(p, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
    fs::path mDir;
};

json trialLine(uint32_t i) {
    return json{{"type", "trial"}, {"trial", i}};
}

std::string errorOf(const fs::path& p) {
    try {
        Journal j(p);
    } catch (const JournalError& e) {
        return e.what();
    }
    return "";
}

TEST_F(JournalTest, AppendsLinesAndReadsThemBackOnReopen) {
    const fs::path p = mDir / "p01.jsonl";
    {
        Journal j(p);
        EXPECT_TRUE(j.existing().empty());
        j.append({{"type", "start"}, {"note", "two\nlines"}});
        j.append(trialLine(0));
    }
    EXPECT_EQ(text(p),
              "{\"note\":\"two\\nlines\",\"type\":\"start\"}\n{\"trial\":0,\"type\":\"trial\"}\n");
    Journal again(p);
    ASSERT_EQ(again.existing().size(), 2u);
    EXPECT_EQ(again.existing()[1], trialLine(0));
    EXPECT_FALSE(again.droppedTornLine());
    EXPECT_EQ(readJournal(p), again.existing());
}

TEST_F(JournalTest, TornLastLineIsDroppedAndTheFileCutBackToItsLastNewline) {
    const fs::path p = mDir / "torn.jsonl";
    const std::string whole = "{\"type\":\"start\"}\n{\"trial\":0,\"type\":\"trial\"}\n";
    std::ofstream(p, std::ios::binary) << whole << "{\"trial\":1,\"type\":\"tr";
    EXPECT_EQ(readJournal(p).size(), 2u); // reading alone leaves the file as it is
    {
        Journal j(p);
        EXPECT_TRUE(j.droppedTornLine());
        ASSERT_EQ(j.existing().size(), 2u);
        EXPECT_EQ(text(p), whole);
        j.append(trialLine(1));
    }
    const auto lines = readJournal(p);
    ASSERT_EQ(lines.size(), 3u);
    EXPECT_EQ(lines[2], trialLine(1));
}

TEST_F(JournalTest, LineThatIsNotJsonInTheMiddleNamesTheFileAndTheLine) {
    const fs::path p = mDir / "bad.jsonl";
    std::ofstream(p) << "{\"type\":\"start\"}\n{\"type\":\"tri\n{\"type\":\"end\"}\n";
    EXPECT_EQ(errorOf(p), p.string() + ": line 2 is not JSON");
    // Refused, not cut: a file that is not a journal keeps every byte.
    EXPECT_EQ(text(p), "{\"type\":\"start\"}\n{\"type\":\"tri\n{\"type\":\"end\"}\n");
    std::ofstream(p) << "[1, 2]\n";
    EXPECT_EQ(errorOf(p),
              p.string() + ": line 1 is not a journal line (a JSON object with a \"type\")");
}

TEST_F(JournalTest, RefusesWhatIsNotARegularFile) {
    EXPECT_EQ(errorOf(mDir), mDir.string() + ": cannot open the journal (Is a directory)");
    const fs::path fifo = mDir / "fifo";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_EQ(errorOf(fifo), fifo.string() + ": a FIFO, not a regular file");
    const fs::path link = mDir / "null.jsonl";
    fs::create_symlink("/dev/null", link);
    EXPECT_EQ(errorOf(link).rfind(link.string() + ": a symlink", 0), 0u);
    const fs::path target = mDir / "real.jsonl";
    std::ofstream(target) << "{\"type\":\"start\"}\n";
    fs::create_symlink(target, mDir / "link.jsonl");
    EXPECT_NE(errorOf(mDir / "link.jsonl"), "");
}

TEST_F(JournalTest, TwoRunsNeverAppendToOneJournal) {
    const fs::path p = mDir / "p.jsonl";
    Journal first(p);
    EXPECT_EQ(errorOf(p).rfind(p.string() + ": another run has this journal open", 0), 0u);
}

TEST_F(JournalTest, FailedAppendLeavesNoPartialLine) {
    const fs::path p = mDir / "full.jsonl";
    Journal j(p);
    j.append(trialLine(0));
    const std::string before = text(p);
    testing::failJournalWrites(ENOSPC, 7);
    try {
        j.append(trialLine(1));
        ADD_FAILURE() << "no error";
    } catch (const JournalError& e) {
        EXPECT_EQ(std::string(e.what()),
                  p.string() + ": cannot append to the journal (No space left on device)");
    }
    EXPECT_EQ(text(p), before);
    testing::clearJournalFaults();
    j.append(trialLine(1));
    EXPECT_EQ(readJournal(p).size(), 2u);
}

TEST_F(JournalTest, EveryLineIsOnDiskBeforeAppendReturns) {
    const fs::path p = mDir / "killed.jsonl";
    const uint64_t syncs = testing::journalSyncs();
    {
        Journal j(p);
        for (uint32_t i = 0; i < 3; ++i)
            j.append(trialLine(i));
    }
    EXPECT_EQ(testing::journalSyncs() - syncs, 3u); // one fsync per line
    fs::remove(p);
    // A run killed (no destructor, no exit handler) after N appends leaves N lines.
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        Journal j(p);
        for (uint32_t i = 0; i < 5; ++i)
            j.append(trialLine(i));
        ::raise(SIGKILL);
        ::_exit(0);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status));
    const auto lines = readJournal(p);
    ASSERT_EQ(lines.size(), 5u);
    EXPECT_EQ(lines[4], trialLine(4));
}

TEST_F(JournalTest, TrialRecordRoundTrips) {
    TrialRecord r;
    r.trial = 7;
    r.practice = true;
    r.condition = "scale";
    r.parameter = "scale";
    r.scene = 1;
    r.level = 1.7;
    r.catchTrial = true;
    r.conditionFirst = false;
    r.response = "second";
    r.positive = true;
    r.reactionMs = 412.5;
    r.flags = {"dropped_frame"};
    r.sliderLevel = 2.1;
    IntervalRecord i;
    i.shown = "condition";
    i.frames = 59;
    i.expectedFrames = 60;
    i.droppedFrames = 1;
    i.latencyMsMean = 11.0;
    i.latencyMsMax = 14.0;
    i.gazeLostFrames = 2;
    i.gaze = {{0.0, 0.5, -0.25}, {16.7, 0.4, -0.2}};
    r.intervals = {i};
    const json j = toJson(r);
    EXPECT_EQ(j["type"], "trial");
    EXPECT_EQ(toJson(trialFromJson(j)), j);
    json missing = j;
    missing.erase("level");
    try {
        (void)trialFromJson(missing);
        ADD_FAILURE() << "no error";
    } catch (const JournalError& e) {
        EXPECT_EQ(std::string(e.what()), "a trial line: key 'level' not found");
    }
}

} // namespace
} // namespace gt::study
