#pragma once
// A long step's progress on stderr, through the log (so -q silences it, and stdout stays the
// --json's). A step that ends within kQuietSeconds prints nothing, so short runs and the tests
// that compare their output see no difference; after that, at most one line every
// kEverySeconds: "render: building the k-NN table 41 % (5400/13120)".
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>

namespace gt::progress {

inline constexpr double kQuietSeconds = 2.0;
inline constexpr double kEverySeconds = 2.0;

class Step {
public:
    // Seconds since some fixed point; steady_clock unless a test gives its own.
    using Clock = std::function<double()>;

    Step(std::string what, std::uint64_t total, Clock clock = {});
    Step(const Step&) = delete;
    Step& operator=(const Step&) = delete;

    // `count` more of `total` done; safe from several threads at once (a parallel loop's rows).
    // Returns the line it printed, if one was due.
    std::optional<std::string> advance(std::uint64_t count = 1);
    // Done up to `fraction` of the whole (0..1), for work that reports a fraction.
    std::optional<std::string> reach(double fraction);

private:
    std::optional<std::string> report(std::uint64_t done);

    std::string mWhat;
    std::uint64_t mTotal;
    Clock mClock;
    double mStart;
    std::atomic<std::uint64_t> mDone{0};
    std::atomic<double> mNextLine;
    std::mutex mPrinting;
};

} // namespace gt::progress
