#pragma once
// What one interval of a trial shows, as typed values. The study library has no Vulkan: the app
// turns a Stimulus into the renderer's settings (apps/gazetrace/study_stimuli.*). The parameters
// a design may vary carry the names the render and demo commands give them, so a design reads
// like a command line.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gt::study {

// The renderer's methods, as the render command names them (--method).
enum class Method { Foveated, Layers, Reference };
// The thesis's reconstructions (--interp).
enum class Interpolation { NearestNeighbour, ModifiedShepard, Rbf };

// The settings one interval renders with. Defaults are the render command's.
struct RenderChoice {
    Method method = Method::Foveated;
    double scale = 1.0;        // --scale: the point set's scaling value (thesis 4.2)
    uint32_t raysPerPoint = 1; // --rays-per-point
    Interpolation interp = Interpolation::NearestNeighbour; // --interp
    uint32_t k = 10;                                        // --k (Modified Shepard, RBF)
    double slope = 0.0275; // --slope: the layers' MAR slope m (Guenter et al. 2012, eq. 1; mA)
    uint32_t layers = 3;   // --layers
    uint32_t spp = 1;      // --spp: the reference's rays per pixel
    bool taa = true;       // --no-taa turns it off
    bool operator==(const RenderChoice&) const = default;
};

// The parameters a study may vary, one per condition; each has the option's name, its range and
// whether a higher value foveates more (a larger scale thins the set, a steeper MAR slope drops
// resolution faster; more rays per point, more layers or a larger k foveate less).
enum class Parameter { Scale, RaysPerPoint, K, Slope, Layers };

struct ParameterInfo {
    Parameter parameter;
    std::string_view name; // the option's name without dashes: "scale", "rays-per-point", ...
    double min;
    double max;
    bool integer;
    bool higherFoveatesMore;
};

[[nodiscard]] const std::vector<ParameterInfo>& parameters();
[[nodiscard]] const ParameterInfo& infoOf(Parameter p);
// Empty when `name` names no parameter.
[[nodiscard]] std::optional<Parameter> parameterNamed(std::string_view name);
// "scale, rays-per-point, k, slope, layers": for error messages.
[[nodiscard]] std::string parameterNames();
// `base` with `p` set to `level` (rounded for integer parameters).
[[nodiscard]] RenderChoice withLevel(RenderChoice base, Parameter p, double level);

// The scene an interval shows: a scene spec as the render command takes it (builtin:market, a
// glTF path), with an optional camera ("x,y,z,tx,ty,tz") or camera path file.
struct SceneChoice {
    std::string scene = "builtin:market";
    std::string camera;
    std::string cameraPath;
    bool operator==(const SceneChoice&) const = default;
};

// One interval's picture: a condition's settings (or the reference) on a scene.
struct Stimulus {
    RenderChoice render;
    SceneChoice scene;
    bool operator==(const Stimulus&) const = default;
};

} // namespace gt::study
