#include "demo_settings.hpp"

namespace gt::app {

DemoDefaults demoDefaults(VkPhysicalDeviceType type) {
    if (type == VK_PHYSICAL_DEVICE_TYPE_CPU) {
        return {.interp = "nn", .k = 5, .scale = 2.0, .raysPerPoint = 1, .label = "CPU fast"};
    }
    return {.interp = "msm", .k = 10, .scale = 1.0, .raysPerPoint = 4, .label = "GPU quality"};
}

void applyDemoDefaults(DemoSettings& settings, const DemoDefaults& defaults,
                       const GivenMethodOptions& given) {
    if (!given.interp) settings.interp = defaults.interp;
    if (!given.k) settings.k = defaults.k;
    if (!given.scale) settings.scale = defaults.scale;
    if (!given.raysPerPoint && settings.method == "foveated") {
        settings.raysPerPoint = defaults.raysPerPoint;
    }
}

} // namespace gt::app
