#pragma once
// `gazetrace render`: one frame of a scene, headless, to a PNG.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace gt::app {

struct RenderOptions {
    std::string scene = "builtin:market";
    uint32_t width = 1280;
    uint32_t height = 720;
    uint32_t spp = 1;
    uint32_t seed = 0;
    std::string method = "reference";
    std::string out = "out/render.png";
    std::string graphDot;  // --graph FILE.dot
    bool validate = false; // Khronos validation layer
};

// Renders and writes the PNG; returns the JSON summary (device, width, height, method, rays,
// gpu_ms per pass, total_ms, output, ...). Throws gt::Error on any failure.
nlohmann::json runRender(const RenderOptions& options);

} // namespace gt::app
