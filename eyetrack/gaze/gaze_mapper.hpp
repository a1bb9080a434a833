#pragma once
// From a pupil to where the eye looks on the screen: the step between detector and filter in the
// eye pipeline. Two models:
//  - PolynomialMapper ("2d"): the pupil centre through the 2D polynomial calibration
//    (gaze/calibration.hpp);
//  - EyeModelMapper ("3d", model/eye_model_mapper.hpp): the pupil ellipse unprojected onto a
//    fitted eyeball (Świrski & Dodgson 2013), the gaze ray turned onto the screen.
// map() may update the model (the 3D eyeball is refitted as ellipses arrive), so it is not const.
#include <optional>
#include <string>

#include <opencv2/core/types.hpp>

#include "gaze/calibration.hpp"
#include "gaze/display_geometry.hpp"
#include "pupil/pupil_detector.hpp"

namespace gt::eyetrack {

class GazeMapper {
public:
    virtual ~GazeMapper() = default;
    GazeMapper() = default;
    GazeMapper(const GazeMapper&) = delete;
    GazeMapper& operator=(const GazeMapper&) = delete;

    // Screen pixels of the calibration's display; nullopt when this pupil cannot be mapped.
    [[nodiscard]] virtual std::optional<cv::Point2d> map(const PupilResult& pupil, double tMs) = 0;
    [[nodiscard]] virtual const DisplayGeometry& display() const = 0;
    [[nodiscard]] virtual std::string model() const = 0; // "2d" | "3d"
};

class PolynomialMapper final : public GazeMapper {
public:
    explicit PolynomialMapper(Calibration calibration) : mCalibration(std::move(calibration)) {}
    [[nodiscard]] std::optional<cv::Point2d> map(const PupilResult& pupil, double) override {
        return mCalibration.map(pupil.centre());
    }
    [[nodiscard]] const DisplayGeometry& display() const override { return mCalibration.display(); }
    [[nodiscard]] std::string model() const override { return "2d"; }
    [[nodiscard]] const Calibration& calibration() const noexcept { return mCalibration; }

private:
    Calibration mCalibration;
};

} // namespace gt::eyetrack
