#pragma once
// `gazetrace layers`: Guenter et al. 2012's layer optimisation (section 4.3) for a display profile
// — the radii, sampling factors, sizes and pixel counts of the layers that minimise eq. (5), and
// the predicted speed-up P*/P; with --fov-table, Figure 12's speed-up against the field of view.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "eccentricity_layers.hpp"

namespace gt::app {

struct LayersOptions {
    std::string profile = "desktop"; // desktop | fove | vive | paper (the paper's monitor)
    std::string slope = "A";         // A | B | a positive MAR slope
    uint32_t layers = 3;
    std::string weights = "unit"; // unit (the paper's predictions) | half-rate (its measurement)
    uint32_t steps = 400;         // grid divisions of (0, e*) for the brute force
    bool fovTable = false;        // Figure 12: 20..120 degrees, omega* = omega0, aspect 3/4
};

[[nodiscard]] nlohmann::json runLayers(const LayersOptions& options);

// `--method layers` of render, demo and xr: the settings from --slope, --layers and --spp (rays
// per layer pixel). Throws ArgumentError naming --slope for a bad slope.
[[nodiscard]] render::EccentricityLayerSettings
layerSettings(const std::string& slope, uint32_t layers, uint32_t raysPerPixel);
// The plan as text, one line per layer, for people.
[[nodiscard]] std::string layersText(const nlohmann::json& result);

} // namespace gt::app
