#include "capture/region_source.hpp"

#include "error.hpp"

namespace gt::eyetrack {

Frame cropFrame(const Frame& frame, const cv::Rect& region) {
    if ((region & cv::Rect(0, 0, frame.grey.cols, frame.grey.rows)) != region) {
        throw CaptureError(
            "eye region " + std::to_string(region.width) + "x" + std::to_string(region.height) +
            "+" + std::to_string(region.x) + "+" + std::to_string(region.y) + " does not fit the " +
            std::to_string(frame.grey.cols) + "x" + std::to_string(frame.grey.rows) + " frame");
    }
    Frame out;
    out.grey = frame.grey(region).clone();
    out.sequence = frame.sequence;
    out.tMs = frame.tMs;
    out.arrival = frame.arrival;
    return out;
}

} // namespace gt::eyetrack
