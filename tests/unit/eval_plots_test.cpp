// eval's plots carry a legend naming each series in its colour, and axes with their ticks; its
// progress counts every frame the run renders.
#include <gtest/gtest.h>

#include "eval_plots.hpp"
#include "eval_progress.hpp"

namespace gt::app {
namespace {

const std::vector<std::string> kNames{"foveated", "uniform_bilinear", "uniform_catmull_rom",
                                      "full_resolution"};

// Pixels of `img` inside `box` with exactly colour `c`.
std::size_t pixelsOf(const quality::RgbaImage& img, const PlotBox& box, std::array<uint8_t, 3> c) {
    std::size_t n = 0;
    for (int y = box.y0; y < box.y1; ++y) {
        for (int x = box.x0; x < box.x1; ++x) {
            const std::size_t p = (static_cast<std::size_t>(y) * img.width + x) * 4;
            n += img.pixels[p] == c[0] && img.pixels[p + 1] == c[1] && img.pixels[p + 2] == c[2];
        }
    }
    return n;
}

bool inside(const PlotLayout& l, const PlotBox& b) {
    return b.x0 >= 0 && b.y0 >= 0 && b.x1 <= l.width && b.y1 <= l.height && b.x0 < b.x1 &&
           b.y0 < b.y1;
}

bool overlap(const PlotBox& a, const PlotBox& b) {
    return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

TEST(EvalPlots, BandBarsHaveALegendEntryPerSeriesInItsColour) {
    const PlotLayout l = bandBarsLayout(kNames, 0.2);
    ASSERT_EQ(l.legend.size(), kNames.size());
    for (std::size_t i = 0; i < kNames.size(); ++i) {
        EXPECT_EQ(l.legend[i].name, kNames[i]);
        EXPECT_EQ(l.legend[i].colour, seriesColour(i));
        EXPECT_TRUE(inside(l, l.legend[i].swatch));
        EXPECT_TRUE(inside(l, l.legend[i].label));
        EXPECT_FALSE(overlap(l.legend[i].swatch, l.area)) << "the legend hides bars";
    }
    // The value axis: from 0 to a round number at or above the largest value, with ticks.
    ASSERT_GE(l.yTicks.size(), 3u);
    EXPECT_EQ(l.yTicks.front(), 0.0);
    EXPECT_GE(l.yMax, 0.2);
    EXPECT_LE(l.yMax, 0.5);
    EXPECT_EQ(l.yTicks.back(), l.yMax);
}

TEST(EvalPlots, RenderedBarsShowTheLegendAndTheText) {
    const std::vector<std::array<double, quality::kBands>> series{
        {0.02, 0.05, 0.08, 0.1}, {0.03, 0.06, 0.09, 0.12}, {0.01, 0.02, 0.03, 0.04}};
    const std::vector<std::string> names(kNames.begin(), kNames.begin() + 3);
    const quality::RgbaImage img = bandBars(series, 0.13, names);
    const PlotLayout l = bandBarsLayout(names, 0.13);
    ASSERT_EQ(img.width, static_cast<uint32_t>(l.width));
    for (std::size_t i = 0; i < names.size(); ++i) {
        const LegendEntry& e = l.legend[i];
        const int area = (e.swatch.x1 - e.swatch.x0) * (e.swatch.y1 - e.swatch.y0);
        EXPECT_EQ(pixelsOf(img, e.swatch, e.colour), static_cast<std::size_t>(area)) << e.name;
        EXPECT_GT(pixelsOf(img, e.label, {0, 0, 0}), 20u) << e.name; // its name is written
    }
    // Tick numbers left of the value axis.
    EXPECT_GT(pixelsOf(img, {0, l.area.y0, l.area.x0 - 6, l.area.y1 + 6}, {0, 0, 0}), 50u);
    // Band labels and the axis title under it.
    EXPECT_GT(pixelsOf(img, {l.area.x0, l.area.y1 + 4, l.area.x1, l.height}, {0, 0, 0}), 100u);
}

TEST(EvalPlots, CurvesHaveALegendAndAxes) {
    const std::vector<std::vector<std::pair<double, double>>> curves{
        {{30000, 0.08}, {20000, 0.1}, {15000, 0.12}, {10000, 0.15}},
        {{30000, 0.1}, {20000, 0.13}, {15000, 0.15}, {10000, 0.2}}};
    const std::vector<std::string> names{"foveated", "uniform_bilinear"};
    const quality::RgbaImage img = curvesImage(curves, names);
    const PlotLayout l = curvesLayout(names, 0.2);
    ASSERT_EQ(l.legend.size(), 2u);
    for (const LegendEntry& e : l.legend) {
        const int area = (e.swatch.x1 - e.swatch.x0) * (e.swatch.y1 - e.swatch.y0);
        EXPECT_EQ(pixelsOf(img, e.swatch, e.colour), static_cast<std::size_t>(area)) << e.name;
    }
    EXPECT_GT(pixelsOf(img, {l.area.x0, l.area.y1 + 4, l.area.x1, l.height}, {0, 0, 0}), 100u);
}

TEST(EvalProgress, CountsEveryFrameOfTheRun) {
    EvalOptions o; // reference, 8 settling frames, uniform baselines
    EXPECT_EQ(evalFrameCount(o, false, 0), 1u + 8u + 2u);
    EXPECT_EQ(evalFrameCount(o, true, 0), 8u + 2u);
    o.temporal = true; // 7 more settling frames, then 12
    o.cameraPath = "path.csv";
    o.pursuit = "pursuit.csv";
    o.sweep = true;
    EXPECT_EQ(evalFrameCount(o, false, 5), 11u + 19u + 24u + (7u + 5u) + 4u * 10u);
    EvalProgress p(3);
    EXPECT_EQ(p.frame("reference"), "eval: frame 1/3 (reference)");
    EXPECT_EQ(p.frame("foveated"), "eval: frame 2/3 (foveated)");
}

} // namespace
} // namespace gt::app
