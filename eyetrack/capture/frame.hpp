#pragma once
// One camera frame as every frame source delivers it: 8-bit greyscale, a sequence number that
// counts from 0 (gaps mean dropped frames) and a monotonic timestamp in milliseconds.
#include <chrono>
#include <cstdint>

#include <opencv2/core.hpp>

namespace gt::eyetrack {

struct Frame {
    cv::Mat grey; // CV_8UC1, owns its pixels (sources never hand out driver memory)
    std::uint64_t sequence = 0;
    double tMs = 0.0; // monotonic capture time (file time for recordings)
    // When the source handed the frame over, for latency measurements on recordings whose
    // timestamps are not on this machine's clock.
    std::chrono::steady_clock::time_point arrival{};
};

} // namespace gt::eyetrack
