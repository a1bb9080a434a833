// The starburst detector's refits: the ordered list the detector walks, how alternatives and
// the size judged for the confidence follow from it, and the lid-line refit on its own.
#include <cmath>
#include <numbers>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "pupil/refit_strategies.hpp"

namespace gt::eyetrack::starburst {
namespace {

TEST(RefitStrategies, OrderIsLidSizeShapeLimbus) {
    std::vector<std::string_view> names;
    for (const RefitStrategy& s : refitStrategies())
        names.push_back(s.name);
    EXPECT_EQ(names, (std::vector<std::string_view>{"lid line", "recent size", "under lid",
                                                    "rounder under lid", "eye shape", "limbus"}));
    const auto strategies = refitStrategies();
    EXPECT_FALSE(strategies[0].heldToRecentSize);
    EXPECT_TRUE(strategies[1].heldToRecentSize);
    EXPECT_EQ(strategies[1].alternatives, strategies[2].alternatives);
    EXPECT_EQ(strategies[2].alternatives, strategies[3].alternatives);
    EXPECT_NE(strategies[1].alternatives, 0);
    EXPECT_EQ(strategies[4].alternatives, 0);
    EXPECT_EQ(strategies[5].alternatives, 0);
}

EllipseFit circle(float x, float radius) {
    EllipseFit f;
    f.ellipse = cv::RotatedRect({x, 50.0F}, {2 * radius, 2 * radius}, 0.0F);
    return f;
}

// Test strategies: each moves the ellipse's centre right by a known step, or declines.
std::optional<EllipseFit> grow(const RefitContext&, const EllipseFit& f) {
    return circle(f.ellipse.center.x + 1.0F, 0.5F * f.ellipse.size.width + 10.0F);
}
std::optional<EllipseFit> stepTen(const RefitContext&, const EllipseFit& f) {
    return circle(f.ellipse.center.x + 10.0F, 0.5F * f.ellipse.size.width);
}
std::optional<EllipseFit> stepHundred(const RefitContext&, const EllipseFit& f) {
    return circle(f.ellipse.center.x + 100.0F, 0.5F * f.ellipse.size.width);
}
std::optional<EllipseFit> decline(const RefitContext&, const EllipseFit&) {
    return std::nullopt;
}

struct Context {
    cv::Mat grey{100, 100, CV_8UC1, cv::Scalar(0)};
    RayLevels levels;
    RansacEllipseParams ransac;
    PupilPriors priors;
    [[nodiscard]] RefitContext get() const { return {grey, grey, {}, {}, levels, ransac, priors}; }
};

TEST(RefitStrategies, WalksInOrderAndSkipsTakenAlternatives) {
    const Context c;
    const std::array list{
        RefitStrategy{"grow", grow},
        RefitStrategy{"first alternative declines", decline, 1, true},
        RefitStrategy{"second alternative", stepTen, 1, true},
        RefitStrategy{"third alternative", stepHundred, 1, true},
        RefitStrategy{"after", stepTen},
    };
    const Refitted r = applyRefits(c.get(), circle(0.0F, 20.0F), list);
    // grow (+1), the second alternative (+10), not the third, then after (+10).
    EXPECT_FLOAT_EQ(r.fit.ellipse.center.x, 21.0F);
    // The size the edges chose: after grow, before the first strategy held to the recent size.
    EXPECT_DOUBLE_EQ(r.fittedSemiMajor, 30.0);
}

TEST(RefitStrategies, FittedSizeIsTheFinalWithoutSizeHeldStrategies) {
    const Context c;
    const std::array list{RefitStrategy{"grow", grow}, RefitStrategy{"grow again", grow}};
    const Refitted r = applyRefits(c.get(), circle(0.0F, 20.0F), list);
    EXPECT_DOUBLE_EQ(r.fittedSemiMajor, 40.0);
}

TEST(RefitStrategies, LidLineIsLeftOut) {
    // The pupil's outline below a lid (y < 38 hidden), and the lid's margin as a straight run of
    // edge points at y = 38, in ray (angle) order as the rays give them.
    const cv::Point2d centre(50.0, 50.0);
    const double radius = 20.0;
    std::vector<cv::Point2d> points, gradients;
    constexpr int kRays = 64;
    for (int i = 0; i < kRays; ++i) {
        const double a = (i + 0.5) * 2.0 * std::numbers::pi / kRays;
        const cv::Point2d dir(std::cos(a), std::sin(a));
        cv::Point2d p = centre + dir * radius;
        if (p.y < 38.0) {
            p = centre + dir * (-12.0 / dir.y); // where the ray meets the lid's line
        }
        points.push_back(p);
        gradients.push_back(p.y <= 38.0 + 1e-9 ? cv::Point2d(0.0, -1.0) : dir);
    }
    cv::Mat grey(100, 100, CV_8UC1, cv::Scalar(0));
    const RayLevels levels;
    RansacEllipseParams ransac;
    ransac.iterations = 150;
    ransac.minAxis = 10.0;
    ransac.maxAxis = 90.0;
    const PupilPriors priors;
    const RefitContext ctx{grey, grey, points, gradients, levels, ransac, priors};
    // The fit the lid pulled flat and low.
    EllipseFit hugging;
    hugging.ellipse = cv::RotatedRect({50.0F, 53.0F}, {40.0F, 30.0F}, 0.0F);
    const auto refit = fitBesideLid(ctx, hugging);
    ASSERT_TRUE(refit.has_value());
    EXPECT_NEAR(refit->ellipse.center.x, 50.0, 0.5);
    EXPECT_NEAR(refit->ellipse.center.y, 50.0, 0.5);
    EXPECT_NEAR(refit->ellipse.size.width, 40.0, 1.0);
    EXPECT_NEAR(refit->ellipse.size.height, 40.0, 1.0);
    // Without a lid among the points, nothing to refit.
    std::vector<cv::Point2d> round;
    for (int i = 0; i < kRays; ++i) {
        const double a = (i + 0.5) * 2.0 * std::numbers::pi / kRays;
        round.push_back(centre + cv::Point2d(std::cos(a), std::sin(a)) * radius);
    }
    const RefitContext plain{grey, grey, round, {}, levels, ransac, priors};
    EXPECT_FALSE(fitBesideLid(plain, circle(50.0F, 20.0F)).has_value());
}

TEST(RefitStrategies, SizeRefitsNeedARecentSize) {
    const Context c; // nothing learnt
    EXPECT_FALSE(fitAtRecentSize(c.get(), circle(50.0F, 30.0F)).has_value());
    EXPECT_FALSE(fitUnderLid(c.get(), circle(50.0F, 30.0F)).has_value());
    EXPECT_FALSE(fitToEyeShape(c.get(), circle(50.0F, 30.0F)).has_value());
}

} // namespace
} // namespace gt::eyetrack::starburst
