#pragma once
// Physical-device choice as a pure function so it can be unit tested without a GPU:
// discrete > integrated > virtual > CPU (lavapipe), overridable by index or name substring
// (a DeviceRequest). Unsuitable devices carry the reason, in vk-bootstrap's spirit.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace gt::vk {

struct DeviceCandidate {
    std::string name;
    VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
    uint32_t apiVersion = 0;
    bool hasComputeQueue = false;
    bool hasRequiredExtensions = false;
    bool hasRequiredFeatures = false;
};

// A device asked for by its index among the enumerated devices or by a case-insensitive
// substring of its name; neither: the automatic choice.
struct DeviceRequest {
    std::optional<std::size_t> index;
    std::string nameContains;
    [[nodiscard]] bool automatic() const { return !index && nameContains.empty(); }
    [[nodiscard]] std::string describe() const {
        return index ? "device " + std::to_string(*index) : "device '" + nameContains + "'";
    }
};

struct DeviceChoice {
    std::optional<std::size_t> index;  // chosen candidate, empty when none fits
    std::vector<std::string> rejected; // "name: reason" for every unsuitable device
    std::string error;                 // why nothing was chosen
};

[[nodiscard]] int typeRank(VkPhysicalDeviceType type) noexcept;
[[nodiscard]] const char* typeName(VkPhysicalDeviceType type) noexcept;

// A request that matches nothing is an error, never ignored.
[[nodiscard]] DeviceChoice chooseDevice(const std::vector<DeviceCandidate>& candidates,
                                        const DeviceRequest& request);

} // namespace gt::vk
