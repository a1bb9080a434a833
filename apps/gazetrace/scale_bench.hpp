#pragma once
// `gazetrace bench --suite scale`: how foveation's gain and cost grow with the display. For each
// headset profile, its left eye at its full pixels per eye: the thesis's point set (nearest
// neighbour and Modified Shepard, k = 10), Guenter et al. 2012's eccentricity layers and the
// full-resolution reference, each at 1 and 8 rays per point, layer pixel or pixel; the rays and
// times of each against the reference, the point set's and tables' build times and each
// method's memory. Printed, written as JSON and plotted against pixels per eye.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_command.hpp"

namespace gt::app {

struct ScaleBenchOptions {
    BenchOptions common;               // json, quick (one timed frame), scene, cache folder
    std::vector<std::string> profiles; // --hmd names; empty: every headset gazetrace knows
    uint32_t frames = 3;               // timed frames per case, after the warm-up
    std::string plot;                  // PNG; empty: beside the JSON, if any
    bool generateSets = false;         // generate every point set (time it) instead of loading
    // Every eye at this size instead of its own, its viewing distance in eye widths kept: the
    // same headset with fewer pixels (a hidden option for tests that must run in seconds).
    std::optional<std::pair<uint32_t, uint32_t>> eyeSize;
    // And at this viewing distance v (eye widths, thesis eq. 1): a narrow field seen at many
    // pixels per degree, where a small eye's point set is sparser than its pixels (hidden).
    std::optional<double> eyeDistance;
};

nlohmann::json runScaleBench(const ScaleBenchOptions& options);

// Where the plot goes: `plot` when given, else the JSON's path with extension .png (or
// _plot.png if that is the JSON itself), else nowhere (empty).
[[nodiscard]] std::string scalePlotPath(const ScaleBenchOptions& options);

} // namespace gt::app
