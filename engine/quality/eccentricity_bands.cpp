#include "eccentricity_bands.hpp"

#include <cmath>

namespace gt::quality {

std::vector<uint8_t> bandMap(const foveation::DisplayProfile& display, uint32_t width,
                             uint32_t height, glm::vec2 gaze) {
    std::vector<uint8_t> band(static_cast<std::size_t>(width) * height);
    for (uint32_t y = 0; y < height; ++y) {
        for (uint32_t x = 0; x < width; ++x) {
            const glm::vec2 d = glm::vec2(static_cast<float>(x), static_cast<float>(y)) - gaze;
            const double e = foveation::ContrastSensitivity::eccentricityDeg(
                glm::length(d), display.width, display.viewingDistance);
            std::size_t b = 0;
            while (b + 1 < kBands && e >= kBandStartDeg[b + 1]) {
                ++b;
            }
            band[static_cast<std::size_t>(y) * width + x] = static_cast<uint8_t>(b);
        }
    }
    return band;
}

std::array<double, kBands> meanPerBand(const ScalarMap& map, const std::vector<uint8_t>& bands) {
    std::array<double, kBands> sum{};
    const auto n = pixelsPerBand(bands);
    for (std::size_t p = 0; p < bands.size(); ++p) {
        sum[bands[p]] += map[p];
    }
    for (std::size_t b = 0; b < kBands; ++b) {
        sum[b] = n[b] ? sum[b] / static_cast<double>(n[b]) : 0.0;
    }
    return sum;
}

std::array<std::size_t, kBands> pixelsPerBand(const std::vector<uint8_t>& bands) {
    std::array<std::size_t, kBands> n{};
    for (const uint8_t b : bands) {
        ++n[b];
    }
    return n;
}

double acuityFalloff(double e) {
    const foveation::ContrastSensitivity csf;
    return csf.cutoffFrequency(e) / csf.cutoffFrequency(0.0);
}

} // namespace gt::quality
