#include "model/ellipse_unprojection.hpp"

#include <algorithm>
#include <cmath>

#include "error.hpp"
#include "pupil/ellipse_fit.hpp"

namespace gt::eyetrack {

std::array<Circle3d, 2> unprojectEllipse(const cv::RotatedRect& ellipse, const CameraIntrinsics& k,
                                         double radius) {
    if (!(ellipse.size.width > 0.0f) || !(ellipse.size.height > 0.0f) || !k.valid() ||
        !(radius > 0.0)) {
        throw EyetrackError("ellipse unprojection: degenerate ellipse, camera or radius");
    }
    const Conic q = Conic::fromEllipse(ellipse);
    const cv::Matx33d c(q.a, q.b / 2, q.d / 2, q.b / 2, q.c, q.e / 2, q.d / 2, q.e / 2, q.f);
    const cv::Matx33d km(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    cv::Matx33d cone = km.t() * c * km;
    // Scale for conditioning (the cone is defined up to scale).
    double norm = 0.0;
    for (int i = 0; i < 9; ++i) {
        norm = std::max(norm, std::abs(cone.val[i]));
    }
    cone *= 1.0 / norm;
    cv::Mat values, vectors;
    cv::eigen(cv::Mat(cone), values, vectors); // descending; rows of `vectors` are eigenvectors
    double l[3] = {values.at<double>(0), values.at<double>(1), values.at<double>(2)};
    cv::Vec3d v[3];
    for (int i = 0; i < 3; ++i) {
        v[i] = {vectors.at<double>(i, 0), vectors.at<double>(i, 1), vectors.at<double>(i, 2)};
    }
    // Two eigenvalues share a sign: make it positive, ordered l1 >= l2 > 0 > l3.
    if (l[1] < 0.0) {
        // Descending with two negative: (l0 > 0 > l1 >= l2) -> negate: (-l2 >= -l1 > 0 > -l0).
        const double n0 = -l[2], n1 = -l[1], n2 = -l[0];
        const cv::Vec3d w0 = v[2], w1 = v[1], w2 = v[0];
        l[0] = n0, l[1] = n1, l[2] = n2;
        v[0] = w0, v[1] = w1, v[2] = w2;
    }
    if (!(l[1] > 0.0) || !(l[2] < 0.0)) {
        throw EyetrackError("ellipse unprojection: the cone through the ellipse is not elliptic");
    }
    const double l1 = l[0], l2 = l[1], l3 = l[2];
    const double nx = std::sqrt(std::max(0.0, (l1 - l2) / (l1 - l3)));
    const double nz = std::sqrt(std::max(0.0, (l2 - l3) / (l1 - l3)));
    const double a = std::sqrt(std::max(0.0, l1 - l2)), b = std::sqrt(std::max(0.0, l2 - l3));
    const double cAbs = radius * l2 * std::sqrt((l1 - l3) / (-l1 * l3));
    std::array<Circle3d, 2> out;
    for (int s = 0; s < 2; ++s) {
        const double sign = s == 0 ? 1.0 : -1.0;
        // Plane family sign * a x - b z = c (eigen frame); its normal (sign a, 0, -b) / |.|.
        const cv::Vec3d planeNormal(sign * nx, 0.0, -nz);
        Circle3d best;
        bool have = false;
        for (const double cSign : {1.0, -1.0}) {
            const double cc = cSign * cAbs;
            // Circle centre: the sphere's centre -(c / 2 l2) (sign a, 0, b) moved onto the
            // plane along its normal.
            const cv::Vec3d sphere = -(cc / (2.0 * l2)) * cv::Vec3d(sign * a, 0.0, b);
            const double t = cc / std::sqrt(l1 - l3) * (l1 + l3) / (2.0 * l2);
            const cv::Vec3d centreEigen = sphere + t * planeNormal;
            const cv::Vec3d centre =
                centreEigen[0] * v[0] + centreEigen[1] * v[1] + centreEigen[2] * v[2];
            if (centre[2] <= 0.0) {
                continue; // behind the camera
            }
            cv::Vec3d n = planeNormal[0] * v[0] + planeNormal[1] * v[1] + planeNormal[2] * v[2];
            n = cv::normalize(n);
            if (n.dot(centre) > 0.0) {
                n = -n; // face the camera
            }
            best = {centre, n, radius};
            have = true;
        }
        if (!have) {
            throw EyetrackError("ellipse unprojection: no circle in front of the camera");
        }
        out[static_cast<std::size_t>(s)] = best;
    }
    return out;
}

} // namespace gt::eyetrack
