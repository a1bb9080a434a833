#pragma once
// One eye's region of a camera that sees both eyes: crops every frame of the wrapped source to a
// rectangle (checked against the first frame's size). Used by `calibrate --regions` on a
// recording; `track --regions` splits each frame of one source itself, so a live camera is opened
// once.
#include <memory>
#include <string>
#include <utility>

#include <opencv2/core/types.hpp>

#include "capture/frame_source.hpp"

namespace gt::eyetrack {

// Crops a frame (a copy); throws CaptureError when the region does not fit the frame.
[[nodiscard]] Frame cropFrame(const Frame& frame, const cv::Rect& region);

class RegionSource final : public FrameSource {
public:
    RegionSource(std::unique_ptr<FrameSource> source, cv::Rect region, std::string name)
        : mSource(std::move(source)), mRegion(region), mName(std::move(name)) {}
    std::optional<Frame> next() override {
        auto f = mSource->next();
        if (!f) {
            return std::nullopt;
        }
        return cropFrame(*f, mRegion);
    }
    std::string describe() const override { return mSource->describe() + " (" + mName + ")"; }
    std::uint64_t droppedFrames() const override { return mSource->droppedFrames(); }
    bool liveClock() const override { return mSource->liveClock(); }

private:
    std::unique_ptr<FrameSource> mSource;
    cv::Rect mRegion;
    std::string mName;
};

} // namespace gt::eyetrack
