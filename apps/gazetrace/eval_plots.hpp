#pragma once
// The pictures `gazetrace eval` writes beside its JSON: an error map in a perceptual colour
// ramp, grouped bars per eccentricity band, and quality-against-rays curves. The bars and the
// curves carry their axes (units, ticks and numbers), the bars' values and a legend naming each
// series in its colour, in a small built-in bitmap font (stb_easy_font); the colours are also
// listed in the JSON (`plots`).
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "quality/eccentricity_bands.hpp"
#include "quality/image.hpp"

namespace gt::app {

// The colour of series i in the bars and curves.
[[nodiscard]] std::array<uint8_t, 3> seriesColour(std::size_t i);
[[nodiscard]] std::string seriesColourHex(std::size_t i);

// FLIP errors in [0, 1] from black through purple and orange to pale yellow.
[[nodiscard]] quality::RgbaImage errorMapImage(const quality::ScalarMap& error, uint32_t width,
                                               uint32_t height);

// A rectangle of a plot, pixels, [x0, x1) x [y0, y1).
struct PlotBox {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct LegendEntry {
    std::string name;
    std::array<uint8_t, 3> colour{};
    PlotBox swatch; // filled with the colour
    PlotBox label;  // the name, in black
};

// Where a plot's parts go: the data area inside the axes, the value axis's ticks and the legend.
struct PlotLayout {
    int width = 0, height = 0;
    PlotBox area;
    double yMax = 1.0;          // the top of the value axis (a round number)
    std::vector<double> yTicks; // 0 .. yMax
    std::vector<LegendEntry> legend;
};

// The series' names as eval lists them in its JSON (`plots.series[].name`).
[[nodiscard]] std::vector<std::string> seriesNames(const nlohmann::json& plotSeries);

// One group of bars per band (x: eccentricity band in degrees), one bar per series (y: FLIP
// from 0 to at least `maxValue`), each bar's value over it, the series named in the legend.
[[nodiscard]] PlotLayout bandBarsLayout(const std::vector<std::string>& names, double maxValue);
[[nodiscard]] quality::RgbaImage
bandBars(const std::vector<std::array<double, quality::kBands>>& series, double maxValue,
         const std::vector<std::string>& names);

// The words of a curves plot: eval's quality-against-rays curves by default; `bench --suite
// scale` puts ratios against pixels per eye on the same axes.
struct CurveAxes {
    std::string title = "mean FLIP against rays (lower is better)";
    std::string yTitle = "mean FLIP (0..1)";
    std::string xTitle = "primary rays per frame (log scale)";
    std::string valueFormat = "%.3f"; // each point's value, printed beside it
    // x ticks at the data's x values instead of at 1, 2 and 5 times the powers of ten (a few
    // values close together, as headsets' pixels per eye, may have none of those between them).
    bool ticksAtData = false;
};

// Polylines of (x, value) per series; x logarithmic (rays per frame), y linear from 0 (mean
// FLIP).
[[nodiscard]] PlotLayout curvesLayout(const std::vector<std::string>& names, double maxValue);
[[nodiscard]] quality::RgbaImage
curvesImage(const std::vector<std::vector<std::pair<double, double>>>& series,
            const std::vector<std::string>& names, const CurveAxes& axes = {});

// `study analyse`'s psychometric plot, one panel per condition: each participant's proportion of
// positive answers per level (a dot whose area grows with the level's trials) and fitted curve in
// the participant's colour, and the group threshold (a black line) with its interval (grey).
struct PsychometricSeries {
    std::string name;                             // the participant's code
    std::vector<std::array<double, 3>> points;    // level, proportion positive, trials
    std::vector<std::pair<double, double>> curve; // the fit sampled: level, probability
};

struct PsychometricPanel {
    std::string title;  // the condition
    std::string xTitle; // the parameter
    double xMin = 0.0, xMax = 1.0;
    std::vector<PsychometricSeries> series;
    std::optional<std::array<double, 3>> group; // mean, low, high
};

[[nodiscard]] quality::RgbaImage psychometricImage(const std::vector<PsychometricPanel>& panels);

} // namespace gt::app
