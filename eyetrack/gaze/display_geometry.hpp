#pragma once
// The screen the eye looks at, for converting between screen pixels and visual angle: accuracy and
// precision (calibration), I-VT velocities (filter) and the synthetic eye's rotation all need it.
// Default: the desktop profile of the renderer (1920x1080, 51 cm wide, seen from 59 cm; Guenter et
// al. 2012's setup).
#include <algorithm>
#include <cmath>
#include <numbers>

#include <opencv2/core/types.hpp>

namespace gt::eyetrack {

struct DisplayGeometry {
    int widthPx = 1920;
    int heightPx = 1080;
    double widthCm = 51.0;
    double distanceCm = 59.0;

    [[nodiscard]] double cmPerPixel() const { return widthCm / widthPx; }

    // Horizontal and vertical gaze angles (degrees) of a screen point, 0 at the screen centre,
    // yaw positive to the right, pitch positive upwards.
    [[nodiscard]] cv::Point2d anglesDeg(cv::Point2d px) const {
        const double k = cmPerPixel();
        const double x = (px.x - 0.5 * widthPx) * k, y = (0.5 * heightPx - px.y) * k;
        const double yaw = std::atan2(x, distanceCm);
        const double pitch = std::atan2(y, std::hypot(x, distanceCm));
        return {yaw * 180.0 / std::numbers::pi, pitch * 180.0 / std::numbers::pi};
    }

    // The inverse of anglesDeg: the screen point seen at these gaze angles (|angle| < 90 deg).
    [[nodiscard]] cv::Point2d pixelAtDeg(cv::Point2d angles) const {
        constexpr double kLimit = 89.0; // a wild extrapolation must not reach tan's pole
        const double rad = std::numbers::pi / 180.0;
        const double yaw = std::clamp(angles.x, -kLimit, kLimit) * rad;
        const double pitch = std::clamp(angles.y, -kLimit, kLimit) * rad;
        const double x = distanceCm * std::tan(yaw);
        const double y = std::hypot(x, distanceCm) * std::tan(pitch);
        const double k = cmPerPixel();
        return {0.5 * widthPx + x / k, 0.5 * heightPx - y / k};
    }

    // Angle (degrees) between the lines of sight to two screen points.
    [[nodiscard]] double angularDistanceDeg(cv::Point2d a, cv::Point2d b) const {
        const double k = cmPerPixel();
        const cv::Vec3d va((a.x - 0.5 * widthPx) * k, (a.y - 0.5 * heightPx) * k, distanceCm);
        const cv::Vec3d vb((b.x - 0.5 * widthPx) * k, (b.y - 0.5 * heightPx) * k, distanceCm);
        const double c = va.dot(vb) / (cv::norm(va) * cv::norm(vb));
        return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / std::numbers::pi;
    }

    // Screen pixels per degree near the centre (for thresholds given in degrees).
    [[nodiscard]] double pixelsPerDegreeAtCentre() const {
        return distanceCm * std::tan(std::numbers::pi / 180.0) / cmPerPixel();
    }
};

} // namespace gt::eyetrack
