#pragma once
// The Vulkan instance, debug messenger, chosen physical device, logical device, one
// compute+graphics queue, the memory allocator and one-shot submission. Owns all of them (RAII).
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "vk/allocator.hpp"
#include "vk/device_selector.hpp"

namespace gt::vk {

struct ContextOptions {
    bool validation = false; // VK_LAYER_KHRONOS_validation + messenger
    bool synchronizationValidation =
        false;                    // VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION
    DeviceRequest deviceOverride; // automatic(): the automatic choice
    bool announceDevice = true;   // print the chosen device on stderr
    // Extensions beyond gazetrace's own: a window system's (glfwGetRequiredInstanceExtensions),
    // VK_KHR_swapchain, what an OpenXR runtime asks for.
    std::vector<std::string> instanceExtensions;
    std::vector<std::string> deviceExtensions;
    // Creates the surface the chosen device must present to, once the instance exists (a GLFW
    // window's). The context owns it from then on and destroys it before the instance.
    std::function<VkSurfaceKHR(VkInstance)> createSurface;
    // Someone else creates the instance and the device from gazetrace's create infos and picks
    // the physical device (OpenXR's XR_KHR_vulkan_enable2: xrCreateVulkanInstanceKHR,
    // xrGetVulkanGraphicsDevice2KHR, xrCreateVulkanDeviceKHR). Each returns the handle or throws.
    std::function<VkInstance(const VkInstanceCreateInfo&)> createInstance;
    std::function<VkPhysicalDevice(VkInstance)> choosePhysicalDevice;
    std::function<VkDevice(VkPhysicalDevice, const VkDeviceCreateInfo&)> createDevice;
};

// Counts what the validation layer reports; tests fail on any error.
struct ValidationCounters {
    std::atomic<uint32_t> errors{0};
    std::atomic<uint32_t> warnings{0};
    std::mutex mutex;
    std::vector<std::string> messages; // errors only, in order
    // An OpenXR runtime's compositor runs in this process on this device and makes its own
    // Vulkan calls inside xr* calls: what validation reports meanwhile is the runtime's.
    std::atomic<int> runtimeCallDepth{0};
    std::atomic<uint32_t> runtimeErrors{0};
};

class Context {
public:
    explicit Context(const ContextOptions& options = {});
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    [[nodiscard]] VkInstance instance() const noexcept { return mInstance; }
    [[nodiscard]] VkPhysicalDevice physicalDevice() const noexcept { return mPhysicalDevice; }
    [[nodiscard]] VkDevice device() const noexcept { return mDevice; }
    [[nodiscard]] VkQueue queue() const noexcept { return mQueue; }
    [[nodiscard]] uint32_t queueFamily() const noexcept { return mQueueFamily; }
    // The surface of ContextOptions::createSurface (VK_NULL_HANDLE without one).
    [[nodiscard]] VkSurfaceKHR surface() const noexcept { return mSurface; }
    [[nodiscard]] const VkPhysicalDeviceProperties& properties() const noexcept { return mProps; }
    [[nodiscard]] std::string deviceName() const { return mProps.deviceName; }
    [[nodiscard]] std::string deviceDescription() const; // "name (type, driver)"
    [[nodiscard]] Allocator& allocator() noexcept { return *mAllocator; }
    [[nodiscard]] bool validationEnabled() const noexcept { return mMessenger != VK_NULL_HANDLE; }
    [[nodiscard]] uint32_t validationErrors() const noexcept { return mCounters.errors.load(); }
    [[nodiscard]] uint32_t validationWarnings() const noexcept { return mCounters.warnings.load(); }
    [[nodiscard]] std::vector<std::string> validationMessages();

    // While one lives, validation errors count as the OpenXR runtime's (its calls into Vulkan
    // from inside an xr* call), not gazetrace's: runtimeValidationErrors(), logged as warnings.
    class RuntimeCallScope {
    public:
        explicit RuntimeCallScope(ValidationCounters& c) : mCounters(c) { ++c.runtimeCallDepth; }
        ~RuntimeCallScope() { --mCounters.runtimeCallDepth; }
        RuntimeCallScope(const RuntimeCallScope&) = delete;
        RuntimeCallScope& operator=(const RuntimeCallScope&) = delete;

    private:
        ValidationCounters& mCounters;
    };
    [[nodiscard]] RuntimeCallScope runtimeCalls() { return RuntimeCallScope(mCounters); }
    [[nodiscard]] uint32_t runtimeValidationErrors() const noexcept {
        return mCounters.runtimeErrors.load();
    }

    // Records with `record`, submits, and waits: for uploads, readbacks and tests.
    void submitAndWait(const std::function<void(VkCommandBuffer)>& record);

    // VK_EXT_debug_utils names; no-ops when the extension is absent.
    void setName(VkObjectType type, uint64_t handle, const std::string& name) const;
    void beginLabel(VkCommandBuffer cmd, const std::string& name) const;
    void endLabel(VkCommandBuffer cmd) const;
    void pushDescriptorSet(VkCommandBuffer cmd, VkPipelineBindPoint bindPoint,
                           VkPipelineLayout layout, uint32_t set, uint32_t count,
                           const VkWriteDescriptorSet* writes) const;

    // Lists the Vulkan devices seen by the loader, one line each (for `gazetrace devices`);
    // throws when there is no instance or no device.
    [[nodiscard]] static std::vector<std::string> listDevices();

private:
    void createInstance(const ContextOptions& options);
    void pickPhysicalDevice(const ContextOptions& options);
    void createDevice(const ContextOptions& options);
    void release() noexcept;

    VkInstance mInstance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT mMessenger = VK_NULL_HANDLE;
    VkSurfaceKHR mSurface = VK_NULL_HANDLE;
    VkPhysicalDevice mPhysicalDevice = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties mProps{};
    std::string mDriverInfo;
    VkDevice mDevice = VK_NULL_HANDLE;
    VkQueue mQueue = VK_NULL_HANDLE;
    uint32_t mQueueFamily = 0;
    VkCommandPool mCommandPool = VK_NULL_HANDLE;
    VkFence mFence = VK_NULL_HANDLE;
    std::unique_ptr<Allocator> mAllocator;
    bool mDebugUtils = false;
    PFN_vkSetDebugUtilsObjectNameEXT mSetName = nullptr;
    PFN_vkCmdBeginDebugUtilsLabelEXT mBeginLabel = nullptr;
    PFN_vkCmdEndDebugUtilsLabelEXT mEndLabel = nullptr;
    PFN_vkCmdPushDescriptorSetKHR mPushDescriptorSet = nullptr;
    ValidationCounters mCounters;
};

} // namespace gt::vk
