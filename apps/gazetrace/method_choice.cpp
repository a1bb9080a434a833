#include "method_choice.hpp"

#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "core/log.hpp"
#include "foveation/point_set_cache.hpp"
#include "method_factory.hpp"
#include "option_parsing.hpp"

namespace gt::app {

std::optional<MethodKind> methodKindOf(const std::string& name) {
    if (name == "foveated") return MethodKind::Foveated;
    if (name == "layers") return MethodKind::Layers;
    if (name == "reference") return MethodKind::Reference;
    return std::nullopt;
}

std::filesystem::path cacheFolder(const std::string& cacheDir) {
    return cacheDir.empty() ? defaultCacheDir() : std::filesystem::path(cacheDir);
}

passes::InterpolateSettings interpolationOf(const std::string& interp, uint32_t k,
                                            const std::string& view) {
    passes::InterpolateSettings s;
    s.method = view.empty() ? parseInterpolation(interp) : parseView(view);
    s.k = k;
    return s;
}

std::unique_ptr<render::PointSetMethod> makePointSetMethod(render::Renderer& renderer,
                                                           const foveation::PointSetParams& params,
                                                           const std::string& cacheDir) {
    return render::makeMethod(render::PointSetConfig{params, cacheFolder(cacheDir), {}},
                              renderer.methodContext());
}

render::FullResolution& MethodChoice::reference(const passes::ReferenceSettings& settings) {
    if (!mReference) {
        mReference =
            render::makeMethod(render::FullResolutionConfig{settings}, mRenderer.methodContext());
    }
    mReference->settings = settings;
    return *mReference;
}

render::EccentricityLayers&
MethodChoice::layers(const render::EccentricityLayerSettings& settings) {
    std::optional<std::pair<uint32_t, uint32_t>> key;
    if (settings.display) key = {settings.display->width, settings.display->height};
    auto& slot = mLayers[key];
    if (!slot) {
        slot = render::makeMethod(render::LayersConfig{settings}, mRenderer.methodContext());
    }
    return *slot;
}

render::PointSetMethod&
MethodChoice::pointSet(const foveation::PointSetParams& params,
                       const std::function<void(render::PointSetMethod&, double ms)>& built) {
    if (mBackground.pending(params)) {
        // Asked for off the frame thread before: wait for that one rather than make it twice.
        return adopt(params, *mBackground.take(params, true), built);
    }
    auto& slot = mPointSets[pointSetKey(params)];
    if (!slot) {
        const auto t = std::chrono::steady_clock::now();
        slot = makePointSetMethod(mRenderer, params, mCacheDir);
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
        if (built) built(*slot, ms);
    }
    return *slot;
}

render::PointSetMethod* MethodChoice::pointSetIfReady(
    const foveation::PointSetParams& params,
    const std::function<void(render::PointSetMethod&, double ms)>& built) {
    const PointSetKey key = pointSetKey(params);
    if (const auto it = mPointSets.find(key); it != mPointSets.end()) return it->second.get();
    const bool first = mAsked.emplace(key, std::chrono::steady_clock::now()).second;
    std::optional<foveation::CachedPointSet> ready = mBackground.take(params);
    if (!ready) {
        if (first) {
            log::info("point set for " + std::to_string(params.display.width) + "x" +
                      std::to_string(params.display.height) + " at scale " +
                      std::to_string(params.scale) +
                      " is being generated off the frame thread; the full-resolution reference "
                      "is shown until it is ready");
        }
        return nullptr;
    }
    return &adopt(params, std::move(*ready), built);
}

render::PointSetMethod&
MethodChoice::adopt(const foveation::PointSetParams& params, foveation::CachedPointSet ready,
                    const std::function<void(render::PointSetMethod&, double ms)>& built) {
    const PointSetKey key = pointSetKey(params);
    if (!ready.warning.empty()) log::warn(ready.warning);
    auto& slot = mPointSets[key];
    slot = std::make_unique<render::PointSetMethod>(mRenderer.methodContext(), std::move(ready.set),
                                                    ready.seconds * 1e3);
    const auto now = std::chrono::steady_clock::now();
    const auto asked = mAsked.find(key);
    const double ms = std::chrono::duration<double, std::milli>(
                          now - (asked != mAsked.end() ? asked->second : now))
                          .count();
    if (asked != mAsked.end()) mAsked.erase(asked);
    if (built) built(*slot, ms);
    return *slot;
}

} // namespace gt::app
