#pragma once
// Comparing 8-bit images in tests.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace gt::test {

// Mean absolute difference over every byte (RGBA8: 0-255 per channel, alpha included).
inline double meanAbsDiff(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        d += std::abs(static_cast<int>(a[i]) - static_cast<int>(b[i]));
    }
    return a.empty() ? 0.0 : d / static_cast<double>(a.size());
}

// Root-mean-square difference over the colour channels of two RGBA8 images (alpha left out).
inline double rgbRmse(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    double se = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        if (i % 4 == 3) {
            continue;
        }
        const double d = static_cast<double>(a[i]) - static_cast<double>(b[i]);
        se += d * d;
        ++n;
    }
    return n == 0 ? 0.0 : std::sqrt(se / static_cast<double>(n));
}

} // namespace gt::test
