#include "method_choice.hpp"

#include <chrono>
#include <cmath>

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
    const foveation::DisplayProfile& d = params.display;
    auto& slot =
        mPointSets[{d.width, d.height, std::lround(d.viewingDistance * 1e4), params.scale}];
    if (!slot) {
        const auto t = std::chrono::steady_clock::now();
        slot = makePointSetMethod(mRenderer, params, mCacheDir);
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
        if (built) built(*slot, ms);
    }
    return *slot;
}

} // namespace gt::app
