#pragma once
// Which foveation method a front end renders with, and the methods themselves, built once per
// display and kept while the run lasts: the thesis's point set (one per display and scale, cached
// on disk), Guenter et al. 2012's eccentricity layers (one per screen geometry) and the
// full-resolution reference. `render`, `demo`, `xr` and `eval` choose through here.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>

#include "background_point_sets.hpp"
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
        : mRenderer(renderer), mCacheDir(std::move(cacheDir)), mBackground(cacheFolder(mCacheDir)) {
    }

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
    // The same without waiting for the set: null until it is ready. The first call starts
    // generating it (or loading it from the cache) on a worker thread and says so once on
    // stderr; the call that finds it ready builds the method (neighbour index, GPU buffers) on
    // the caller's thread. `built` hears of it with the milliseconds from the first call.
    render::PointSetMethod*
    pointSetIfReady(const foveation::PointSetParams& params,
                    const std::function<void(render::PointSetMethod&, double ms)>& built = {});

private:
    // The method of a set generated off the frame thread, built here and kept.
    render::PointSetMethod&
    adopt(const foveation::PointSetParams& params, foveation::CachedPointSet ready,
          const std::function<void(render::PointSetMethod&, double ms)>& built);

    render::Renderer& mRenderer;
    std::string mCacheDir;
    std::unique_ptr<render::FullResolution> mReference;
    std::map<std::optional<std::pair<uint32_t, uint32_t>>,
             std::unique_ptr<render::EccentricityLayers>>
        mLayers;
    std::map<PointSetKey, std::unique_ptr<render::PointSetMethod>> mPointSets;
    // When each set generated off the frame thread was asked for.
    std::map<PointSetKey, std::chrono::steady_clock::time_point> mAsked;
    // Declared last, so destroyed first: it waits for a set still being generated while the
    // rest stands.
    BackgroundPointSets mBackground;
};

} // namespace gt::app
