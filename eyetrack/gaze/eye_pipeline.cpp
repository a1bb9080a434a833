#include "gaze/eye_pipeline.hpp"

#include "error.hpp"

namespace gt::eyetrack {

EyePipeline::EyePipeline(std::unique_ptr<FrameSource> source,
                         std::unique_ptr<PupilDetector> detector,
                         std::unique_ptr<GazeMapper> mapper, GazeFilterConfig filter)
    : mSource(std::move(source)), mDetector(std::move(detector)), mMapper(std::move(mapper)) {
    if (!mDetector) {
        throw EyetrackError("eye pipeline: a detector is needed");
    }
    if (mMapper) {
        filter.display = mMapper->display();
        mFilter.emplace(filter);
    }
}

EyeStep EyePipeline::process(const Frame& frame) {
    EyeStep step;
    step.pupil = mDetector->detect(frame.grey, frame.tMs);
    if (!mMapper) {
        return step;
    }
    if (step.pupil.found) {
        step.screen = mMapper->map(step.pupil, frame.tMs);
    }
    step.sample = mFilter->process(frame.tMs, step.screen, step.pupil.confidence);
    return step;
}

} // namespace gt::eyetrack
