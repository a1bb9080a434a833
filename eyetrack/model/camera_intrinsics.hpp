#pragma once
// A pinhole eye camera: focal lengths and principal point in pixels (no lens distortion; eye
// cameras are undistorted before this, or close enough over the small eye region). Shared by the
// synthetic eye's perspective camera and the 3D eye model, which unprojects pupil ellipses with
// it. Saved as {"fx":..,"fy":..,"cx":..,"cy":..}; `track --model 3d --intrinsics FILE` reads it,
// or the flags give the numbers.
#include <cmath>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

namespace gt::eyetrack {

struct CameraIntrinsics {
    double fx = 0.0, fy = 0.0; // pixels
    double cx = 0.0, cy = 0.0; // principal point, pixels (pixel centres at integers)

    [[nodiscard]] bool valid() const {
        return std::isfinite(fx) && std::isfinite(fy) && std::isfinite(cx) && std::isfinite(cy) &&
               fx > 0.0 && fy > 0.0;
    }
    // Camera coordinates: x right, y down, z forward (OpenCV). p.z must be > 0.
    [[nodiscard]] cv::Point2d project(const cv::Vec3d& p) const {
        return {cx + fx * p[0] / p[2], cy + fy * p[1] / p[2]};
    }
    // The point at depth z = 1 seen at pixel u.
    [[nodiscard]] cv::Vec3d unproject(cv::Point2d u) const {
        return {(u.x - cx) / fx, (u.y - cy) / fy, 1.0};
    }
    // The default eye camera of `gazetrace eyesim` for an image of `size`: principal point at
    // the image centre, 9.1 px/mm at the eye's 35 mm distance on a 240-row image (sim/).
    [[nodiscard]] static CameraIntrinsics eyesimDefault(cv::Size size);

    [[nodiscard]] nlohmann::json toJson() const;
    // Throws FormatError naming `what` when a field is missing, not a number or not positive.
    [[nodiscard]] static CameraIntrinsics fromJson(const nlohmann::json& j,
                                                   const std::string& what);
    [[nodiscard]] static CameraIntrinsics load(const std::filesystem::path& file);
    void save(const std::filesystem::path& file) const; // atomic
};

} // namespace gt::eyetrack
