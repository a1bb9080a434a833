// Seed 002's layer model (Guenter et al. 2012, section 4.3) against the paper's own numbers and
// values worked by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/error.hpp"
#include "foveation/eccentricity_layers.hpp"

namespace gt::foveation {
namespace {

TEST(EccentricityLayers, PaperMonitorRadiusAndSharpness) {
    // Section 5: "e* = 23.4 deg (Eq. 6) ... omega* = 0.0516 deg (Eq. 7) ... omega0/omega* ~ 40 %".
    const LayerDisplay d = LayerDisplay::paperMonitor();
    EXPECT_NEAR(d.radiusDeg(), 23.4, 0.05);
    EXPECT_NEAR(d.sharpnessDeg(), 0.0516, 0.00005);
    EXPECT_NEAR(kOmega0Deg / d.sharpnessDeg(), 0.40, 0.01);
    EXPECT_DOUBLE_EQ(d.pixels(), 1920.0 * 1080.0); // eq. (8)
}

TEST(EccentricityLayers, MarModelIsLinear) {
    const MarModel a{kSlopeA};
    EXPECT_DOUBLE_EQ(a.marDeg(0.0), 1.0 / 48.0);
    // 1.65 arc minutes more per degree of eccentricity.
    EXPECT_NEAR((a.marDeg(10.0) - a.marDeg(0.0)) / 10.0 * 60.0, 1.65, 1e-9);
    EXPECT_NEAR(kSlopeB * 60.0, 1.32, 1e-9);
}

TEST(EccentricityLayers, ThreeLayersMatchHandWorkedValues) {
    // e1 = 5 deg, e2 = 12 deg at slope A on the paper's monitor, worked by hand from eqs. (2)-(5):
    // s2 = (0.0275 * 5 + 1/48) / 0.0515905 = 3.0690, s3 = (0.0275 * 12 + 1/48) / 0.0515905 = 6.8004,
    // D1 = 2 * 59 * tan 5 * 1920 / 51 = 388.66, D2 = 2 * 59 * tan 12 * 1920 / (3.0690 * 51) = 307.67,
    // D3 = 1920 / 6.8004 = 282.34; P = 388.66^2 + 307.67^2 + 0.5625 * 282.34^2 = 290,553.
    const std::vector<double> radii{5.0, 12.0};
    const LayerPlan p = planLayers(LayerDisplay::paperMonitor(), MarModel{kSlopeA}, radii);
    ASSERT_EQ(p.layers.size(), 3u);
    EXPECT_DOUBLE_EQ(p.layers[0].samplingFactor, 1.0);
    EXPECT_NEAR(p.layers[1].samplingFactor, 3.0690, 1e-4);
    EXPECT_NEAR(p.layers[2].samplingFactor, 6.8004, 1e-4);
    EXPECT_NEAR(p.layers[0].diameter, 388.66, 0.01);
    EXPECT_NEAR(p.layers[1].diameter, 307.67, 0.01);
    EXPECT_NEAR(p.layers[2].diameter, 282.34, 0.01);
    EXPECT_NEAR(p.layers[2].radiusDeg, 23.374, 0.001);
    EXPECT_NEAR(p.work, 290553.4, 1.0);
    EXPECT_NEAR(p.speedup(), 2073600.0 / 290553.4, 1e-3);
    // Half-rate weights (w1 = 1, w_i = 1/2): P = 151,053 + (94,661 + 44,840) / 2.
    const std::vector<double> w = halfRateWeights(3);
    EXPECT_NEAR(planLayers(LayerDisplay::paperMonitor(), MarModel{kSlopeA}, radii, w).work,
                151053.1 + (94660.6 + 44839.6) / 2.0, 1.0);
}

TEST(EccentricityLayers, SamplingNeverFinerThanTheDisplay) {
    // At e1 = 0.5 deg eq. (2) gives s2 = (0.01375 + 0.02083) / 0.0516 = 0.67: the layer stays at
    // the display's own pitch instead.
    const std::vector<double> radii{0.5};
    const LayerPlan p = planLayers(LayerDisplay::paperMonitor(), MarModel{kSlopeA}, radii);
    EXPECT_DOUBLE_EQ(p.layers[1].samplingFactor, 1.0);
}

TEST(EccentricityLayers, RejectsRadiiOutOfOrderOrOutside) {
    const LayerDisplay d = LayerDisplay::paperMonitor();
    const std::vector<double> descending{10.0, 5.0}, outside{5.0, 30.0}, zero{0.0};
    EXPECT_THROW((void)planLayers(d, MarModel{}, descending), ArgumentError);
    EXPECT_THROW((void)planLayers(d, MarModel{}, outside), ArgumentError);
    EXPECT_THROW((void)planLayers(d, MarModel{}, zero), ArgumentError);
    EXPECT_THROW((void)optimiseLayers(d, MarModel{}, 5), ArgumentError);
    EXPECT_THROW((void)optimiseLayers(d, MarModel{}, 0), ArgumentError);
}

TEST(EccentricityLayers, OptimiserFindsTheGridOptimum) {
    // Every pair (e1 < e2) on a 12-step grid, evaluated independently through planLayers.
    const LayerDisplay d = LayerDisplay::paperMonitor();
    const MarModel mar{kSlopeB};
    constexpr uint32_t kSteps = 12;
    double best = std::numeric_limits<double>::infinity(), bestE1 = 0, bestE2 = 0;
    for (uint32_t i = 1; i < kSteps; ++i) {
        for (uint32_t j = i + 1; j < kSteps; ++j) {
            const std::vector<double> r{d.radiusDeg() * i / kSteps, d.radiusDeg() * j / kSteps};
            const double work = planLayers(d, mar, r).work;
            if (work < best) {
                best = work;
                bestE1 = r[0];
                bestE2 = r[1];
            }
        }
    }
    const LayerPlan p = optimiseLayers(d, mar, 3, {}, kSteps);
    EXPECT_NEAR(p.work, best, 1e-6 * best);
    EXPECT_NEAR(p.layers[0].radiusDeg, bestE1, 1e-9);
    EXPECT_NEAR(p.layers[1].radiusDeg, bestE2, 1e-9);
    // A finer grid can only do as well or better, and n = 1 is the plain display.
    EXPECT_LE(optimiseLayers(d, mar, 3).work, p.work);
    EXPECT_DOUBLE_EQ(optimiseLayers(d, mar, 1).speedup(), 1.0);
}

TEST(EccentricityLayers, FigureTwelveShape) {
    // Figure 12: predicted speed-up P*/P at omega* = omega0 and alpha* = 3/4 rises with the field
    // of view, and more layers help more at wide fields.
    for (const double slope : {kSlopeA, kSlopeB}) {
        double last2 = 0.0, last3 = 0.0, last4 = 0.0;
        for (double fov = 20.0; fov <= 120.0; fov += 10.0) {
            const LayerDisplay d = LayerDisplay::acuityMatched(fov);
            EXPECT_NEAR(d.sharpnessDeg(), kOmega0Deg, 1e-9);
            EXPECT_NEAR(d.radiusDeg(), fov / 2.0, 1e-9);
            const double s2 = optimiseLayers(d, MarModel{slope}, 2, {}, 200).speedup();
            const double s3 = optimiseLayers(d, MarModel{slope}, 3, {}, 200).speedup();
            const double s4 = optimiseLayers(d, MarModel{slope}, 4, {}, 100).speedup();
            EXPECT_GT(s2, last2) << fov;
            EXPECT_GT(s3, last3) << fov;
            EXPECT_GT(s4, last4) << fov;
            EXPECT_GE(s3, s2) << fov;
            if (fov >= 60.0) {
                EXPECT_GT(s3, 1.1 * s2) << fov;
                EXPECT_GT(s4, s3) << fov;
            }
            last2 = s2;
            last3 = s3;
            last4 = s4;
        }
        // Cost grows as tan^2 e* without foveation and far slower with it (Figure 13).
        EXPECT_GT(last4, 10.0 * optimiseLayers(LayerDisplay::acuityMatched(20.0),
                                               MarModel{slope}, 4, {}, 100)
                                    .speedup());
    }
}

TEST(EccentricityLayers, PortraitProfilesTakeTheLongAxis) {
    const LayerDisplay fove = LayerDisplay::fromProfile({"fove", 1280, 1440, 0.85});
    EXPECT_DOUBLE_EQ(fove.resolution, 1440.0);
    EXPECT_NEAR(fove.aspect, 1280.0 / 1440.0, 1e-12);
    EXPECT_NEAR(fove.width, 1440.0 / 1280.0, 1e-12);
    EXPECT_DOUBLE_EQ(fove.pixels(), 1280.0 * 1440.0);
    const LayerDisplay desk = LayerDisplay::fromProfile({"desktop", 1920, 1080, 59.0 / 51.0});
    EXPECT_NEAR(desk.radiusDeg(), LayerDisplay::paperMonitor().radiusDeg(), 1e-9);
    EXPECT_NEAR(desk.sharpnessDeg(), LayerDisplay::paperMonitor().sharpnessDeg(), 1e-12);
}

TEST(EccentricityLayers, ParsesSlopes) {
    EXPECT_DOUBLE_EQ(parseSlope("A"), kSlopeA);
    EXPECT_DOUBLE_EQ(parseSlope("B"), kSlopeB);
    EXPECT_DOUBLE_EQ(parseSlope("0.03"), 0.03);
    EXPECT_THROW((void)parseSlope("C"), ArgumentError);
    EXPECT_THROW((void)parseSlope("-0.1"), ArgumentError);
    EXPECT_THROW((void)parseSlope("0.02x"), ArgumentError);
}

} // namespace
} // namespace gt::foveation
