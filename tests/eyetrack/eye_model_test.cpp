// The 3D eye model: ellipse unprojection against circles of known pose, and the eyeball fit on
// the synthetic eye's exact ellipses (perspective camera), before and after the headset slips.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "error.hpp"
#include "model/ellipse_unprojection.hpp"
#include "model/eye_model.hpp"
#include "sim/synthetic_eye.hpp"

using namespace gt::eyetrack;

namespace {

double angleDeg(const cv::Vec3d& a, const cv::Vec3d& b) {
    return std::acos(std::clamp(cv::normalize(a).dot(cv::normalize(b)), -1.0, 1.0)) * 180.0 /
           std::numbers::pi;
}

cv::RotatedRect imageOf(const Circle3d& c, const CameraIntrinsics& k) {
    const cv::Vec3d helper(0, 1, 0);
    const cv::Vec3d u = cv::normalize(helper.cross(c.normal)), v = c.normal.cross(u);
    std::vector<cv::Point2f> pts;
    for (int i = 0; i < 128; ++i) {
        const double a = 2.0 * std::numbers::pi * i / 128;
        const cv::Point2d p = k.project(c.centre + (u * std::cos(a) + v * std::sin(a)) * c.radius);
        pts.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y));
    }
    return cv::fitEllipse(pts);
}

} // namespace

TEST(EllipseUnprojection, OneOfTheTwoCirclesIsTheTrueOne) {
    const CameraIntrinsics k{320.0, 320.0, 159.5, 119.5};
    for (const cv::Vec3d& normal :
         {cv::Vec3d(0.2, -0.3, -1.0), cv::Vec3d(-0.5, 0.1, -1.0), cv::Vec3d(0.05, 0.4, -1.0)}) {
        const Circle3d truth{{3.0, -2.0, 35.0}, cv::normalize(normal), 2.0};
        const auto both = unprojectEllipse(imageOf(truth, k), k, 2.0);
        double bestAngle = 1e9, bestDistance = 1e9;
        for (const Circle3d& c : both) {
            EXPECT_LT(c.normal.dot(c.centre), 0.0); // faces the camera
            EXPECT_GT(c.centre[2], 0.0);
            if (angleDeg(c.normal, truth.normal) < bestAngle) {
                bestAngle = angleDeg(c.normal, truth.normal);
                bestDistance = cv::norm(c.centre - truth.centre);
            }
        }
        EXPECT_LT(bestAngle, 0.2) << normal;
        EXPECT_LT(bestDistance, 0.05) << normal;
        // The radius sets the scale: twice the radius, twice the distance.
        const auto twice = unprojectEllipse(imageOf(truth, k), k, 4.0);
        EXPECT_NEAR(cv::norm(twice[0].centre), 2.0 * cv::norm(both[0].centre), 1e-6);
    }
    EXPECT_THROW((void)unprojectEllipse(cv::RotatedRect({10, 10}, {0, 5}, 0), k, 2.0),
                 EyetrackError);
}

TEST(EyeModel, FitsTheSyntheticEyeAndFollowsASlip) {
    EyeSimConfig c;
    c.seed = 3;
    c.frames = 2400;
    applyPreset(c, "clean");
    c.perspective = true;
    const SyntheticEye eye(c);
    EyeModel model(eye.intrinsics());
    auto meanError = [&](const SyntheticEye& e, int from, int to) {
        double sum = 0.0;
        int n = 0;
        for (int f = from; f < to; f += 7) {
            EyeTruth t;
            (void)e.render(f, &t);
            const auto g = model.gaze(cv::RotatedRect({float(t.centre.x), float(t.centre.y)},
                                                      {float(2 * t.axisA), float(2 * t.axisB)},
                                                      float(t.angleDeg)));
            if (!g) continue;
            sum += angleDeg(*g, t.gazeDirection);
            ++n;
        }
        return n ? sum / n : 1e9;
    };
    auto feed = [&](const SyntheticEye& e, int from, int to) {
        for (int f = from; f < to; f += 4) {
            EyeTruth t;
            (void)e.render(f, &t);
            model.add(cv::RotatedRect({float(t.centre.x), float(t.centre.y)},
                                      {float(2 * t.axisA), float(2 * t.axisB)}, float(t.angleDeg)));
        }
    };
    feed(eye, 0, 1200); // the calibration grid: nine fixations
    ASSERT_TRUE(model.ready());
    // The eye's centre is recovered up to the scale of the assumed pupil radius: its direction.
    EyeTruth t0;
    (void)eye.render(0, &t0);
    EXPECT_LT(angleDeg(model.centre(), t0.eyeCentreMm), 0.5);
    EXPECT_LT(meanError(eye, 1200, 2400), 0.4);

    // The headset slips 2 mm sideways and 1 mm down, turning 2 degrees: after a refit on new
    // ellipses the model follows.
    EyeSimConfig slipped = c;
    slipped.slipMm = {2.0, 1.0, 0.0};
    slipped.slipDeg = 2.0;
    slipped.slipAtMs = 0.0;
    const SyntheticEye moved(slipped);
    model.clearWindow();
    feed(moved, 0, 1200);
    EXPECT_LT(meanError(moved, 1200, 2400), 0.4);
}
