#pragma once
// The journal of one participant's run: JSON lines, appended, each line written with one write()
// and fsync'd before the next trial starts, so a run that is interrupted (a crash, SIGINT, a
// pulled plug) keeps every trial answered so far and can resume. The first line ("start") holds
// the design, the seed, the participant's code and the run's id; then one line per ended trial
// ("trial"), per repeated trial ("repeat": why), per resumption ("resume"), and "end".
// A torn last line (no newline: the write was cut) is dropped when the journal is reopened.
#include <array>
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

    // The lines already there when it was opened (a torn last line dropped).
    [[nodiscard]] const std::vector<nlohmann::json>& existing() const noexcept;
    // Appends one line, written whole and fsync'd. Throws JournalError (a full disk) naming the
    // file; the journal is then left as it was before the call.
    void append(const nlohmann::json& line);
    [[nodiscard]] const std::filesystem::path& path() const noexcept;

private:
    std::filesystem::path mPath;
    std::vector<nlohmann::json> mExisting;
    int mFd = -1;
};

[[nodiscard]] nlohmann::json toJson(const TrialRecord& record);
[[nodiscard]] TrialRecord trialFromJson(const nlohmann::json& line); // throws JournalError

// Reads a journal without opening it for writing (study analyse).
[[nodiscard]] std::vector<nlohmann::json> readJournal(const std::filesystem::path& path);

} // namespace gt::study
