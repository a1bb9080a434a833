#pragma once
// The journal of one participant's run: JSON lines, appended, each line written with one write()
// and fsync'd before the next trial starts, so a run that is interrupted (a crash, SIGINT, a
// pulled plug) keeps every trial answered so far and can resume. The first line ("start") holds
// the design, the seed, the participant's code and the run's id; then one line per ended trial
// ("trial"), per repeated trial ("repeat": why), per resumption ("resume"), and "end".
// A torn last line (no newline: the write was cut) is dropped when the journal is reopened: the
// file is cut back to its last newline, so the next line appended starts on a line of its own.
//
// The journal is the one file gazetrace appends to instead of replacing (io/atomic_write.hpp):
// a run that is killed between two trials must leave every trial before it on disk, and
// rewriting the whole file through a temporary after every trial would cost a copy per trial
// for nothing a line written whole with O_APPEND and fsync'd does not already give. The rules
// for the path follow io's otherwise:
//  - a missing file is created (0644), and its folder fsync'd so the new name survives a crash;
//  - only a regular file is appended to: a FIFO, a socket, a device or a folder is refused,
//    checked with fstat() on the open descriptor (a name swapped after a check cannot pass);
//  - a symlink is refused (O_NOFOLLOW): appending through it would write into whatever it names;
//  - an existing file must read as a journal (every complete line a JSON object) before
//    anything is cut or appended, so a wrongly named file is refused, not truncated;
//  - the file is locked (flock, exclusive) while open: two runs never append to one journal.
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gt::study {

class JournalError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// What one interval measured.
struct IntervalRecord {
    std::string shown; // "condition", "comparison", a ramp step "condition@1.4"
    uint32_t frames = 0;
    uint32_t expectedFrames = 0; // intervalMs at the refresh rate
    uint32_t droppedFrames = 0;  // frames longer than 1.5 refresh periods
    double latencyMsMean = 0.0;
    double latencyMsMax = 0.0;
    uint32_t gazeLostFrames = 0;
    // Gaze samples: [ms since the interval began, x deg, y deg]; lost frames are left out.
    std::vector<std::array<double, 3>> gaze;
};

struct TrialRecord {
    uint32_t trial = 0; // index in the plan
    bool practice = false;
    std::string condition;
    std::string parameter; // the varied parameter's name
    uint32_t scene = 0;    // index into the design's scenes
    double level = 0.0;
    bool catchTrial = false;
    bool conditionFirst = true;
    std::string response; // "first", "second", "same", "yes", "no", "up", "down", "accept"
    bool positive = false;
    double reactionMs = 0.0; // from the end of the last interval to the answer
    std::vector<IntervalRecord> intervals;
    std::vector<std::string> flags;    // "dropped_frame", "gaze_lost", "max_repeats"
    std::optional<double> sliderLevel; // Slider: the recorded level
};

class Journal {
public:
    // Opens `path` for appending (created when missing), after reading what it holds. Throws
    // JournalError naming the file (not a regular file, unreadable, a line that is not JSON).
    explicit Journal(std::filesystem::path path);
    ~Journal();
    Journal(const Journal&) = delete;
    Journal& operator=(const Journal&) = delete;

    // The lines already there when it was opened (a torn last line dropped), and whether one was.
    [[nodiscard]] const std::vector<nlohmann::json>& existing() const noexcept;
    [[nodiscard]] bool droppedTornLine() const noexcept { return mDroppedTorn; }
    // Appends one line, written whole and fsync'd. Throws JournalError (a full disk) naming the
    // file; the journal is then left as it was before the call.
    void append(const nlohmann::json& line);
    [[nodiscard]] const std::filesystem::path& path() const noexcept;

private:
    std::filesystem::path mPath;
    std::vector<nlohmann::json> mExisting;
    int mFd = -1;
    bool mDroppedTorn = false;
};

[[nodiscard]] nlohmann::json toJson(const TrialRecord& record);
[[nodiscard]] TrialRecord trialFromJson(const nlohmann::json& line); // throws JournalError

// Reads a journal without opening it for writing (study analyse); a torn last line is left out,
// a line that is not a JSON object in the middle is a JournalError naming the file and the line.
[[nodiscard]] std::vector<nlohmann::json> readJournal(const std::filesystem::path& path);

// The journal's fault seam for tests, which is io's write-fault seam (io::testing::failWrites):
// while set, append() fails with `error` (e.g. ENOSPC) after `okBytes` bytes of the line, and so
// do io's writers. GAZETRACE_WRITE_FAULT=enospc in the environment sets it for a whole process.
// journalSyncs() counts the fsync() calls append() made.
namespace testing {
void failJournalWrites(int error, std::size_t okBytes = 0);
void clearJournalFaults();
[[nodiscard]] uint64_t journalSyncs();
} // namespace testing

} // namespace gt::study
