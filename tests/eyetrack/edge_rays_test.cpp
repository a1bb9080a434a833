// The starburst detector's second stage: levels around a candidate, and rays that stop on the
// pupil's outline, skip glints inside it and drop crossings onto a glint.
#include <algorithm>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "pupil/box_blur.hpp"
#include "pupil/edge_rays.hpp"

namespace gt::eyetrack::starburst {
namespace {

struct Eye {
    cv::Mat grey, smooth, integral;
    BilinearRange cells;
    explicit Eye(cv::Mat g) : grey(std::move(g)) {
        boxBlur3x3(grey, smooth);
        cv::integral(grey, integral, CV_32S);
        cells.build(smooth);
    }
    [[nodiscard]] RayImage rays() const { return {smooth, cells, integral}; }
};

cv::Mat disc(int pupilLevel, int irisLevel) {
    cv::Mat grey(240, 320, CV_8UC1, cv::Scalar(irisLevel));
    cv::circle(grey, {160, 120}, 25, cv::Scalar(pupilLevel), cv::FILLED, cv::LINE_AA);
    return grey;
}

TEST(EdgeRays, MeasureLevelsBetweenPupilAndIris) {
    const Eye eye(disc(30, 130));
    const auto lv = measureLevels(eye.grey, {{160, 120}, 20.0, 0.0}, 12.0, 1.0);
    ASSERT_TRUE(lv.has_value());
    EXPECT_NEAR(lv->pupil, 30.0, 2.0);
    EXPECT_NEAR(lv->surround, 130.0, 2.0);
    EXPECT_GT(lv->threshold, lv->pupil);
    EXPECT_LT(lv->threshold, lv->surround);
    EXPECT_GT(lv->glint, lv->surround);
    // Too little contrast: no pupil there.
    const Eye faint(disc(120, 130));
    EXPECT_FALSE(measureLevels(faint.grey, {{160, 120}, 20.0, 0.0}, 12.0, 1.0).has_value());
}

TEST(EdgeRays, NoiseSigmaOfWhiteNoise) {
    cv::Mat grey(240, 320, CV_8UC1);
    cv::RNG rng(3);
    rng.fill(grey, cv::RNG::NORMAL, 100, 6);
    cv::Mat smooth;
    boxBlur3x3(grey, smooth);
    EXPECT_NEAR(noiseSigma(grey, smooth), 6.0, 1.5);
    const cv::Mat flat(240, 320, CV_8UC1, cv::Scalar(100));
    EXPECT_LT(noiseSigma(flat, flat), 1.0);
}

TEST(EdgeRays, PointsLieOnTheOutline) {
    const Eye eye(disc(30, 130));
    const RayLevels lv{.pupil = 30.0, .surround = 130.0, .threshold = 80.0, .glint = 200.0};
    EdgeRays rays(64);
    rays.cast(eye.rays(), {158, 121}, 60.0, lv);
    ASSERT_EQ(rays.points().size(), 64U);
    ASSERT_EQ(rays.gradients().size(), 64U);
    // The anti-aliased disc's half-way level lies half a pixel out.
    for (std::size_t i = 0; i < rays.points().size(); ++i) {
        const cv::Point2d d = rays.points()[i] - cv::Point2d(160, 120);
        EXPECT_NEAR(cv::norm(d), 25.5, 0.5) << i;
        // Gradients point out of the pupil (dark -> bright).
        EXPECT_GT(rays.gradients()[i].dot(d * (1.0 / cv::norm(d))), 0.8) << i;
    }
    // Every other ray (the first pass's coarser fan).
    rays.cast(eye.rays(), {158, 121}, 60.0, lv, false, 2);
    EXPECT_EQ(rays.points().size(), 32U);
}

TEST(EdgeRays, GlintsInsideAreSkippedAndOnTheEdgeDropped) {
    cv::Mat grey = disc(30, 130);
    cv::circle(grey, {168, 120}, 2, cv::Scalar(255), cv::FILLED); // inside the pupil
    cv::circle(grey, {160, 145}, 3, cv::Scalar(255), cv::FILLED); // on its lower edge
    const Eye eye(grey);
    const RayLevels lv{.pupil = 30.0, .surround = 130.0, .threshold = 80.0, .glint = 200.0};
    EXPECT_TRUE(isGlint(eye.smooth, eye.integral, {160, 145}, lv));
    EXPECT_FALSE(isGlint(eye.smooth, eye.integral, {185, 120}, lv)); // a plain edge
    EdgeRays rays(128);
    rays.cast(eye.rays(), {160, 120}, 60.0, lv);
    EXPECT_LT(rays.points().size(), 128U); // the rays onto the edge's glint are dropped
    EXPECT_GT(rays.points().size(), 110U);
    for (const cv::Point2d& p : rays.points()) {
        EXPECT_NEAR(cv::norm(p - cv::Point2d(160, 120)), 25.5, 0.5);
        EXPECT_GT(cv::norm(p - cv::Point2d(160, 145)), 3.0);
    }
}

TEST(EdgeRays, IrisOnlyDropsEdgesOntoALidMargin) {
    cv::Mat grey = disc(30, 130);
    // A lid over the pupil's top, its margin lined with lashes: darker than the iris, brighter
    // than the threshold, so the first pass takes its edge for the pupil's.
    cv::rectangle(grey, {0, 0}, {319, 105}, cv::Scalar(84), cv::FILLED);
    const Eye eye(grey);
    const RayLevels lv{.pupil = 30.0, .surround = 130.0, .threshold = 80.0, .glint = 250.0};
    const auto alongLid = [](const EdgeRays& r) {
        return std::count_if(r.points().begin(), r.points().end(),
                             [](const cv::Point2d& p) { return p.y < 107.0; });
    };
    EdgeRays rays(64);
    rays.cast(eye.rays(), {160, 120}, 60.0, lv, false);
    const auto plain = alongLid(rays);
    EXPECT_GT(plain, 8);
    // Only where the lid's line meets the iris, the outside half iris, may a point stay.
    rays.cast(eye.rays(), {160, 120}, 60.0, lv, true);
    EXPECT_LE(4 * alongLid(rays), plain);
    EXPECT_GT(rays.points().size(), 30U); // the rest of the outline stays
}

} // namespace
} // namespace gt::eyetrack::starburst
