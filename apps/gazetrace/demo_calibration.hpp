#pragma once
// `gazetrace demo --calibrate --gaze track:SOURCE --calibration OUT.json`: the calibration run
// in the window. The demo plans the targets — a 3 x 3 grid on the desktop screen, then validation
// targets between its points, one after another — and shows each one (the scene stays live and
// its fovea follows the target). Meanwhile a worker matches the tracker's frames to the target
// shown when each was taken: per target the median pupil centre after the eye settled, the
// fit, then the accuracy on the validation targets, which the fit never saw
// (eyetrack/gaze/recording_calibration.hpp). A synthetic eye (`synthetic:SEED`) is handed the
// demo's schedule, so it looks where the demo shows its targets.
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "gaze/recording_calibration.hpp"
#include "sim/gaze_schedule.hpp"

namespace gt::app {

class CalibrationSession {
public:
    // `gazeSpec` must be track:SOURCE; the calibration is written to `out` when it succeeds.
    CalibrationSession(const std::string& gazeSpec, std::string out);
    ~CalibrationSession();
    CalibrationSession(const CalibrationSession&) = delete;
    CalibrationSession& operator=(const CalibrationSession&) = delete;

    [[nodiscard]] double durationMs() const noexcept { return mDurationMs; }
    // The target shown at `tMs` (screen pixels of the desktop screen), or none (done).
    [[nodiscard]] std::optional<glm::vec2> target(double tMs) const;
    [[nodiscard]] const eyetrack::DisplayGeometry& display() const noexcept {
        return mConfig.display;
    }
    // Waits for the fit, saves it, and returns the summary. Throws when it failed.
    [[nodiscard]] nlohmann::json finish();

private:
    eyetrack::ScheduleConfig mConfig;
    double mDurationMs = 0.0;
    std::optional<eyetrack::TargetSchedule> mSchedule;
    std::string mSource, mOut;
    std::optional<eyetrack::CalibrationResult> mResult;
    std::string mError;
    std::jthread mWorker;
};

} // namespace gt::app
