#pragma once
// What every `bench` suite measures the same way: the median of a series, and the unmeasured
// frames before it.
#include <algorithm>
#include <vector>

namespace gt::app {

// Unmeasured frames before each measured series, until this much wall time has passed (at
// least one frame): a GPU left idle while the CPU built a table clocks down, and its first
// short frames measured up to 5x slower than the same frames once busy (H100: TAA 0.31 ms
// cold, 0.06 ms warm). On lavapipe this is one frame.
inline constexpr double kWarmUpMs = 500.0;

// Runs `frame` (returning its wall milliseconds) until kWarmUpMs have passed.
template <typename Frame> void warmUp(Frame&& frame) {
    double ms = 0.0;
    do {
        ms += frame();
    } while (ms < kWarmUpMs);
}

// The median of `v`; 0 for an empty series.
[[nodiscard]] inline double median(std::vector<double> v) {
    if (v.empty()) {
        return 0.0;
    }
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

} // namespace gt::app
