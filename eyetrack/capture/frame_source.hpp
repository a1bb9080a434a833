#pragma once
// Where frames come from. One interface for cameras, recordings and synthetic eyes:
//   v4l2:/dev/videoN[?width=..&height=..&fps=..&format=grey|yuyv|mjpeg]   a V4L2 camera
//   video:FILE        a video file (OpenCV VideoCapture; timestamps from the file)
//   images:DIR        sorted image files in a folder (timestamps from --fps, default 30)
//   synthetic:SEED[?preset=clean|hard&frames=N&size=WxH&fps=F]   gazetrace's synthetic eye
// next() returns frames in order and nullopt at the end of a finite source. A source that fails
// (a missing or truncated file, an unplugged camera that does not come back) throws CaptureError
// naming itself, after every good frame has been delivered.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "capture/frame.hpp"

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

// "scheme:rest?key=value&..." split into its parts.
struct SourceSpec {
    std::string scheme;
    std::string target;
    std::map<std::string, std::string> options;
};
[[nodiscard]] SourceSpec parseSourceSpec(const std::string& spec); // throws CaptureError

[[nodiscard]] std::unique_ptr<FrameSource> openFrameSource(const std::string& spec);

// Converts any image OpenCV decodes to the 8-bit grey frames the tracker works on.
[[nodiscard]] cv::Mat toGrey(const cv::Mat& image);

} // namespace gt::eyetrack
