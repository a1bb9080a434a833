#include "scene/environment.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include <stb_image.h>

#include "checked_size.hpp"
#include "core/error.hpp"
#include "limits.hpp"
#include "scene/image_io.hpp"
#include "scene/radiance_hdr.hpp"

namespace gt::scene {

namespace {

// Radiance pictures go through gt's strict reader (radiance_hdr.hpp explains why), anything
// else through stb_image.
RgbImage loadFloat(const std::filesystem::path& p) {
    // Through the shared input rule: a regular file of bounded size only.
    const std::vector<std::uint8_t> file = image::readFileBytes(p);
    const std::span<const std::uint8_t> bytes(file);
    if (isRadianceHdr(bytes)) {
        return decodeRadianceHdr(bytes, p.string());
    }
    if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
        throw LoadError(p.string() + ": too large for the image decoder");
    }
    int w = 0, h = 0, n = 0;
    // The size from the header, checked before stb takes the picture's memory.
    if (stbi_info_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &n)) {
        const auto pixels =
            io::checkedMul(static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(h));
        if (!pixels || *pixels > io::limits::kSkyPixels) {
            throw LoadError(p.string() + ": " + std::to_string(w) + "x" + std::to_string(h) +
                            " pixels, more than the 16384x8192 gazetrace reads");
        }
    }
    float* data =
        stbi_loadf_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &n, 3);
    if (!data)
        throw LoadError(p.string() + ": cannot decode image (" + stbi_failure_reason() + ")");
    RgbImage img{w, h, std::vector<float>(data, data + static_cast<std::size_t>(w) * h * 3)};
    stbi_image_free(data);
    return img;
}

glm::vec3 fetch(const RgbImage& img, int x, int y) {
    x = std::clamp(x, 0, img.width - 1);
    y = std::clamp(y, 0, img.height - 1);
    const float* p = &img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3];
    return {p[0], p[1], p[2]};
}

glm::vec3 bilinear(const RgbImage& img, float u, float v) {
    const float x = u * static_cast<float>(img.width) - 0.5f,
                y = v * static_cast<float>(img.height) - 0.5f;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
    return glm::mix(glm::mix(fetch(img, x0, y0), fetch(img, x0 + 1, y0), fx),
                    glm::mix(fetch(img, x0, y0 + 1), fetch(img, x0 + 1, y0 + 1), fx), fy);
}

// Cube-map face lookup in the usual (OpenGL) convention, faces stored top row first.
glm::vec3 sampleCube(const std::array<RgbImage, 6>& faces, glm::vec3 d) {
    const glm::vec3 a = glm::abs(d);
    int face;
    float sc, tc, ma;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x > 0 ? 0 : 1;
        ma = a.x;
        sc = d.x > 0 ? -d.z : d.z;
        tc = -d.y;
    } else if (a.y >= a.z) {
        face = d.y > 0 ? 2 : 3;
        ma = a.y;
        sc = d.x;
        tc = d.y > 0 ? d.z : -d.z;
    } else {
        face = d.z > 0 ? 4 : 5;
        ma = a.z;
        sc = d.z > 0 ? d.x : -d.x;
        tc = -d.y;
    }
    return bilinear(faces[static_cast<std::size_t>(face)], 0.5f * (sc / ma + 1.0f),
                    0.5f * (tc / ma + 1.0f));
}

glm::vec3 equirectDirection(float u, float v) {
    const float phi = (u - 0.5f) * 2.0f * std::numbers::pi_v<float>;
    const float theta = v * std::numbers::pi_v<float>;
    return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

} // namespace

namespace {

// Halves `img` with a 2 x 2 box filter (odd edges dropped) until its width is within the limit.
void halveToLimit(RgbImage& img, uint32_t maxWidth) {
    while (img.width > static_cast<int>(maxWidth) && img.width >= 2 && img.height >= 2) {
        const int w = img.width / 2, h = img.height / 2;
        std::vector<float> out(static_cast<std::size_t>(w) * h * 3);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                for (int c = 0; c < 3; ++c) {
                    auto at = [&](int xx, int yy) {
                        return img.rgb[(static_cast<std::size_t>(yy) * img.width + xx) * 3 + c];
                    };
                    out[(static_cast<std::size_t>(y) * w + x) * 3 + c] =
                        0.25f * (at(2 * x, 2 * y) + at(2 * x + 1, 2 * y) + at(2 * x, 2 * y + 1) +
                                 at(2 * x + 1, 2 * y + 1));
                }
            }
        }
        img.rgb = std::move(out);
        img.width = w;
        img.height = h;
    }
}

void note(std::vector<std::string>* warnings, const std::string& line) {
    if (warnings) warnings->push_back(line);
}

} // namespace

Environment loadEnvironment(const std::filesystem::path& path, std::vector<std::string>* warnings,
                            uint32_t maxWidth) {
    maxWidth = std::max(maxWidth, 2u);
    std::error_code ec;
    Environment env;
    env.name = path.string();
    std::filesystem::path facePrefix;
    if (std::filesystem::is_directory(path, ec)) {
        for (const char* candidate : {"m0_", ""}) {
            if (std::filesystem::exists(path / (std::string(candidate) + "px.hdr"), ec)) {
                facePrefix = path / candidate;
                break;
            }
        }
        if (facePrefix.empty())
            throw LoadError(path.string() + ": no cube faces (px.hdr ...) in this folder");
    } else {
        const std::string stem = path.stem().string();
        if (stem.size() >= 2 &&
            (stem.ends_with("px") || stem.ends_with("nx") || stem.ends_with("py") ||
             stem.ends_with("ny") || stem.ends_with("pz") || stem.ends_with("nz"))) {
            facePrefix = path.parent_path() / stem.substr(0, stem.size() - 2);
        }
    }
    if (!facePrefix.empty()) {
        std::array<RgbImage, 6> faces;
        const char* names[6] = {"px", "nx", "py", "ny", "pz", "nz"};
        for (int i = 0; i < 6; ++i) {
            faces[static_cast<std::size_t>(i)] = loadFloat(facePrefix.string() + names[i] + ".hdr");
        }
        const int size = faces[0].width;
        for (const RgbImage& f : faces) {
            if (f.width != size || f.height != size)
                throw LoadError(path.string() + ": cube faces differ in size or are not square");
        }
        env.width = std::min(static_cast<uint32_t>(4 * size), maxWidth);
        env.height = env.width / 2;
        if (env.width < static_cast<uint32_t>(4 * size)) {
            note(warnings, path.string() + ": cube faces of " + std::to_string(size) +
                               " pixels resampled to a " + std::to_string(env.width) + "x" +
                               std::to_string(env.height) + " sky (the limit)");
        }
        env.texels.resize(static_cast<std::size_t>(env.width) * env.height);
        for (uint32_t y = 0; y < env.height; ++y) {
            for (uint32_t x = 0; x < env.width; ++x) {
                const glm::vec3 d = equirectDirection(
                    (static_cast<float>(x) + 0.5f) / static_cast<float>(env.width),
                    (static_cast<float>(y) + 0.5f) / static_cast<float>(env.height));
                env.texels[static_cast<std::size_t>(y) * env.width + x] =
                    glm::vec4(sampleCube(faces, d), 1.0f);
            }
        }
        return env;
    }
    RgbImage img = loadFloat(path);
    if (img.width != 2 * img.height) {
        throw LoadError(path.string() +
                        ": an equirectangular environment must be twice as wide as high (" +
                        std::to_string(img.width) + "x" + std::to_string(img.height) + ")");
    }
    if (img.width > static_cast<int>(maxWidth)) {
        const int before = img.width, beforeH = img.height;
        halveToLimit(img, maxWidth);
        note(warnings, path.string() + ": " + std::to_string(before) + "x" +
                           std::to_string(beforeH) + " sky downsampled to " +
                           std::to_string(img.width) + "x" + std::to_string(img.height) +
                           " (the limit is " + std::to_string(maxWidth) + " wide)");
    }
    env.width = static_cast<uint32_t>(img.width);
    env.height = static_cast<uint32_t>(img.height);
    env.texels.resize(static_cast<std::size_t>(img.width) * img.height);
    for (std::size_t i = 0; i < env.texels.size(); ++i) {
        env.texels[i] = glm::vec4(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2], 1.0f);
    }
    return env;
}

glm::vec3 sampleEnvironment(const Environment& env, glm::vec3 d) {
    const float pi = std::numbers::pi_v<float>;
    // At the poles the azimuth is undefined (GLSL's atan(0, 0) is): pin it to u = 0.5.
    const bool pole = std::abs(d.x) + std::abs(d.z) < 1e-12f;
    const float u = pole ? 0.5f : 0.5f + std::atan2(d.x, -d.z) / (2.0f * pi);
    const float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / pi;
    const float x = u * static_cast<float>(env.width) - 0.5f,
                y = v * static_cast<float>(env.height) - 0.5f;
    const float fx0 = std::floor(x), fy0 = std::floor(y);
    const float ax = x - fx0, ay = y - fy0;
    const int w = static_cast<int>(env.width), h = static_cast<int>(env.height);
    auto at = [&](int xi, int yi) {
        xi = ((xi % w) + w) % w;
        yi = std::clamp(yi, 0, h - 1);
        return glm::vec3(env.texels[static_cast<std::size_t>(yi) * env.width + xi]);
    };
    const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
    return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), ax),
                    glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), ax), ay);
}

} // namespace gt::scene
