#pragma once
// Classic image measures beside FLIP: per-pixel squared error (for PSNR), SSIM (Wang, Bovik,
// Sheikh and Simoncelli 2004: 11 x 11 Gaussian window of sigma 1.5, K1 = 0.01, K2 = 0.03, on
// the Rec. 709 luma of the sRGB values), and the bleeding of bright samples into dark pixels.
#include <cstdint>

#include "image.hpp"

namespace gt::quality {

// Mean over the three colour channels of the squared difference, in (1/255)^2 units.
[[nodiscard]] ScalarMap squaredErrorMap(const RgbaImage& reference, const RgbaImage& test);
// Mean absolute difference over the colour channels, in 1/255 units.
[[nodiscard]] ScalarMap absoluteErrorMap(const RgbaImage& reference, const RgbaImage& test);
// PSNR in dB of a mean squared error in (1/255)^2 units (99 dB when it is 0).
[[nodiscard]] double psnrDb(double meanSquaredError);
// The SSIM index of every pixel.
[[nodiscard]] ScalarMap ssimMap(const RgbaImage& reference, const RgbaImage& test);

// Pixels where the reference is dark (every channel below `darkBelow`) within `radius` pixels of
// a bright one (some channel above `brightAbove`): the pixels interpolation on linear radiance
// brightens. 1 for such a pixel, 0 elsewhere.
[[nodiscard]] std::vector<uint8_t> darkNearBrightMask(const RgbaImage& reference,
                                                      uint8_t darkBelow = 60,
                                                      uint8_t brightAbove = 200, int radius = 10);

} // namespace gt::quality
