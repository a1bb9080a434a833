#pragma once
// Picture quality per eccentricity band (0-5, 5-10, 10-20 and 20+ degrees from the gaze), from
// a display profile's geometry (thesis, eq. 1), and the thesis's falloff of the eye's cut-off
// frequency fc(e) / fc(0) = e2 / (e + e2) (eq. 2): at eccentricity e a pixel spans that much
// less of what the eye resolves, so FLIP there is taken at ppd * fc(0) / fc(e) pixels per degree
// (`eval`'s flip_ecc) and detail the eye cannot resolve is not counted.
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "foveation/contrast_sensitivity.hpp"
#include "image.hpp"

namespace gt::quality {

inline constexpr std::size_t kBands = 4;
inline constexpr std::array<double, kBands> kBandStartDeg{0.0, 5.0, 10.0, 20.0};
inline constexpr std::array<std::string_view, kBands> kBandNames{"0-5", "5-10", "10-20", "20+"};

// The band of every pixel of a width x height image seen on `display` (same pixel pitch and
// viewing distance) with the gaze at `gaze` (pixels, origin top-left).
[[nodiscard]] std::vector<uint8_t> bandMap(const foveation::DisplayProfile& display, uint32_t width,
                                           uint32_t height, glm::vec2 gaze);

// Mean of `map` over each band's pixels (0 for an empty band).
[[nodiscard]] std::array<double, kBands> meanPerBand(const ScalarMap& map,
                                                     const std::vector<uint8_t>& bands);
[[nodiscard]] std::array<std::size_t, kBands> pixelsPerBand(const std::vector<uint8_t>& bands);

// fc(e) / fc(0) of the thesis, eq. (2).
[[nodiscard]] double acuityFalloff(double eccentricityDeg);

} // namespace gt::quality
