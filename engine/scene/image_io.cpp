#include "scene/image_io.hpp"

#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>

#include <stb_image.h>
#include <stb_image_write.h>

#include "core/error.hpp"

namespace gt::image {

void writePngAtomic(const std::filesystem::path& path, uint32_t width, uint32_t height,
                    std::span<const uint8_t> rgba) {
    if (width == 0 || height == 0 || rgba.size() != static_cast<std::size_t>(width) * height * 4) {
        throw Error("cannot write " + path.string() + ": image size does not match its data");
    }
    const std::filesystem::path dir = path.parent_path().empty() ? "." : path.parent_path();
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) {
        throw Error("cannot write " + path.string() + ": folder " + dir.string() +
                    " does not exist");
    }
    const std::filesystem::path tmp =
        dir / ("." + path.filename().string() + ".tmp" + std::to_string(std::random_device{}()));
    const int ok = stbi_write_png(tmp.c_str(), static_cast<int>(width), static_cast<int>(height), 4,
                                  rgba.data(), static_cast<int>(width * 4));
    if (!ok) {
        std::filesystem::remove(tmp, ec);
        throw Error("cannot write " + path.string() + " (disk full or no permission?)");
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw Error("cannot write " + path.string() + ": " + ec.message());
    }
}

DecodedImage decode(std::span<const uint8_t> bytes, const std::string& what) {
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
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw LoadError(path.string() + ": cannot open");
    }
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
    if (!in && !in.eof()) {
        throw LoadError(path.string() + ": cannot read");
    }
    return bytes;
}

DecodedImage readPng(const std::filesystem::path& path) {
    return decode(readFileBytes(path), path.string());
}

} // namespace gt::image
