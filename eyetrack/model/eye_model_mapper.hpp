#pragma once
// The "3d" gaze mapper: each confident pupil ellipse goes into the eye model's window (which
// refits itself, following the eye when the headset slips), the model's optical axis for the
// ellipse goes through the calibration rotation onto the screen.
#include "gaze/gaze_mapper.hpp"
#include "model/eye_model.hpp"
#include "model/model3d_calibration.hpp"

namespace gt::eyetrack {

class EyeModelMapper final : public GazeMapper {
public:
    // Starts from the calibration's eye sphere.
    explicit EyeModelMapper(Model3dCalibration calibration, EyeModelConfig config = {});

    [[nodiscard]] std::optional<cv::Point2d> map(const PupilResult& pupil, double tMs) override;
    [[nodiscard]] const DisplayGeometry& display() const override { return mCalibration.display; }
    [[nodiscard]] std::string model() const override { return "3d"; }
    [[nodiscard]] const EyeModel& eyeModel() const noexcept { return mModel; }

    // Pupils at least this confident feed the model's window.
    static constexpr double kFitConfidence = 0.75;

private:
    Model3dCalibration mCalibration;
    EyeModel mModel;
};

} // namespace gt::eyetrack
