#pragma once
// The pictures `gazetrace eval` writes beside its JSON: an error map in a perceptual colour
// ramp, grouped bars per eccentricity band, and quality-against-rays curves. Plain rasters
// with no text: the colours are listed in the JSON (`plots`) and the README.
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "quality/eccentricity_bands.hpp"
#include "quality/image.hpp"

namespace gt::app {

// The colour of series i in the bars and curves.
[[nodiscard]] std::array<uint8_t, 3> seriesColour(std::size_t i);
[[nodiscard]] std::string seriesColourHex(std::size_t i);

// FLIP errors in [0, 1] from black through purple and orange to pale yellow.
[[nodiscard]] quality::RgbaImage errorMapImage(const quality::ScalarMap& error, uint32_t width,
                                               uint32_t height);
// One group of bars per band, one bar per series (its value over `maxValue`).
[[nodiscard]] quality::RgbaImage
bandBars(const std::vector<std::array<double, quality::kBands>>& series, double maxValue);
// Polylines of (rays, value) per series; x logarithmic over the rays, y linear from 0.
[[nodiscard]] quality::RgbaImage
curvesImage(const std::vector<std::vector<std::pair<double, double>>>& series);

} // namespace gt::app
