#pragma once
// Environment images (HDR skies) for `--scene cubemap:FILE`, the thesis's experiment setup
// (thesis, 6.1): rays that miss everything sample the environment instead of the sky
// gradient. Stored as a linear RGB equirectangular image; six cube faces are resampled into
// one on load.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace gt::scene {

struct Environment {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<glm::vec4> texels; // linear RGB, row 0 = up
    std::string name;
};

// FILE.hdr (or .png/.jpg) with a 2:1 aspect: equirectangular. A face named PREFIX_px.hdr (or a
// folder holding px/nx/py/ny/pz/nz faces): a cube map. Throws gt::LoadError naming the file.
// Skies are kept to at most kMaxEnvironmentWidth x kMaxEnvironmentWidth / 2 texels (32 M; 512 MB
// as the tracer holds them): a larger one is box-filtered down by halves, a cube map resampled
// at that size, and a line saying so goes to `warnings` (16384 x 8192 did not finish;
// it also exceeds lavapipe's 128 M-element texel buffers).
inline constexpr uint32_t kMaxEnvironmentWidth = 8192;
[[nodiscard]] Environment loadEnvironment(const std::filesystem::path& path,
                                          std::vector<std::string>* warnings = nullptr,
                                          uint32_t maxWidth = kMaxEnvironmentWidth);

// Equirectangular lookup: u from the azimuth (0 at -z, growing towards +x), v from the polar
// angle (0 straight up). Bilinear, wrapping in u. The GLSL twin is in shaders/common/trace.glsl.
[[nodiscard]] glm::vec3 sampleEnvironment(const Environment& env, glm::vec3 direction);

} // namespace gt::scene
