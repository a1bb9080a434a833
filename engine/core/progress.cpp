#include "core/progress.hpp"

#include <algorithm>
#include <cstdio>

#include "core/log.hpp"

namespace gt::progress {

namespace {
double steadySeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}
} // namespace

Step::Step(std::string what, std::uint64_t total, Clock clock)
    : mWhat(std::move(what)), mTotal(std::max<std::uint64_t>(total, 1)),
      mClock(clock ? std::move(clock) : Clock(steadySeconds)), mStart(mClock()),
      mNextLine(mStart + kQuietSeconds) {}

std::optional<std::string> Step::advance(std::uint64_t count) {
    return report(mDone.fetch_add(count, std::memory_order_relaxed) + count);
}

std::optional<std::string> Step::reach(double fraction) {
    const double f = std::clamp(fraction, 0.0, 1.0);
    const auto done = static_cast<std::uint64_t>(f * static_cast<double>(mTotal));
    mDone.store(done, std::memory_order_relaxed);
    return report(done);
}

std::optional<std::string> Step::report(std::uint64_t done) {
    const double now = mClock();
    if (now < mNextLine.load(std::memory_order_relaxed)) {
        return std::nullopt;
    }
    // One thread prints; the others carry on rather than wait.
    const std::unique_lock lock(mPrinting, std::try_to_lock);
    if (!lock.owns_lock() || now < mNextLine.load(std::memory_order_relaxed)) {
        return std::nullopt;
    }
    mNextLine.store(now + kEverySeconds, std::memory_order_relaxed);
    done = std::min(done, mTotal);
    char percent[16];
    std::snprintf(
        percent, sizeof percent, "%d %%",
        static_cast<int>(100.0 * static_cast<double>(done) / static_cast<double>(mTotal)));
    const std::string line = mWhat + " " + percent + " (" + std::to_string(done) + "/" +
                             std::to_string(mTotal) + ", " +
                             std::to_string(static_cast<int>(now - mStart)) + " s)";
    log::info(line);
    return line;
}

} // namespace gt::progress
