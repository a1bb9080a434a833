#pragma once
// PNG output that never leaves a half-written file (write to a temporary name in the same
// folder, then rename), and image decoding for textures.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace gt::image {

// Textures are box-filtered to 2048 anyway; 16384 a side (1 GiB decoded) is past any real one.
inline constexpr uint32_t kMaxImageSide = 16384;

// `rgba` is width*height*4 bytes, top row first. Throws gt::Error naming the path on failure;
// on failure no file (neither the temporary nor the target) is left behind.
void writePngAtomic(const std::filesystem::path& path, uint32_t width, uint32_t height,
                    std::span<const uint8_t> rgba);

struct DecodedImage {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba; // 4 bytes per pixel
};

struct ImageSize {
    uint32_t width = 0, height = 0;
};

// The size an image's header claims, read without decoding; nullopt when stb cannot read the
// header. Throws gt::LoadError naming `what` past kMaxImageSide pixels a side.
[[nodiscard]] std::optional<ImageSize> headerSize(std::span<const uint8_t> bytes,
                                                  const std::string& what);

// Decodes PNG/JPEG/BMP/TGA bytes; throws gt::LoadError with stb's reason on failure, naming
// `what`, and before decoding when the header claims more than kMaxImageSide pixels a side.
[[nodiscard]] DecodedImage decode(std::span<const uint8_t> bytes, const std::string& what);
[[nodiscard]] DecodedImage readPng(const std::filesystem::path& path);

// A whole file's bytes, through io::readInputFile (a regular file of at most
// io::limits::kImageFileBytes); throws gt::LoadError naming the path when it cannot be read.
[[nodiscard]] std::vector<uint8_t> readFileBytes(const std::filesystem::path& path);

} // namespace gt::image
