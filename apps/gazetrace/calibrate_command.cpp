#include <opencv2/core/utility.hpp>

#include "capture/frame_source.hpp"
#include "eye_commands.hpp"
#include "gaze/calibration_set.hpp"
#include "gaze/recording_calibration.hpp"
#include "pupil/pupil_detector.hpp"

namespace gt::app {

nlohmann::json runCalibrate(const CalibrateOptions& o) {
    cv::setNumThreads(1);
    const auto schedule = eyetrack::TargetSchedule::load(o.targets);
    auto source = eyetrack::openFrameSource(o.source);
    const auto detector = eyetrack::makePupilDetector(o.detector);
    const auto camera = eyeCamera(o.camera);
    const auto r = eyetrack::calibrateFromRecording(*source, schedule, o.display, o.settleMs,
                                                    *detector, camera);
    eyetrack::CalibrationSet set;
    set.eyes.push_back({"both", r.calibration, r.model3d});
    set.save(o.out);
    nlohmann::json j{{"frames", r.frames},
                     {"calibration_targets", r.calibrationTargets},
                     {"outliers_dropped", r.calibration.outliersDropped()},
                     {"model_terms", r.calibration.terms()},
                     {"fit_error_deg", r.calibration.fitErrorDeg()},
                     {"validation_targets", r.validationTargets},
                     {"validation_samples", r.validationSamples},
                     {"accuracy_deg", r.accuracyDeg},
                     {"precision_deg", r.precisionDeg},
                     {"output", o.out}};
    if (r.model3d) {
        j["model3d"] = {{"fit_error_deg", r.model3d->fitErrorDeg},
                        {"accuracy_deg", r.accuracy3dDeg},
                        {"precision_deg", r.precision3dDeg},
                        {"eye_radius_mm", r.model3d->eyeRadiusMm}};
    }
    return j;
}

} // namespace gt::app
