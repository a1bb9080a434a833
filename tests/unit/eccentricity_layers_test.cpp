// The layer model of Guenter et al. 2012 (section 4.3) against the paper's own numbers and
// values worked by hand.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "core/error.hpp"
#include "foveation/eccentricity_layers.hpp"
#include "layer_layout.hpp"

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
    // s2 = (0.0275 * 5 + 1/48) / 0.0515905 = 3.0690, s3 = (0.0275 * 12 + 1/48) / 0.0515905
    // = 6.8004, D1 = 2 * 59 * tan 5 * 1920 / 51 = 388.66, D2 = 2 * 59 * tan 12 * 1920 / (3.0690 *
    // 51) = 307.67, D3 = 1920 / 6.8004 = 282.34; P = 388.66^2 + 307.67^2 + 0.5625 * 282.34^2 =
    // 290,553.
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
        EXPECT_GT(last4, 10.0 * optimiseLayers(LayerDisplay::acuityMatched(20.0), MarModel{slope},
                                               4, {}, 100)
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

// ---------------------------------------------------------------------------------------------
// Where the layers go on a view (renderer/layer_layout).

TEST(LayerLayout, JitterCoversThePixelEvenly) {
    // Halton (2, 3): any 6 consecutive frames put one offset in each cell of a 2 x 3 split of
    // the pixel, and 64 frames fill a 4 x 4 split with 4 each, all within [-0.5, 0.5).
    for (uint64_t start : {0u, 5u, 17u}) {
        std::array<int, 6> cells{};
        for (uint64_t f = start; f < start + 6; ++f) {
            const glm::vec2 j = render::layerJitter(f);
            ASSERT_GE(j.x, -0.5f);
            ASSERT_LT(j.x, 0.5f);
            ASSERT_GE(j.y, -0.5f);
            ASSERT_LT(j.y, 0.5f);
            ++cells[static_cast<std::size_t>(std::floor((j.x + 0.5f) * 2.0f) * 3 +
                                             std::floor((j.y + 0.5f) * 3.0f))];
        }
        for (const int c : cells) {
            EXPECT_EQ(c, 1) << start;
        }
    }
    std::array<int, 16> grid{};
    glm::vec2 mean(0.0f);
    for (uint64_t f = 0; f < 64; ++f) {
        const glm::vec2 j = render::layerJitter(f);
        mean += j / 64.0f;
        ++grid[static_cast<std::size_t>(std::floor((j.x + 0.5f) * 4.0f) * 4 +
                                        std::floor((j.y + 0.5f) * 4.0f))];
    }
    for (const int c : grid) {
        EXPECT_GE(c, 2);
    }
    EXPECT_NEAR(mean.x, 0.0f, 0.02f);
    EXPECT_NEAR(mean.y, 0.0f, 0.02f);
}

TEST(LayerLayout, DesktopLayersMatchTheOptimum) {
    // The desktop profile at 1920 x 1080, slope A: the optimiser's plan, each inner layer a
    // square of 2 tan(e_i) * D* V* / W* display pixels at pitch s_i, the outer the whole screen.
    const LayerDisplay d = LayerDisplay::fromProfile({"desktop", 1920, 1080, 59.0 / 51.0});
    const render::LayerLayout lay = render::layoutLayers(1920, 1080, d, MarModel{kSlopeA}, 3);
    ASSERT_EQ(lay.grids.size(), 3u);
    const double perTangent = 1920.0 * 59.0 / 51.0;
    for (std::size_t i = 0; i < 2; ++i) {
        const double r =
            std::tan(lay.plan.layers[i].radiusDeg * std::numbers::pi / 180.0) * perTangent;
        EXPECT_NEAR(lay.grids[i].radiusPx, r, 1e-3);
        EXPECT_EQ(lay.grids[i].width,
                  static_cast<uint32_t>(std::ceil(
                      std::min(2.0 * r, 1080.0) / lay.plan.layers[i].samplingFactor - 1e-6)));
    }
    EXPECT_TRUE(lay.grids[2].outer);
    EXPECT_EQ(lay.grids[2].width, static_cast<uint32_t>(std::ceil(1920.0 / lay.grids[2].pitch)));
    EXPECT_EQ(lay.grids[2].height, static_cast<uint32_t>(std::ceil(1080.0 / lay.grids[2].pitch)));
    // The layers hold about P of eq. (5): the outer layer's ceil() and clipping aside.
    EXPECT_NEAR(static_cast<double>(lay.pixels()), lay.plan.work, 0.01 * lay.plan.work);
}

TEST(LayerLayout, InnerLayersFollowTheGazeInsideTheDisplay) {
    render::LayerGrid g{50, 50, 2.0f, 100.0f, false}; // 100 px square
    // Centred on the gaze, the corner on a multiple of the pitch.
    render::LayerRect r = render::placeLayer(g, 640, 480, {320.0f, 240.0f});
    EXPECT_EQ(r.size, glm::vec2(100.0f));
    EXPECT_NEAR(r.origin.x + 50.0f, 320.5f, 1.0f);
    EXPECT_FLOAT_EQ(std::fmod(r.origin.x, 2.0f), 0.0f);
    // Near a corner it moves inside: the display's part of the gaze's disc stays covered.
    r = render::placeLayer(g, 640, 480, {10.0f, 470.0f});
    EXPECT_EQ(r.origin, glm::vec2(0.0f, 380.0f));
    // The outer layer is centred on the display; a jitter moves the grid in layer pixels.
    const render::LayerGrid outer{107, 81, 6.0f, 0.0f, true};
    r = render::placeLayer(outer, 640, 480, {10.0f, 10.0f});
    EXPECT_EQ(r.origin, glm::vec2((640.0f - 642.0f) / 2.0f, (480.0f - 486.0f) / 2.0f));
    EXPECT_EQ(render::jittered(r, 6.0f, {0.5f, -0.25f}).origin, r.origin + glm::vec2(3.0f, -1.5f));
}

TEST(LayerLayout, SubFrustumSpansItsRectangle) {
    const trace::FrustumTangents view{-1.0f, 1.0f, 0.75f, -0.75f};
    const trace::FrustumTangents sub =
        render::subFrustum(view, 800, 600, {{200.0f, 150.0f}, {400.0f, 300.0f}});
    EXPECT_FLOAT_EQ(sub.left, -0.5f);
    EXPECT_FLOAT_EQ(sub.right, 0.5f);
    EXPECT_FLOAT_EQ(sub.up, 0.375f);
    EXPECT_FLOAT_EQ(sub.down, -0.375f);
    // And back: a symmetric camera's push gives its tangents.
    const shaders::trace::CameraPush c = trace::cameraPush(scene::Camera{}, view);
    const trace::FrustumTangents t = render::tangentsOf(c);
    EXPECT_FLOAT_EQ(t.left, -1.0f);
    EXPECT_FLOAT_EQ(t.up, 0.75f);
}

} // namespace
} // namespace gt::foveation
