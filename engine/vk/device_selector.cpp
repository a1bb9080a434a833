#include "vk/device_selector.hpp"

#include <algorithm>
#include <cctype>

namespace gt::vk {

int typeRank(VkPhysicalDeviceType type) noexcept {
    switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
        return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
        return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
        return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
        return 1;
    default:
        return 0;
    }
}

const char* typeName(VkPhysicalDeviceType type) noexcept {
    switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
        return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
        return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
        return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
        return "cpu";
    default:
        return "other";
    }
}

namespace {
std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

std::string unsuitableReason(const DeviceCandidate& c) {
    if (c.apiVersion < VK_API_VERSION_1_3) return "needs Vulkan 1.3";
    if (!c.hasComputeQueue) return "no queue for compute (and presenting to the window)";
    if (!c.hasRequiredExtensions) return "missing VK_KHR_push_descriptor or a display extension";
    if (!c.hasRequiredFeatures) return "missing synchronization2 or timeline features";
    return {};
}
} // namespace

DeviceChoice chooseDevice(const std::vector<DeviceCandidate>& candidates,
                          const DeviceRequest& request) {
    DeviceChoice choice;
    if (candidates.empty()) {
        choice.error = "no Vulkan device found (install mesa-vulkan-drivers for lavapipe)";
        return choice;
    }
    std::vector<std::size_t> suitable;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        const std::string reason = unsuitableReason(candidates[i]);
        if (reason.empty()) {
            suitable.push_back(i);
        } else {
            choice.rejected.push_back(candidates[i].name + ": " + reason);
        }
    }
    if (!request.automatic()) {
        std::optional<std::size_t> match;
        if (request.index) {
            if (*request.index < candidates.size()) match = request.index;
        } else {
            for (std::size_t i = 0; i < candidates.size() && !match; ++i) {
                if (lower(candidates[i].name).find(lower(request.nameContains)) !=
                    std::string::npos)
                    match = i;
            }
        }
        if (!match) {
            choice.error = "the requested " + request.describe() + " matches none of the " +
                           std::to_string(candidates.size()) + " Vulkan device(s)";
            return choice;
        }
        if (std::find(suitable.begin(), suitable.end(), *match) == suitable.end()) {
            choice.error = "the requested " + request.describe() + " is " +
                           candidates[*match].name +
                           ", which is unsuitable: " + unsuitableReason(candidates[*match]);
            return choice;
        }
        choice.index = match;
        return choice;
    }
    if (suitable.empty()) {
        choice.error = "no suitable Vulkan device: " + choice.rejected.front();
        return choice;
    }
    // Stable: among equal ranks the first enumerated wins.
    choice.index =
        *std::max_element(suitable.begin(), suitable.end(), [&](std::size_t a, std::size_t b) {
            return typeRank(candidates[a].type) < typeRank(candidates[b].type);
        });
    return choice;
}

} // namespace gt::vk
