#include "scene/image_io.hpp"

#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <stb_image.h>
#include <stb_image_write.h>

#include "atomic_write.hpp"
#include "core/error.hpp"
#include "core/input.hpp"
#include "limits.hpp"

namespace gt::image {

void writePngAtomic(const std::filesystem::path& path, uint32_t width, uint32_t height,
                    std::span<const uint8_t> rgba) {
    if (width == 0 || height == 0 || rgba.size() != static_cast<std::size_t>(width) * height * 4) {
        throw Error("cannot write " + path.string() + ": image size does not match its data");
    }
    // Encoded in memory, then written through io::writeFileAtomic, which checks that every byte
    // reached the disk: stbi_write_png to a file cannot see a failing fwrite or fclose, and on a
    // full disk render printed "wrote" and left a 0-byte PNG in place of the old one.
    std::vector<std::byte> png;
    const auto append = [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<std::byte>*>(context);
        const auto* b = static_cast<const std::byte*>(data);
        out->insert(out->end(), b, b + size);
    };
    if (!stbi_write_png_to_func(append, &png, static_cast<int>(width), static_cast<int>(height), 4,
                                rgba.data(), static_cast<int>(width * 4))) {
        throw Error("cannot write " + path.string() + ": PNG encoding failed");
    }
    try {
        io::writeFileAtomic(path, png);
    } catch (const io::WriteError& e) {
        throw Error(e.what());
    }
}

std::optional<ImageSize> headerSize(std::span<const uint8_t> bytes, const std::string& what) {
    if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
        throw LoadError(what + ": too large for the image decoder");
    }
    int w = 0, h = 0, n = 0;
    if (!stbi_info_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &n) ||
        w <= 0 || h <= 0) {
        return std::nullopt;
    }
    // The header first: stb allocates the whole picture before it reads the pixels, so a
    // 100-byte PNG claiming 23000 x 23000 makes it ask for 2 GB (limits up front).
    if (static_cast<uint32_t>(w) > kMaxImageSide || static_cast<uint32_t>(h) > kMaxImageSide) {
        throw LoadError(what + ": " + std::to_string(w) + "x" + std::to_string(h) +
                        " pixels, more than the " + std::to_string(kMaxImageSide) +
                        " a side gazetrace decodes");
    }
    return ImageSize{static_cast<uint32_t>(w), static_cast<uint32_t>(h)};
}

DecodedImage decode(std::span<const uint8_t> bytes, const std::string& what) {
    (void)headerSize(bytes, what);
    int w = 0, h = 0, n = 0;
    stbi_uc* pixels =
        stbi_load_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &n, 4);
    if (!pixels) {
        throw LoadError(what + ": cannot decode image (" + stbi_failure_reason() + ")");
    }
    DecodedImage img;
    img.width = static_cast<uint32_t>(w);
    img.height = static_cast<uint32_t>(h);
    img.rgba.assign(pixels, pixels + static_cast<std::size_t>(w) * h * 4);
    stbi_image_free(pixels);
    return img;
}

std::vector<uint8_t> readFileBytes(const std::filesystem::path& path) {
    const std::string bytes = readInput(path, io::limits::kImageFileBytes);
    return {bytes.begin(), bytes.end()};
}

DecodedImage readPng(const std::filesystem::path& path) {
    return decode(readFileBytes(path), path.string());
}

} // namespace gt::image
