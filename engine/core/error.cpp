#include "core/error.hpp"

#include <filesystem>

namespace gt {

VulkanError::VulkanError(VkResult result, const char* expr, const char* file, int line)
    : Error(std::string(expr) + " failed with " + toString(result) + " (" +
            std::filesystem::path(file).filename().string() + ":" + std::to_string(line) + ")"),
      mResult(result) {}

const char* toString(VkResult result) noexcept {
    switch (result) {
#define GT_CASE(x)                                                                                 \
    case x:                                                                                        \
        return #x;
        GT_CASE(VK_SUCCESS)
        GT_CASE(VK_NOT_READY)
        GT_CASE(VK_TIMEOUT)
        GT_CASE(VK_INCOMPLETE)
        GT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        GT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        GT_CASE(VK_ERROR_INITIALIZATION_FAILED)
        GT_CASE(VK_ERROR_DEVICE_LOST)
        GT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        GT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        GT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        GT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        GT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        GT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        GT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        GT_CASE(VK_ERROR_FRAGMENTED_POOL)
        GT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
        GT_CASE(VK_ERROR_SURFACE_LOST_KHR)
        GT_CASE(VK_ERROR_OUT_OF_DATE_KHR)
        GT_CASE(VK_SUBOPTIMAL_KHR)
#undef GT_CASE
    default:
        return "VK_ERROR_(unknown)";
    }
}

} // namespace gt
