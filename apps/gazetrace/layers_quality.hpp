#pragma once
// `gazetrace bench --suite layers`, the picture side: eccentricity layers (Guenter et al. 2012)
// against the point-set method (the thesis) and a uniform render with the same rays, per
// eccentricity band — a still view against a many-ray reference, a moving camera, and smooth
// pursuit over a still scene (with and without geometric LOD).
#include <nlohmann/json.hpp>

namespace gt::app {

struct LayerQualityOptions {
    bool quick = false; // fewer frames and reference rays (a smoke run)
    std::string scene = "builtin:market";
    std::string lodScene = "builtin:gallery"; // the pursuit with and without LOD
    std::string cacheDir;
};

[[nodiscard]] nlohmann::json measureLayerQuality(const LayerQualityOptions& options);
void printLayerQuality(const nlohmann::json& quality);

} // namespace gt::app
