#include <opencv2/core/utility.hpp>

#include "capture/frame_source.hpp"
#include "eye_commands.hpp"
#include "gaze/recording_calibration.hpp"
#include "pupil/pupil_detector.hpp"

namespace gt::app {

nlohmann::json runCalibrate(const CalibrateOptions& o) {
    cv::setNumThreads(1);
    const auto schedule = eyetrack::TargetSchedule::load(o.targets);
    auto source = eyetrack::openFrameSource(o.source);
    const auto detector = eyetrack::makePupilDetector(o.detector);
    const auto r =
        eyetrack::calibrateFromRecording(*source, schedule, o.display, o.settleMs, *detector);
    r.calibration.save(o.out);
    return {{"frames", r.frames},
            {"calibration_targets", r.calibrationTargets},
            {"outliers_dropped", r.calibration.outliersDropped()},
            {"model_terms", r.calibration.terms()},
            {"fit_error_deg", r.calibration.fitErrorDeg()},
            {"validation_targets", r.validationTargets},
            {"validation_samples", r.validationSamples},
            {"accuracy_deg", r.accuracyDeg},
            {"precision_deg", r.precisionDeg},
            {"output", o.out}};
}

} // namespace gt::app
