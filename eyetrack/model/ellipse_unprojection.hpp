#pragma once
// A pupil ellipse back to the 3D circle it is the image of (Safaee-Rad et al. 1992, as used by
// Świrski & Dodgson 2013, section 3.1). The rays from the camera centre through the ellipse form
// an elliptic cone X^T Q X = 0, Q = K^T C K (C: the image conic, K: the intrinsics). In Q's
// eigenbasis, with eigenvalues l1 >= l2 > 0 > l3, the planes that cut the cone in circles have
// normals (+-sqrt((l1 - l2)/(l1 - l3)), 0, sqrt((l2 - l3)/(l1 - l3))): subtracting l2 |X|^2 from
// the cone leaves (l1 - l2) x^2 - (l2 - l3) z^2, a pair of planes, and on any plane parallel to
// one of them the cone coincides with a sphere. A circle of radius r on such a plane sits at
// distance |c| / sqrt(l1 - l3) from the camera's centre along its normal, with
// |c| = r l2 sqrt((l1 - l3) / (-l1 l3)). So an ellipse gives two circles (the two tilts that
// project to it), each known up to the scale set by the assumed radius r.
#include <array>

#include <opencv2/core.hpp>

#include "model/camera_intrinsics.hpp"

namespace gt::eyetrack {

struct Circle3d {
    cv::Vec3d centre; // camera frame (x right, y down, z forward), units of the radius
    cv::Vec3d normal; // unit, facing the camera (normal . centre < 0)
    double radius = 0.0;
};

// Both circles of radius `radius` that project to `ellipse` (pixels). Throws EyetrackError for a
// degenerate ellipse (an axis of zero length or a cone that is not elliptic).
[[nodiscard]] std::array<Circle3d, 2>
unprojectEllipse(const cv::RotatedRect& ellipse, const CameraIntrinsics& camera, double radius);

} // namespace gt::eyetrack
