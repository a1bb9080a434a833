#pragma once
// The 3D model's calibration: the rotation from the eye camera's frame to the display's, fitted
// from the optical axes the eye model gives while the viewer fixates known targets (Kabsch's
// least-squares rotation between the axes and the directions to the targets). With the display
// rigid to the camera (a headset, or a camera fixed to the screen), this rotation does not change
// when the eye moves in front of the camera: slippage is left to the eye model's refit.
// A screen point's direction: from the viewer, (x, y, distance) in the display's frame (x right,
// y down, z towards the screen), as DisplayGeometry places the eye.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "gaze/display_geometry.hpp"
#include "model/camera_intrinsics.hpp"

namespace gt::eyetrack {

[[nodiscard]] cv::Vec3d directionToScreen(const DisplayGeometry& d, cv::Point2d px);
// nullopt when the direction does not meet the screen's plane in front of the viewer.
[[nodiscard]] std::optional<cv::Point2d> screenOfDirection(const DisplayGeometry& d,
                                                           const cv::Vec3d& dir);

struct Model3dCalibration {
    DisplayGeometry display;
    CameraIntrinsics camera;
    cv::Matx33d rotation = cv::Matx33d::eye(); // camera frame -> display frame
    cv::Vec3d eyeCentreMm{0, 0, 0};            // the eye model at calibration (a start)
    double eyeRadiusMm = 0.0;
    double pupilRadiusMm = 2.0; // assumed by the model (scale only)
    double fitErrorDeg = 0.0;   // mean, on the calibration targets

    // Kabsch: the rotation taking each axis to its target direction. Throws CalibrationError
    // with fewer than 3 pairs.
    void fitRotation(const std::vector<cv::Vec3d>& axes, const std::vector<cv::Point2d>& targets);
    [[nodiscard]] std::optional<cv::Point2d> map(const cv::Vec3d& axis) const;

    [[nodiscard]] nlohmann::json toJson() const;
    // Throws FormatError naming `what`.
    [[nodiscard]] static Model3dCalibration
    fromJson(const nlohmann::json& j, const DisplayGeometry& display, const std::string& what);
};

} // namespace gt::eyetrack
