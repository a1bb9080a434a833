#pragma once
// Separable convolution of scalar images with replicated borders: what FLIP's contrast and
// feature filters and SSIM's Gaussian window are built from.
#include <cstdint>
#include <vector>

#include "image.hpp"

namespace gt::quality {

// A 1-D kernel of odd length, centred.
using Kernel = std::vector<float>;

// `src` (width x height) convolved with `kx` along rows and `ky` along columns.
[[nodiscard]] ScalarMap convolveSeparable(const ScalarMap& src, uint32_t width, uint32_t height,
                                          const Kernel& kx, const Kernel& ky);

// exp(-x^2 / (2 sigma^2)) for x in [-radius, radius], normalised to sum 1.
[[nodiscard]] Kernel gaussianKernel(double sigma, int radius);

} // namespace gt::quality
