#include "model/eye_model_mapper.hpp"

namespace gt::eyetrack {

EyeModelMapper::EyeModelMapper(Model3dCalibration calibration, EyeModelConfig config)
    : mCalibration(std::move(calibration)), mModel([&] {
          config.pupilRadiusMm = mCalibration.pupilRadiusMm;
          return EyeModel(mCalibration.camera, config);
      }()) {
    mModel.setSphere(mCalibration.eyeCentreMm, mCalibration.eyeRadiusMm);
}

std::optional<cv::Point2d> EyeModelMapper::map(const PupilResult& pupil, double /*tMs*/) {
    if (pupil.confidence >= kFitConfidence) {
        mModel.add(pupil.ellipse);
    }
    const auto axis = mModel.gaze(pupil.ellipse);
    if (!axis) {
        return std::nullopt;
    }
    return mCalibration.map(*axis);
}

} // namespace gt::eyetrack
