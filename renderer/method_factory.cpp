#include "method_factory.hpp"

namespace gt::render {

std::unique_ptr<FullResolution> makeMethod(const FullResolutionConfig& config,
                                           const MethodContext& mc) {
    return std::make_unique<FullResolution>(mc, config.settings);
}

std::unique_ptr<PointSetMethod> makeMethod(const PointSetConfig& config, const MethodContext& mc) {
    auto method = std::make_unique<PointSetMethod>(mc, config.params, config.cacheDir);
    method->settings = config.settings;
    return method;
}

std::unique_ptr<EccentricityLayers> makeMethod(const LayersConfig& config,
                                               const MethodContext& mc) {
    return std::make_unique<EccentricityLayers>(mc, config.settings);
}

std::unique_ptr<FoveationMethod> makeMethod(const MethodConfig& config, const MethodContext& mc) {
    return std::visit(
        [&](const auto& c) -> std::unique_ptr<FoveationMethod> { return makeMethod(c, mc); },
        config);
}

} // namespace gt::render
