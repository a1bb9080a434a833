#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <opencv2/core/utility.hpp>

#include "capture/frame_source.hpp"
#include "capture/region_source.hpp"
#include "core/error.hpp"
#include "eye_commands.hpp"
#include "eye_source_parsing.hpp"
#include "gaze/calibration_set.hpp"
#include "gaze/recording_calibration.hpp"
#include "option_parsing.hpp"
#include "pupil/pupil_detector.hpp"
#include "stop_request.hpp"

namespace gt::app {

namespace {

// The recording handed to eyetrack::calibrateFromRecording: each next() first checks for a stop
// request (SIGINT, SIGTERM), so calibrating fails within a frame of one, with nothing written.
class InterruptibleSource final : public eyetrack::FrameSource {
public:
    explicit InterruptibleSource(std::unique_ptr<eyetrack::FrameSource> source)
        : mSource(std::move(source)) {}
    std::optional<eyetrack::Frame> next() override {
        throwIfStopRequested();
        return mSource->next();
    }
    std::string describe() const override { return mSource->describe(); }
    std::uint64_t droppedFrames() const override { return mSource->droppedFrames(); }
    bool liveClock() const override { return mSource->liveClock(); }

private:
    std::unique_ptr<eyetrack::FrameSource> mSource;
};

} // namespace

nlohmann::json runCalibrate(const CalibrateOptions& o) {
    cv::setNumThreads(1);
    const bool binocular = !o.sourceLeft.empty() || !o.sourceRight.empty() || !o.regions.empty();
    if (!binocular && o.source.empty())
        throw ArgumentError("calibrate: --source (or --source-left and --source-right)");
    if (binocular && o.regions.empty() && (o.sourceLeft.empty() || o.sourceRight.empty()))
        throw ArgumentError("two eyes need both --source-left and --source-right");
    if (!o.regions.empty() && (o.source.empty() || !o.sourceLeft.empty()))
        throw ArgumentError("--regions splits the one --source; without --source-left/-right");
    const auto schedule = eyetrack::TargetSchedule::load(o.targets);
    const auto camera = eyeCamera(o.camera);
    // One session, one schedule: each eye is calibrated on its own camera (or region).
    struct Eye {
        std::string name;
        std::unique_ptr<eyetrack::FrameSource> source;
    };
    std::vector<Eye> eyes;
    if (!binocular) {
        eyes.push_back({"both", openFrameSource(o.source)});
    } else if (!o.regions.empty()) {
        const auto [left, right] = parseEyeRegions(o.regions);
        eyes.push_back({"left", std::make_unique<eyetrack::RegionSource>(openFrameSource(o.source),
                                                                         left, "left eye")});
        eyes.push_back({"right", std::make_unique<eyetrack::RegionSource>(openFrameSource(o.source),
                                                                          right, "right eye")});
    } else {
        eyes.push_back({"left", openFrameSource(o.sourceLeft)});
        eyes.push_back({"right", openFrameSource(o.sourceRight)});
    }
    eyetrack::CalibrationSet set;
    nlohmann::json perEye = nlohmann::json::object();
    for (Eye& e : eyes) {
        const auto detector = eyetrack::makePupilDetector(pupilDetectorKind(o.detector));
        InterruptibleSource source(std::move(e.source));
        const auto r = eyetrack::calibrateFromRecording(source, schedule, o.display, o.settleMs,
                                                        *detector, camera);
        set.eyes.push_back({e.name, r.calibration, r.model3d});
        nlohmann::json j{{"frames", r.frames},
                         {"calibration_targets", r.calibrationTargets},
                         {"outliers_dropped", r.calibration.outliersDropped()},
                         {"model_terms", r.calibration.terms()},
                         {"fit_error_deg", r.calibration.fitErrorDeg()},
                         {"validation_targets", r.validationTargets},
                         {"validation_samples", r.validationSamples},
                         {"accuracy_deg", r.accuracyDeg},
                         {"precision_deg", r.precisionDeg}};
        if (r.model3d) {
            j["model3d"] = {{"fit_error_deg", r.model3d->fitErrorDeg},
                            {"accuracy_deg", r.accuracy3dDeg},
                            {"precision_deg", r.precision3dDeg},
                            {"eye_radius_mm", r.model3d->eyeRadiusMm}};
        }
        perEye[e.name] = j;
    }
    throwIfStopRequested(); // the fits of a long recording take a while
    set.save(o.out);
    if (!binocular) {
        nlohmann::json j = perEye["both"];
        j["output"] = o.out;
        return j;
    }
    return {{"eyes", perEye}, {"output", o.out}};
}

} // namespace gt::app
