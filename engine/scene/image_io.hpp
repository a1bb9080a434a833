#pragma once
// PNG output that never leaves a half-written file (write to a temporary name in the same
// folder, then rename), and image decoding for textures.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace gt::image {

// `rgba` is width*height*4 bytes, top row first. Throws gt::Error naming the path on failure;
// on failure no file (neither the temporary nor the target) is left behind.
void writePngAtomic(const std::filesystem::path& path, uint32_t width, uint32_t height,
                    std::span<const uint8_t> rgba);

struct DecodedImage {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba; // 4 bytes per pixel
};

// Decodes PNG/JPEG/BMP/TGA bytes; throws gt::LoadError with stb's reason on failure.
[[nodiscard]] DecodedImage decode(std::span<const uint8_t> bytes, const std::string& what);
[[nodiscard]] DecodedImage readPng(const std::filesystem::path& path);

// A whole file's bytes; throws gt::LoadError naming the path when it cannot be opened or read.
[[nodiscard]] std::vector<uint8_t> readFileBytes(const std::filesystem::path& path);

} // namespace gt::image
