#pragma once
// An 8-bit display-referred picture as the renderer writes it (sRGB-encoded RGBA, rows top
// first): what every picture-quality measure in engine/quality compares.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gt::quality {

struct RgbaImage {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> pixels; // 4 bytes per pixel

    [[nodiscard]] std::size_t count() const noexcept {
        return static_cast<std::size_t>(width) * height;
    }
    [[nodiscard]] uint8_t at(std::size_t pixel, int channel) const noexcept {
        return pixels[4 * pixel + static_cast<std::size_t>(channel)];
    }
};

// A per-pixel scalar map (an error or similarity map), row-major, top row first.
using ScalarMap = std::vector<float>;

} // namespace gt::quality
