#pragma once
// Where frames come from. One interface for cameras (V4L2), recordings (a video file, a folder of
// images) and synthetic eyes, opened from a FrameSourceConfig (capture/frame_source_config.hpp).
// next() returns frames in order and nullopt at the end of a finite source. A source that fails
// (a missing or truncated file, an unplugged camera that does not come back) throws CaptureError
// naming itself, after every good frame has been delivered.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "capture/frame.hpp"
#include "capture/frame_source_config.hpp"

namespace gt::eyetrack {

class FrameSource {
public:
    virtual ~FrameSource() = default;
    [[nodiscard]] virtual std::optional<Frame> next() = 0;
    [[nodiscard]] virtual std::string describe() const = 0;
    // Frames lost between delivered ones (sequence gaps).
    [[nodiscard]] virtual std::uint64_t droppedFrames() const { return 0; }
    // True when timestamps are on this machine's monotonic clock (live cameras), so latency can
    // be measured from them.
    [[nodiscard]] virtual bool liveClock() const { return false; }
};

// Throws CaptureError when the source cannot be opened.
[[nodiscard]] std::unique_ptr<FrameSource> openFrameSource(const FrameSourceConfig& config);

// Converts any image OpenCV decodes to the 8-bit grey frames the tracker works on.
[[nodiscard]] cv::Mat toGrey(const cv::Mat& image);

} // namespace gt::eyetrack
