#pragma once
// Upscaling a low-resolution render to the display (the uniform baseline of picture-quality
// comparisons): bilinear, and Catmull-Rom bicubic (sharper, the better filter reported beside
// it). Pixel centres align (a source pixel covers dst/src destination pixels); edges clamp.
#include <cstdint>

#include "image.hpp"

namespace gt::quality {

enum class Upscale { Bilinear, CatmullRom };

[[nodiscard]] RgbaImage upscale(const RgbaImage& src, uint32_t width, uint32_t height,
                                Upscale filter);

} // namespace gt::quality
