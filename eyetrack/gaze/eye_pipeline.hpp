#pragma once
// One eye's path from camera frames to gaze samples: source -> detector -> mapper -> filter.
// The renderer's tracker thread (gaze/gaze_tracker.hpp) and `gazetrace track` both drive this
// one object, so what is measured offline is what the renderer gets. The mapper is optional: a
// pipeline without calibration still detects pupils (track's scoring, contact sheets).
#include <memory>
#include <optional>

#include "capture/frame_source.hpp"
#include "gaze/gaze_filter.hpp"
#include "gaze/gaze_mapper.hpp"
#include "pupil/pupil_detector.hpp"

namespace gt::eyetrack {

struct EyeStep {
    PupilResult pupil;
    std::optional<cv::Point2d> screen; // mapped gaze before filtering (a mapper, a pupil)
    std::optional<GazeSample> sample;  // filtered gaze (with a mapper)
};

class EyePipeline {
public:
    // source may be null (frames are then pushed to process() by the caller: one camera that
    // sees both eyes feeds two pipelines); mapper may be null. The filter's display is the
    // mapper's.
    EyePipeline(std::unique_ptr<FrameSource> source, std::unique_ptr<PupilDetector> detector,
                std::unique_ptr<GazeMapper> mapper, GazeFilterConfig filter = {});

    // The next frame, nullopt at the end (throws CaptureError as the source does).
    [[nodiscard]] std::optional<Frame> grab() { return mSource ? mSource->next() : std::nullopt; }
    [[nodiscard]] EyeStep process(const Frame& frame);

    // Only with a source.
    [[nodiscard]] FrameSource& source() noexcept { return *mSource; }
    [[nodiscard]] const FrameSource& source() const noexcept { return *mSource; }
    [[nodiscard]] PupilDetector& detector() noexcept { return *mDetector; }
    [[nodiscard]] GazeMapper* mapper() noexcept { return mMapper.get(); }
    [[nodiscard]] const GazeMapper* mapper() const noexcept { return mMapper.get(); }

private:
    std::unique_ptr<FrameSource> mSource;
    std::unique_ptr<PupilDetector> mDetector;
    std::unique_ptr<GazeMapper> mMapper;
    std::optional<GazeFilter> mFilter;
};

} // namespace gt::eyetrack
