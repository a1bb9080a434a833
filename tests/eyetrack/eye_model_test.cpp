// The 3D eye model: ellipse unprojection against circles of known pose, and the eyeball fit on
// the synthetic eye's exact ellipses (perspective camera), before and after the headset slips.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <filesystem>
#include <unistd.h>

#include "error.hpp"
#include "gaze/calibration_set.hpp"
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
    applyPreset(c, EyeSimPreset::Clean);
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

TEST(CalibrationSet, VersionThreeRoundTripAndVersionTwoStillLoads) {
    const DisplayGeometry d;
    std::vector<CalibrationPoint> pts;
    for (int i = 0; i < 9; ++i) {
        const double gx = (i % 3) - 1.0, gy = (i / 3) - 1.0;
        pts.push_back({{160 + 30 * gx, 120 + 25 * gy}, d.pixelAtDeg({14 * gx, -8 * gy})});
    }
    const Calibration poly = Calibration::fit(pts, d);
    Model3dCalibration m;
    m.display = d;
    m.camera = {318.5, 318.5, 159.5, 119.5};
    m.eyeCentreMm = {1.0, -0.5, 30.0};
    m.eyeRadiusMm = 9.0;
    m.fitRotation({{0, 0, -1}, {0.2, 0, -0.98}, {0, 0.2, -0.98}},
                  {{960, 540}, {1300, 540}, {960, 800}});
    CalibrationSet set;
    set.eyes.push_back({"left", poly, m});
    set.eyes.push_back({"right", poly, std::nullopt});
    const auto dir =
        std::filesystem::temp_directory_path() / ("gazetrace_calset_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    set.save(dir / "v3.json");
    const CalibrationSet back = CalibrationSet::load(dir / "v3.json");
    ASSERT_EQ(back.eyes.size(), 2u);
    ASSERT_TRUE(back.eye("left").model3d);
    EXPECT_FALSE(back.eye("right").model3d);
    EXPECT_NEAR(cv::norm(back.eye("left").model3d->rotation - m.rotation), 0.0, 1e-9);
    EXPECT_NEAR(cv::norm(back.eye("left").poly.map({170, 130}) - poly.map({170, 130})), 0.0, 1e-6);
    EXPECT_NO_THROW((void)makeGazeMapper(back.eye("left"), GazeModel::ThreeD));
    EXPECT_THROW((void)makeGazeMapper(back.eye("right"), GazeModel::ThreeD), CalibrationError);
    EXPECT_THROW((void)back.eye("both"), CalibrationError); // two eyes: say which
    // Version 2 (a bare polynomial) loads as the one eye "both", and also through
    // Calibration::load; a version-3 file with one eye loads through both too.
    poly.save(dir / "v2.json");
    EXPECT_EQ(CalibrationSet::load(dir / "v2.json").eye("both").eye, "both");
    CalibrationSet one;
    one.eyes.push_back({"both", poly, m});
    one.save(dir / "one.json");
    EXPECT_NO_THROW((void)Calibration::load(dir / "one.json"));
    EXPECT_THROW((void)CalibrationSet::load(dir / "one.json").eye("left"), CalibrationError);
    // A two-eye file read for one eye (the renderer's --gaze track:) says so.
    try {
        (void)Calibration::load(dir / "v3.json");
        ADD_FAILURE() << "a two-eye file loaded as one";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("two eyes"), std::string::npos) << e.what();
    }
    // Not a rotation.
    auto j = set.toJson();
    j["eyes"][0]["model3d"]["rotation"][0] = 2.0;
    EXPECT_THROW((void)CalibrationSet::fromJson(j, "x"), FormatError);
    std::filesystem::remove_all(dir);
}
