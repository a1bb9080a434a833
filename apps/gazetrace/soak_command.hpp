#pragma once
// `gazetrace soak`: many frames of the renderer with the gaze and the settings changing all the
// time, Khronos validation and synchronisation validation on, resident memory sampled as it
// goes. It fails (exit 1, one line) on any validation error or when resident memory
// grows by more than --max-growth percent from the end of the warm-up to the last frame.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace gt::app {

struct SoakOptions {
    std::string scene = "builtin:market";
    // The animated phase's scene (the shipped sample, relative to the repository).
    std::string animatedScene = "content/animated/moving_parts.gltf";
    bool animatedSceneGiven = false;
    uint32_t frames = 1000;
    uint32_t width = 1920, height = 1080; // the desktop profile's screen
    double maxGrowthPercent = 5.0;
    std::string cacheDir;
    std::string json; // also write the results here
    bool quiet = false;
};

// The results; throws gt::Error when the soak failed (after writing the JSON).
nlohmann::json runSoak(const SoakOptions& options);

} // namespace gt::app
