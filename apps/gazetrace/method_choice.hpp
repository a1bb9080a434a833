#pragma once
// Which foveation method a front end renders with, and the methods themselves, built once per
// display and kept while the run lasts: the thesis's point set (one per display and scale, cached
// on disk), Guenter et al. 2012's eccentricity layers (one per screen geometry) and the
// full-resolution reference. `render`, `demo`, `xr` and `eval` choose through here.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>

#include "eccentricity_layers.hpp"
#include "foveation/contrast_sensitivity.hpp"
#include "foveation/point_set.hpp"
#include "full_resolution.hpp"
#include "point_set_method.hpp"
#include "renderer.hpp"

namespace gt::app {

enum class MethodKind { Foveated, Layers, Reference };

// "foveated" | "layers" | "reference"; empty for any other name (each front end words its own
// error for it).
[[nodiscard]] std::optional<MethodKind> methodKindOf(const std::string& name);

// The point-set cache folder: --cache, or the default one.
[[nodiscard]] std::filesystem::path cacheFolder(const std::string& cacheDir);

// The interpolation of the thesis's point set from --interp and --k; a debug --view (points,
// cells, eccentricity) takes the interpolation's place.
[[nodiscard]] passes::InterpolateSettings interpolationOf(const std::string& interp, uint32_t k,
                                                          const std::string& view);

// The point-set method for `params` (loaded from, or generated into, the cache folder).
[[nodiscard]] std::unique_ptr<render::PointSetMethod>
makePointSetMethod(render::Renderer& renderer, const foveation::PointSetParams& params,
                   const std::string& cacheDir);

class MethodChoice {
public:
    MethodChoice(render::Renderer& renderer, std::string cacheDir)
        : mRenderer(renderer), mCacheDir(std::move(cacheDir)) {}

    // The reference with these settings (built on first use).
    render::FullResolution& reference(const passes::ReferenceSettings& settings);
    // The layers for this screen geometry (settings.display; none: each view's own frustum),
    // built on first use with these settings.
    render::EccentricityLayers& layers(const render::EccentricityLayerSettings& settings);
    // The point set of this display and scale, built on first use; `built` hears of each build
    // with its milliseconds. Its settings stay the caller's to set.
    render::PointSetMethod&
    pointSet(const foveation::PointSetParams& params,
             const std::function<void(render::PointSetMethod&, double ms)>& built = {});

private:
    render::Renderer& mRenderer;
    std::string mCacheDir;
    std::unique_ptr<render::FullResolution> mReference;
    std::map<std::optional<std::pair<uint32_t, uint32_t>>,
             std::unique_ptr<render::EccentricityLayers>>
        mLayers;
    // Viewing distance to 1e-4 display widths: a runtime's per-frame float noise in an eye's
    // field of view must not rebuild the set.
    std::map<std::tuple<uint32_t, uint32_t, long, double>, std::unique_ptr<render::PointSetMethod>>
        mPointSets;
};

} // namespace gt::app
