#include "capture/region_source.hpp"

#include <cstdio>

#include "error.hpp"

namespace gt::eyetrack {

std::pair<cv::Rect, cv::Rect> parseEyeRegions(const std::string& text) {
    int v[8] = {};
    char extra = 0;
    if (std::sscanf(text.c_str(), "%d,%d,%d,%d;%d,%d,%d,%d%c", &v[0], &v[1], &v[2], &v[3], &v[4],
                    &v[5], &v[6], &v[7], &extra) != 8) {
        throw CaptureError("--regions " + text +
                           ": expected X,Y,W,H;X,Y,W,H (left eye; right eye)");
    }
    const cv::Rect l(v[0], v[1], v[2], v[3]), r(v[4], v[5], v[6], v[7]);
    for (const cv::Rect& q : {l, r}) {
        if (q.x < 0 || q.y < 0 || q.width < 32 || q.height < 24) {
            throw CaptureError("--regions " + text +
                               ": each region must start at >= 0 and be at least 32x24");
        }
    }
    return {l, r};
}

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
