#pragma once
// Builds a foveation method from its typed configuration (settings.hpp). The overloads for one
// method's config return that method, for the callers that read its own state back.
#include <memory>

#include "settings.hpp"

namespace gt::render {

[[nodiscard]] std::unique_ptr<FullResolution> makeMethod(const FullResolutionConfig& config,
                                                         const MethodContext& mc);
[[nodiscard]] std::unique_ptr<PointSetMethod> makeMethod(const PointSetConfig& config,
                                                         const MethodContext& mc);
[[nodiscard]] std::unique_ptr<EccentricityLayers> makeMethod(const LayersConfig& config,
                                                             const MethodContext& mc);
[[nodiscard]] std::unique_ptr<FoveationMethod> makeMethod(const MethodConfig& config,
                                                          const MethodContext& mc);

} // namespace gt::render
