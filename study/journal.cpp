#include "journal.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <span>
#include <string_view>
#include <utility>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "atomic_write.hpp"
#include "file_kind.hpp"
#include "input_file.hpp"
#include "limits.hpp"

namespace gt::study {

namespace {

using nlohmann::json;

// A journal holds a run's trials with their gaze samples: a few kilobytes a trial, so the text
// table limit (256 MiB) is tens of thousands of trials.
constexpr uint64_t kMaxJournalBytes = io::limits::kTextTableBytes;

// fsync() calls append() made, for the tests (testing::journalSyncs).
std::atomic<uint64_t> gSyncs{0};

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what, int error = 0) {
    throw JournalError(path.string() + ": " + what +
                       (error != 0 ? std::string(" (") + std::strerror(error) + ")" : ""));
}

struct Parsed {
    std::vector<json> lines;
    std::size_t completeBytes = 0; // up to and with the last newline
};

// Every complete line a JSON object; what follows the last newline (a cut write) is left out.
Parsed parseLines(const std::filesystem::path& path, std::string_view text) {
    Parsed parsed;
    std::size_t begin = 0;
    std::size_t number = 1;
    for (std::size_t end = text.find('\n'); end != std::string_view::npos;
         begin = end + 1, end = text.find('\n', begin), ++number) {
        const std::string_view line = text.substr(begin, end - begin);
        json j = json::parse(line, nullptr, false);
        if (j.is_discarded()) {
            fail(path, "line " + std::to_string(number) + " is not JSON");
        }
        if (!j.is_object() || !j.contains("type") || !j["type"].is_string()) {
            fail(path, "line " + std::to_string(number) +
                           " is not a journal line (a JSON object with a \"type\")");
        }
        parsed.lines.push_back(std::move(j));
        parsed.completeBytes = end + 1;
    }
    return parsed;
}

// The whole file through `fd` (opened O_RDWR: the bytes checked are the bytes appended to).
std::string readAll(const std::filesystem::path& path, int fd, uint64_t size) {
    std::string text(static_cast<std::size_t>(size), '\0');
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t n =
            ::pread(fd, text.data() + done, text.size() - done, static_cast<off_t>(done));
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n < 0) {
            fail(path, "cannot read it", errno);
        }
        if (n == 0) {
            break;
        }
        done += static_cast<std::size_t>(n);
    }
    text.resize(done);
    return text;
}

void syncFolderOf(const std::filesystem::path& path) {
    const std::filesystem::path folder =
        path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) {
        return; // the file itself is synced with every line; the name is best effort
    }
    (void)::fsync(fd);
    ::close(fd);
}

} // namespace

Journal::Journal(std::filesystem::path path) : mPath(std::move(path)) {
    struct stat before {};
    const bool existed = ::lstat(mPath.c_str(), &before) == 0;
    mFd =
        ::open(mPath.c_str(),
               O_RDWR | O_APPEND | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY, 0644);
    if (mFd < 0) {
        const int e = errno;
        if (e == ELOOP) {
            fail(mPath, "a symlink; a journal is appended in place, never through a link");
        }
        fail(mPath, "cannot open the journal", e);
    }
    try {
        struct stat st {};
        if (::fstat(mFd, &st) != 0) {
            fail(mPath, "cannot read its status", errno);
        }
        if (!S_ISREG(st.st_mode)) {
            fail(mPath, io::fileKind(st.st_mode) + ", not a regular file");
        }
        if (::flock(mFd, LOCK_EX | LOCK_NB) != 0) {
            fail(mPath, "another run has this journal open", errno);
        }
        const auto size = static_cast<uint64_t>(st.st_size);
        if (size > kMaxJournalBytes) {
            fail(mPath, io::describeBytes(size) + " is over the " +
                            io::describeBytes(kMaxJournalBytes) + " limit for a journal");
        }
        const std::string text = readAll(mPath, mFd, size);
        Parsed parsed = parseLines(mPath, text);
        if (parsed.completeBytes < text.size()) {
            // A line cut by a crash: gone, so the next append starts on a line of its own.
            if (::ftruncate(mFd, static_cast<off_t>(parsed.completeBytes)) != 0) {
                fail(mPath, "cannot drop its torn last line", errno);
            }
            if (::fsync(mFd) != 0) {
                fail(mPath, "cannot sync it", errno);
            }
            mDroppedTorn = true;
        }
        mExisting = std::move(parsed.lines);
        if (!existed) {
            syncFolderOf(mPath);
        }
    } catch (...) {
        ::close(mFd);
        throw;
    }
}

Journal::~Journal() {
    if (mFd >= 0) {
        ::close(mFd);
    }
}

const std::vector<nlohmann::json>& Journal::existing() const noexcept {
    return mExisting;
}

const std::filesystem::path& Journal::path() const noexcept {
    return mPath;
}

void Journal::append(const nlohmann::json& line) {
    // dump() escapes control characters in strings: the text has no newline of its own.
    const std::string text = line.dump() + "\n";
    struct stat st {};
    if (::fstat(mFd, &st) != 0) {
        fail(mPath, "cannot append to the journal", errno);
    }
    const off_t before = st.st_size;
    int error = io::writeAll(mFd, std::as_bytes(std::span(text.data(), text.size())));
    if (error == 0 && ::fsync(mFd) != 0) {
        error = errno;
    }
    if (error == 0) {
        gSyncs.fetch_add(1);
        return;
    }
    // No partial line may stay: the journal is left as it was before the call.
    (void)::ftruncate(mFd, before);
    (void)::fsync(mFd);
    fail(mPath, "cannot append to the journal", error);
}

nlohmann::json toJson(const TrialRecord& r) {
    json intervals = json::array();
    for (const IntervalRecord& i : r.intervals) {
        intervals.push_back({{"shown", i.shown},
                             {"frames", i.frames},
                             {"expected_frames", i.expectedFrames},
                             {"dropped_frames", i.droppedFrames},
                             {"latency_ms_mean", i.latencyMsMean},
                             {"latency_ms_max", i.latencyMsMax},
                             {"gaze_lost_frames", i.gazeLostFrames},
                             {"gaze", i.gaze}});
    }
    json j{{"type", "trial"},
           {"trial", r.trial},
           {"practice", r.practice},
           {"condition", r.condition},
           {"parameter", r.parameter},
           {"scene", r.scene},
           {"level", r.level},
           {"catch", r.catchTrial},
           {"condition_first", r.conditionFirst},
           {"response", r.response},
           {"positive", r.positive},
           {"reaction_ms", r.reactionMs},
           {"intervals", intervals},
           {"flags", r.flags}};
    if (r.sliderLevel) {
        j["slider_level"] = *r.sliderLevel;
    }
    return j;
}

TrialRecord trialFromJson(const nlohmann::json& line) {
    try {
        if (line.value("type", "") != "trial") {
            throw JournalError("not a trial line");
        }
        TrialRecord r;
        r.trial = line.at("trial").get<uint32_t>();
        r.practice = line.at("practice").get<bool>();
        r.condition = line.at("condition").get<std::string>();
        r.parameter = line.at("parameter").get<std::string>();
        r.scene = line.value("scene", 0U);
        r.level = line.at("level").get<double>();
        r.catchTrial = line.at("catch").get<bool>();
        r.conditionFirst = line.at("condition_first").get<bool>();
        r.response = line.at("response").get<std::string>();
        r.positive = line.at("positive").get<bool>();
        r.reactionMs = line.at("reaction_ms").get<double>();
        for (const json& i : line.at("intervals")) {
            IntervalRecord ir;
            ir.shown = i.at("shown").get<std::string>();
            ir.frames = i.at("frames").get<uint32_t>();
            ir.expectedFrames = i.at("expected_frames").get<uint32_t>();
            ir.droppedFrames = i.at("dropped_frames").get<uint32_t>();
            ir.latencyMsMean = i.at("latency_ms_mean").get<double>();
            ir.latencyMsMax = i.at("latency_ms_max").get<double>();
            ir.gazeLostFrames = i.at("gaze_lost_frames").get<uint32_t>();
            ir.gaze = i.at("gaze").get<std::vector<std::array<double, 3>>>();
            r.intervals.push_back(std::move(ir));
        }
        r.flags = line.at("flags").get<std::vector<std::string>>();
        if (line.contains("slider_level")) {
            r.sliderLevel = line["slider_level"].get<double>();
        }
        return r;
    } catch (const JournalError& e) {
        throw JournalError(std::string("a trial line: ") + e.what());
    } catch (const nlohmann::json::exception& e) {
        // nlohmann's text starts "[json.exception.out_of_range.403] key 'level' not found".
        std::string what = e.what();
        const auto close = what.find("] ");
        throw JournalError("a trial line: " +
                           (close == std::string::npos ? what : what.substr(close + 2)));
    }
}

std::vector<nlohmann::json> readJournal(const std::filesystem::path& path) {
    std::string text;
    try {
        text = io::readInputFile(path, kMaxJournalBytes);
    } catch (const io::InputError& e) {
        throw JournalError(e.what());
    }
    return parseLines(path, text).lines;
}

namespace testing {

void failJournalWrites(int error, std::size_t okBytes) {
    io::testing::failWrites(error, okBytes);
}

void clearJournalFaults() {
    io::testing::clearWriteFaults();
}

uint64_t journalSyncs() {
    return gSyncs.load();
}

} // namespace testing

} // namespace gt::study
