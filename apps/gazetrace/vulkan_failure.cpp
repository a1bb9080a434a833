#include "vulkan_failure.hpp"

namespace gt::app {

namespace {
// The options every rendering command has that shrink what the device must hold.
constexpr const char* kSmaller =
    "try a smaller --width/--height (demo: the window; xr: --resolution-scale), fewer --spp or "
    "--rays-per-point, or --method foveated";
} // namespace

std::string vulkanFailureMessage(const VulkanError& error) {
    switch (error.result()) {
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
        return std::string("out of GPU memory: ") + error.what() + "; " + kSmaller;
    case VK_ERROR_OUT_OF_HOST_MEMORY:
        return std::string("out of memory: ") + error.what() + "; " + kSmaller;
    case VK_ERROR_DEVICE_LOST:
        return std::string("the GPU stopped responding (a driver reset, often after one frame ran "
                           "too long): ") +
               error.what() + "; " + kSmaller + ", and see the driver's log (dmesg)";
    default:
        return error.what();
    }
}

} // namespace gt::app
