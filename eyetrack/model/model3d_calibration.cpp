#include "model/model3d_calibration.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include "error.hpp"
#include "formats/json_file.hpp"

namespace gt::eyetrack {

cv::Vec3d directionToScreen(const DisplayGeometry& d, cv::Point2d px) {
    const double k = d.cmPerPixel();
    return cv::normalize(
        cv::Vec3d((px.x - 0.5 * d.widthPx) * k, (px.y - 0.5 * d.heightPx) * k, d.distanceCm));
}

std::optional<cv::Point2d> screenOfDirection(const DisplayGeometry& d, const cv::Vec3d& dir) {
    if (!(dir[2] > 1e-6)) {
        return std::nullopt;
    }
    const double k = d.cmPerPixel();
    const cv::Point2d p(0.5 * d.widthPx + d.distanceCm * dir[0] / dir[2] / k,
                        0.5 * d.heightPx + d.distanceCm * dir[1] / dir[2] / k);
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
        return std::nullopt;
    }
    return p;
}

void Model3dCalibration::fitRotation(const std::vector<cv::Vec3d>& axes,
                                     const std::vector<cv::Point2d>& targets) {
    if (axes.size() != targets.size() || axes.size() < 3) {
        throw CalibrationError("3D calibration: at least 3 targets with an eye model are needed");
    }
    cv::Matx33d h = cv::Matx33d::zeros();
    for (std::size_t i = 0; i < axes.size(); ++i) {
        h += axes[i] * directionToScreen(display, targets[i]).t();
    }
    cv::Mat w, u, vt;
    cv::SVD::compute(cv::Mat(h), w, u, vt);
    const cv::Matx33d U(u), Vt(vt);
    const cv::Matx33d v = Vt.t();
    const double det = cv::determinant(v * U.t());
    const cv::Matx33d fix(1, 0, 0, 0, 1, 0, 0, 0, det < 0 ? -1.0 : 1.0);
    rotation = v * fix * U.t();
    double sum = 0.0;
    for (std::size_t i = 0; i < axes.size(); ++i) {
        const cv::Vec3d a = rotation * axes[i];
        const cv::Vec3d t = directionToScreen(display, targets[i]);
        sum += std::acos(std::clamp(a.dot(t) / cv::norm(a), -1.0, 1.0)) * 180.0 / CV_PI;
    }
    fitErrorDeg = sum / static_cast<double>(axes.size());
}

std::optional<cv::Point2d> Model3dCalibration::map(const cv::Vec3d& axis) const {
    return screenOfDirection(display, rotation * axis);
}

nlohmann::json Model3dCalibration::toJson() const {
    std::vector<double> r(rotation.val, rotation.val + 9);
    return {{"intrinsics", camera.toJson()},
            {"rotation", r},
            {"eye_centre_mm", {eyeCentreMm[0], eyeCentreMm[1], eyeCentreMm[2]}},
            {"eye_radius_mm", eyeRadiusMm},
            {"pupil_radius_mm", pupilRadiusMm},
            {"fit_error_deg", fitErrorDeg},
            {"refraction", "not modelled"}};
}

Model3dCalibration Model3dCalibration::fromJson(const nlohmann::json& j,
                                                const DisplayGeometry& display,
                                                const std::string& what) {
    auto bad = [&](const std::string& why) {
        return FormatError("calibration " + what + ": 3D model: " + why);
    };
    if (!j.is_object()) {
        throw bad("not a JSON object");
    }
    Model3dCalibration m;
    m.display = display;
    // Every field typed and named (a wrong type is one line naming the field).
    const JsonFields fields(j, "calibration " + what, "model3d.");
    constexpr double kAny = std::numeric_limits<double>::max(); // finite; bounded below
    m.camera = CameraIntrinsics::fromJson(fields.at("intrinsics"), what);
    const std::vector<double> r = fields.numbers("rotation", 9, -kAny, kAny);
    for (int i = 0; i < 9; ++i) {
        m.rotation.val[i] = r[static_cast<std::size_t>(i)];
    }
    // An eye a metre from its camera, or with a radius beyond that, is no eye model.
    const std::vector<double> c = fields.numbers("eye_centre_mm", 3, -1000.0, 1000.0);
    for (int i = 0; i < 3; ++i) {
        m.eyeCentreMm[i] = c[static_cast<std::size_t>(i)];
    }
    m.eyeRadiusMm = fields.number("eye_radius_mm", -1000.0, 1000.0);
    m.pupilRadiusMm = fields.number("pupil_radius_mm", -1000.0, 1000.0);
    m.fitErrorDeg = fields.number("fit_error_deg", 0.0, 360.0, 0.0);
    // A rotation: orthonormal with determinant 1.
    const cv::Matx33d e = m.rotation * m.rotation.t() - cv::Matx33d::eye();
    double off = 0.0;
    for (int i = 0; i < 9; ++i) {
        off = std::max(off, std::abs(e.val[i]));
    }
    if (!(off < 1e-3) || !(cv::determinant(m.rotation) > 0.0)) {
        throw bad("\"rotation\" is not a rotation");
    }
    if (!(m.eyeRadiusMm > 0.0) || !(m.pupilRadiusMm > 0.0) || !(m.eyeCentreMm[2] > 0.0) ||
        !std::isfinite(m.eyeCentreMm[0]) || !std::isfinite(m.eyeCentreMm[1])) {
        throw bad("the eye sphere must be in front of the camera with positive radii");
    }
    return m;
}

} // namespace gt::eyetrack
