#pragma once
// Calibration from a recording whose target schedule is known (eyesim writes one): detect the
// pupil in every frame, take the median pupil centre per calibration target after the eye has
// settled, fit, then measure accuracy and precision on the validation targets, which the fit
// never saw.
//  - accuracy: mean angular distance between gaze and target over validation samples (degrees);
//  - precision: RMS of the angular distance between successive samples on the same target.
#include <filesystem>
#include <optional>
#include <vector>

#include "capture/frame_source.hpp"
#include "gaze/calibration.hpp"
#include "model/model3d_calibration.hpp"
#include "pupil/pupil_detector.hpp"
#include "sim/gaze_schedule.hpp"

namespace gt::eyetrack {

struct ScheduledTarget {
    double tMs = 0.0;
    cv::Point2d target;
    GazePhase phase = GazePhase::Calibration;
    int targetIndex = 0; // targets are told apart by (phase, index)
};

class TargetSchedule {
public:
    // CSV with columns t_ms, target_x, target_y and optionally phase and target_index (without
    // them every row is a calibration target, numbered by runs of equal positions). Throws
    // FormatError.
    [[nodiscard]] static TargetSchedule load(const std::filesystem::path& file);
    [[nodiscard]] static TargetSchedule fromRows(std::vector<ScheduledTarget> rows);
    // The target shown at tMs and when it appeared; nullopt before the first row.
    [[nodiscard]] std::optional<std::pair<ScheduledTarget, double>> at(double tMs) const;

private:
    std::vector<ScheduledTarget> mRows;
    std::vector<double> mOnsetMs; // per row: when its target appeared
};

struct CalibrationResult {
    Calibration calibration;
    // With camera intrinsics: the 3D eye model's calibration and its validation accuracy.
    std::optional<Model3dCalibration> model3d;
    double accuracy3dDeg = 0.0;
    double precision3dDeg = 0.0;
    int calibrationTargets = 0;
    int validationTargets = 0;
    int validationSamples = 0;
    double accuracyDeg = 0.0;
    double precisionDeg = 0.0;
    int frames = 0;
};

// `camera`: the eye camera's intrinsics, to fit the 3D eye model too (model/eye_model.hpp): the
// eyeball from the calibration phase's ellipses, then the rotation onto the display.
[[nodiscard]] CalibrationResult
calibrateFromRecording(FrameSource& source, const TargetSchedule& schedule,
                       const DisplayGeometry& display, double settleMs, PupilDetector& detector,
                       const std::optional<CameraIntrinsics>& camera = std::nullopt);

} // namespace gt::eyetrack
