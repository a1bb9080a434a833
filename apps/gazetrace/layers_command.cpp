#include "layers_command.hpp"

#include <cstdio>
#include <vector>

#include "core/error.hpp"
#include "foveation/contrast_sensitivity.hpp"
#include "foveation/eccentricity_layers.hpp"
#include "option_parsing.hpp"

namespace gt::app {

namespace {

using foveation::LayerDisplay;
using foveation::LayerPlan;
using foveation::MarModel;

LayerDisplay displayOf(const std::string& profile) {
    if (profile == "paper") {
        return LayerDisplay::paperMonitor();
    }
    return LayerDisplay::fromProfile(displayProfile(profile));
}

std::vector<double> weightsOf(const std::string& name, uint32_t layers) {
    if (name == "unit") {
        return std::vector<double>(layers, 1.0);
    }
    if (name == "half-rate") {
        return foveation::halfRateWeights(layers);
    }
    throw ArgumentError("--weights: '" + name + "' (unit or half-rate)");
}

nlohmann::json planJson(const LayerPlan& p) {
    nlohmann::json layers = nlohmann::json::array();
    for (const foveation::Layer& l : p.layers) {
        layers.push_back({{"e_deg", l.radiusDeg},
                          {"s", l.samplingFactor},
                          {"D", l.diameter},
                          {"P", l.pixels},
                          {"w", l.weight}});
    }
    return {
        {"layers", layers}, {"P", p.work}, {"P_star", p.displayPixels}, {"speedup", p.speedup()}};
}

} // namespace

render::EccentricityLayerSettings layerSettings(const std::string& slope, uint32_t layers,
                                                uint32_t raysPerPixel) {
    render::EccentricityLayerSettings s;
    s.slope = parseSlope(slope);
    s.layers = layers;
    s.raysPerPixel = raysPerPixel;
    return s;
}

nlohmann::json runLayers(const LayersOptions& o) {
    const MarModel mar{parseSlope(o.slope)};
    if (o.steps < 8 || o.steps > 4000) {
        throw ArgumentError("--steps: 8 to 4000");
    }
    if (o.fovTable) {
        // Figure 12: the display matched to foveal acuity at every field of view.
        nlohmann::json rows = nlohmann::json::array();
        for (int fov = 20; fov <= 120; fov += 10) {
            const LayerDisplay d = LayerDisplay::acuityMatched(fov);
            nlohmann::json row = {{"fov_deg", fov}, {"D_star", d.resolution}};
            for (uint32_t n = 2; n <= 4; ++n) {
                const auto w = weightsOf(o.weights, n);
                row["speedup_n" + std::to_string(n)] =
                    foveation::optimiseLayers(d, mar, n, w, n == 4 ? o.steps / 4 : o.steps)
                        .speedup();
            }
            rows.push_back(row);
        }
        return {{"figure", 12}, {"slope", mar.slope}, {"aspect", 0.75}, {"rows", rows}};
    }
    const LayerDisplay d = displayOf(o.profile);
    const std::vector<double> w = weightsOf(o.weights, o.layers);
    nlohmann::json j = planJson(foveation::optimiseLayers(d, mar, o.layers, w, o.steps));
    j["profile"] = o.profile;
    j["slope"] = mar.slope;
    j["omega0_deg"] = mar.omega0Deg;
    j["weights"] = o.weights;
    j["e_star_deg"] = d.radiusDeg();
    j["omega_star_deg"] = d.sharpnessDeg();
    j["D_star"] = d.resolution;
    j["aspect"] = d.aspect;
    return j;
}

std::string layersText(const nlohmann::json& r) {
    std::string out;
    char line[256];
    if (r.contains("rows")) {
        std::snprintf(line, sizeof(line), "Figure 12, slope %.4f: P*/P against field of view\n",
                      r["slope"].get<double>());
        out += line;
        out += "fov_deg      D*     n=2     n=3     n=4\n";
        for (const auto& row : r["rows"]) {
            std::snprintf(line, sizeof(line), "%7d %7.0f %7.2f %7.2f %7.2f\n",
                          row["fov_deg"].get<int>(), row["D_star"].get<double>(),
                          row["speedup_n2"].get<double>(), row["speedup_n3"].get<double>(),
                          row["speedup_n4"].get<double>());
            out += line;
        }
        return out;
    }
    std::snprintf(line, sizeof(line), "%s, slope %.4f: e* = %.2f deg, omega* = %.4f deg\n",
                  r["profile"].get<std::string>().c_str(), r["slope"].get<double>(),
                  r["e_star_deg"].get<double>(), r["omega_star_deg"].get<double>());
    out += line;
    out += "layer   e_deg       s        D           P\n";
    int i = 1;
    for (const auto& l : r["layers"]) {
        std::snprintf(line, sizeof(line), "%5d %7.2f %7.3f %8.1f %11.0f\n", i++,
                      l["e_deg"].get<double>(), l["s"].get<double>(), l["D"].get<double>(),
                      l["P"].get<double>());
        out += line;
    }
    std::snprintf(line, sizeof(line), "P = %.0f, P* = %.0f, predicted speed-up P*/P = %.2f\n",
                  r["P"].get<double>(), r["P_star"].get<double>(), r["speedup"].get<double>());
    out += line;
    return out;
}

} // namespace gt::app
