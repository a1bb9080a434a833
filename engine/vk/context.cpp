#include "vk/context.hpp"

#include <cstring>

#include "core/error.hpp"
#include "core/log.hpp"
#include "vk/device_selector.hpp"

namespace gt::vk {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT /*types*/,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data,
                                             void* user) {
    auto* counters = static_cast<ValidationCounters*>(user);
    const char* msg = data && data->pMessage ? data->pMessage : "(no message)";
    if ((severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) &&
        counters->runtimeCallDepth.load() > 0) {
        ++counters->runtimeErrors;
        log::warn(std::string("validation (inside the OpenXR runtime's call): ") + msg);
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        ++counters->errors;
        {
            std::lock_guard lock(counters->mutex);
            counters->messages.emplace_back(msg);
        }
        log::error(std::string("validation: ") + msg);
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        ++counters->warnings;
        log::warn(std::string("validation: ") + msg);
    }
    return VK_FALSE;
}

bool hasLayer(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    for (const auto& l : layers) {
        if (std::strcmp(l.layerName, name) == 0) return true;
    }
    return false;
}

bool hasInstanceExtension(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> exts(n);
    vkEnumerateInstanceExtensionProperties(nullptr, &n, exts.data());
    for (const auto& e : exts) {
        if (std::strcmp(e.extensionName, name) == 0) return true;
    }
    return false;
}

bool hasDeviceExtension(VkPhysicalDevice pd, const char* name) {
    uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> exts(n);
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());
    for (const auto& e : exts) {
        if (std::strcmp(e.extensionName, name) == 0) return true;
    }
    return false;
}

bool presents(VkPhysicalDevice pd, uint32_t family, VkSurfaceKHR surface) {
    if (surface == VK_NULL_HANDLE) return true;
    VkBool32 ok = VK_FALSE;
    return vkGetPhysicalDeviceSurfaceSupportKHR(pd, family, surface, &ok) == VK_SUCCESS && ok;
}

// One queue does everything: compute, graphics (the overlay) and, with a surface, present.
std::optional<uint32_t> computeQueueFamily(VkPhysicalDevice pd,
                                           VkSurfaceKHR surface = VK_NULL_HANDLE) {
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
    for (uint32_t i = 0; i < n; ++i) {
        constexpr VkQueueFlags both = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
        if ((families[i].queueFlags & both) == both && families[i].timestampValidBits > 0 &&
            presents(pd, i, surface)) {
            return i;
        }
    }
    if (surface != VK_NULL_HANDLE) return std::nullopt;
    for (uint32_t i = 0; i < n; ++i) {
        if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) return i;
    }
    return std::nullopt;
}

DeviceCandidate describe(VkPhysicalDevice pd, VkSurfaceKHR surface,
                         const std::vector<std::string>& extraExtensions) {
    VkPhysicalDeviceProperties props{};
    vkGetPhysicalDeviceProperties(pd, &props);
    DeviceCandidate c;
    c.name = props.deviceName;
    c.type = props.deviceType;
    c.apiVersion = props.apiVersion;
    c.hasComputeQueue = computeQueueFamily(pd, surface).has_value();
    c.hasRequiredExtensions = hasDeviceExtension(pd, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);
    for (const std::string& e : extraExtensions) {
        c.hasRequiredExtensions = c.hasRequiredExtensions && hasDeviceExtension(pd, e.c_str());
    }
    if (c.apiVersion >= VK_API_VERSION_1_3) {
        VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
        VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        f12.pNext = &f13;
        VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
        f2.pNext = &f12;
        vkGetPhysicalDeviceFeatures2(pd, &f2);
        c.hasRequiredFeatures = f13.synchronization2 && f12.hostQueryReset;
    }
    return c;
}

std::vector<VkPhysicalDevice> enumerate(VkInstance instance) {
    uint32_t n = 0;
    VkResult r = vkEnumeratePhysicalDevices(instance, &n, nullptr);
    if (r != VK_SUCCESS && r != VK_INCOMPLETE) return {};
    std::vector<VkPhysicalDevice> devices(n);
    vkEnumeratePhysicalDevices(instance, &n, devices.data());
    devices.resize(n);
    return devices;
}

} // namespace

Context::Context(const ContextOptions& options) {
    try {
        createInstance(options);
        if (options.createSurface) {
            mSurface = options.createSurface(mInstance);
            if (mSurface == VK_NULL_HANDLE) throw Error("the window system gave no surface");
        }
        pickPhysicalDevice(options);
        createDevice(options);
    } catch (...) {
        release(); // the destructor will not run: free what was created so far
        throw;
    }
}

void Context::createInstance(const ContextOptions& options) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "gazetrace";
    app.applicationVersion = VK_MAKE_VERSION(0, 1, 0);
    app.pEngineName = "gazetrace";
    app.apiVersion = VK_API_VERSION_1_3;

    std::vector<const char*> layers;
    std::vector<const char*> extensions;
    mDebugUtils = hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (mDebugUtils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    for (const std::string& e : options.instanceExtensions) {
        if (!hasInstanceExtension(e.c_str())) {
            throw Error("the Vulkan instance lacks " + e + ", which the display needs");
        }
        extensions.push_back(e.c_str());
    }
    if (options.validation) {
        if (!hasLayer(kValidationLayer)) {
            throw Error("validation requested but VK_LAYER_KHRONOS_validation is not installed "
                        "(apt-get install vulkan-validationlayers)");
        }
        if (!mDebugUtils) throw Error("validation requested but VK_EXT_debug_utils is missing");
        layers.push_back(kValidationLayer);
    }
    const std::vector<VkValidationFeatureEnableEXT> enables = {
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = static_cast<uint32_t>(enables.size());
    features.pEnabledValidationFeatures = enables.data();

    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledLayerCount = static_cast<uint32_t>(layers.size());
    info.ppEnabledLayerNames = layers.data();
    if (options.validation && options.synchronizationValidation) info.pNext = &features;
    info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    if (options.createInstance) {
        mInstance = options.createInstance(info);
        if (mInstance == VK_NULL_HANDLE) throw Error("the instance hook gave no Vulkan instance");
    } else {
        const VkResult r = vkCreateInstance(&info, nullptr, &mInstance);
        if (r == VK_ERROR_INCOMPATIBLE_DRIVER) {
            throw Error("no Vulkan driver found (install mesa-vulkan-drivers for lavapipe)");
        }
        GT_VK_CHECK(r);
    }

    if (options.validation) {
        // A messenger passed only through VkInstanceCreateInfo::pNext covers instance creation
        // alone; this one sees everything after it.
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(mInstance, "vkCreateDebugUtilsMessengerEXT"));
        VkDebugUtilsMessengerCreateInfoEXT m{
            VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        m.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                        VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                        VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        m.pfnUserCallback = debugCallback;
        m.pUserData = &mCounters;
        GT_VK_CHECK(create(mInstance, &m, nullptr, &mMessenger));
    }
    if (mDebugUtils) {
        mSetName = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
            vkGetInstanceProcAddr(mInstance, "vkSetDebugUtilsObjectNameEXT"));
        mBeginLabel = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
            vkGetInstanceProcAddr(mInstance, "vkCmdBeginDebugUtilsLabelEXT"));
        mEndLabel = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
            vkGetInstanceProcAddr(mInstance, "vkCmdEndDebugUtilsLabelEXT"));
    }
}

void Context::pickPhysicalDevice(const ContextOptions& options) {
    if (options.choosePhysicalDevice) {
        // The runtime's device: it must still do what gazetrace needs.
        mPhysicalDevice = options.choosePhysicalDevice(mInstance);
        const DeviceCandidate c = describe(mPhysicalDevice, mSurface, options.deviceExtensions);
        const DeviceChoice choice = chooseDevice({c}, {});
        if (!choice.index) throw Error("the device the runtime requires: " + choice.error);
    } else {
        const std::vector<VkPhysicalDevice> devices = enumerate(mInstance);
        std::vector<DeviceCandidate> candidates;
        candidates.reserve(devices.size());
        for (VkPhysicalDevice pd : devices)
            candidates.push_back(describe(pd, mSurface, options.deviceExtensions));
        const DeviceChoice choice = chooseDevice(candidates, options.deviceOverride);
        if (!choice.index) throw Error(choice.error);
        mPhysicalDevice = devices[*choice.index];
    }
    vkGetPhysicalDeviceProperties(mPhysicalDevice, &mProps);
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    p2.pNext = &driver;
    vkGetPhysicalDeviceProperties2(mPhysicalDevice, &p2);
    mDriverInfo = std::string(driver.driverName) + " " + driver.driverInfo;
    mQueueFamily = *computeQueueFamily(mPhysicalDevice, mSurface);
    if (options.announceDevice) log::info("device: " + deviceDescription());
}

void Context::createDevice(const ContextOptions& options) {
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo q{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    q.queueFamilyIndex = mQueueFamily;
    q.queueCount = 1;
    q.pQueuePriorities = &priority;

    // The features one at a time, not as VkPhysicalDeviceVulkan12/13Features: an OpenXR runtime
    // creating the device (xrCreateVulkanDeviceKHR) chains its own single-feature structures
    // (Monado: VkPhysicalDeviceTimelineSemaphoreFeatures), which must not meet the 1.2 block
    // in one chain (VUID-VkDeviceCreateInfo-pNext-02830).
    VkPhysicalDeviceSynchronization2Features sync2{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SYNCHRONIZATION_2_FEATURES};
    sync2.synchronization2 = VK_TRUE;
    VkPhysicalDeviceHostQueryResetFeatures queryReset{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_HOST_QUERY_RESET_FEATURES};
    queryReset.hostQueryReset = VK_TRUE;
    queryReset.pNext = &sync2;
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f2.pNext = &queryReset;

    std::vector<const char*> extensions = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    for (const std::string& e : options.deviceExtensions)
        extensions.push_back(e.c_str());
    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    info.pNext = &f2;
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &q;
    info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    if (options.createDevice) {
        mDevice = options.createDevice(mPhysicalDevice, info);
        if (mDevice == VK_NULL_HANDLE) throw Error("the device hook gave no Vulkan device");
    } else {
        GT_VK_CHECK(vkCreateDevice(mPhysicalDevice, &info, nullptr, &mDevice));
    }
    vkGetDeviceQueue(mDevice, mQueueFamily, 0, &mQueue);
    mPushDescriptorSet = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
        vkGetDeviceProcAddr(mDevice, "vkCmdPushDescriptorSetKHR"));

    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = mQueueFamily;
    GT_VK_CHECK(vkCreateCommandPool(mDevice, &pool, nullptr, &mCommandPool));
    VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    GT_VK_CHECK(vkCreateFence(mDevice, &fence, nullptr, &mFence));
    mAllocator = std::make_unique<Allocator>(mPhysicalDevice, mDevice);
}

Context::~Context() {
    release();
}

void Context::release() noexcept {
    if (mDevice != VK_NULL_HANDLE) vkDeviceWaitIdle(mDevice);
    mAllocator.reset();
    if (mFence != VK_NULL_HANDLE) vkDestroyFence(mDevice, mFence, nullptr);
    if (mCommandPool != VK_NULL_HANDLE) vkDestroyCommandPool(mDevice, mCommandPool, nullptr);
    if (mDevice != VK_NULL_HANDLE) vkDestroyDevice(mDevice, nullptr);
    if (mSurface != VK_NULL_HANDLE) vkDestroySurfaceKHR(mInstance, mSurface, nullptr);
    mSurface = VK_NULL_HANDLE;
    if (mMessenger != VK_NULL_HANDLE) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(mInstance, "vkDestroyDebugUtilsMessengerEXT"));
        destroy(mInstance, mMessenger, nullptr);
    }
    if (mInstance != VK_NULL_HANDLE) vkDestroyInstance(mInstance, nullptr);
    mFence = VK_NULL_HANDLE;
    mCommandPool = VK_NULL_HANDLE;
    mDevice = VK_NULL_HANDLE;
    mMessenger = VK_NULL_HANDLE;
    mInstance = VK_NULL_HANDLE;
}

std::string Context::deviceDescription() const {
    return std::string(mProps.deviceName) + " (" + typeName(mProps.deviceType) + ", " +
           mDriverInfo + ")";
}

std::vector<std::string> Context::validationMessages() {
    std::lock_guard lock(mCounters.mutex);
    return mCounters.messages;
}

void Context::submitAndWait(const std::function<void(VkCommandBuffer)>& record) {
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = mCommandPool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    GT_VK_CHECK(vkAllocateCommandBuffers(mDevice, &alloc, &cmd));
    struct Free {
        VkDevice d;
        VkCommandPool p;
        VkCommandBuffer c;
        ~Free() { vkFreeCommandBuffers(d, p, 1, &c); }
    } guard{mDevice, mCommandPool, cmd};
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    GT_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
    record(cmd);
    GT_VK_CHECK(vkEndCommandBuffer(cmd));
    VkCommandBufferSubmitInfo cbInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cbInfo.commandBuffer = cmd;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cbInfo;
    GT_VK_CHECK(vkResetFences(mDevice, 1, &mFence));
    GT_VK_CHECK(vkQueueSubmit2(mQueue, 1, &submit, mFence));
    GT_VK_CHECK(vkWaitForFences(mDevice, 1, &mFence, VK_TRUE, UINT64_MAX));
}

void Context::setName(VkObjectType type, uint64_t handle, const std::string& name) const {
    if (!mSetName || handle == 0) return;
    VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    info.objectType = type;
    info.objectHandle = handle;
    info.pObjectName = name.c_str();
    mSetName(mDevice, &info);
}

void Context::beginLabel(VkCommandBuffer cmd, const std::string& name) const {
    if (!mBeginLabel) return;
    VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
    label.pLabelName = name.c_str();
    mBeginLabel(cmd, &label);
}

void Context::endLabel(VkCommandBuffer cmd) const {
    if (mEndLabel) mEndLabel(cmd);
}

void Context::pushDescriptorSet(VkCommandBuffer cmd, VkPipelineBindPoint bindPoint,
                                VkPipelineLayout layout, uint32_t set, uint32_t count,
                                const VkWriteDescriptorSet* writes) const {
    mPushDescriptorSet(cmd, bindPoint, layout, set, count, writes);
}

std::vector<std::string> Context::listDevices() {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_3;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    VkInstance instance = VK_NULL_HANDLE;
    const VkResult r = vkCreateInstance(&info, nullptr, &instance);
    if (r != VK_SUCCESS) {
        throw VulkanError(r, "vkCreateInstance (no Vulkan driver? install mesa-vulkan-drivers)",
                          __FILE__, __LINE__);
    }
    std::vector<std::string> lines;
    const auto devices = enumerate(instance);
    if (devices.empty()) {
        vkDestroyInstance(instance, nullptr);
        throw Error("no Vulkan device found (install mesa-vulkan-drivers for lavapipe)");
    }
    for (std::size_t i = 0; i < devices.size(); ++i) {
        const DeviceCandidate c = describe(devices[i], VK_NULL_HANDLE, {});
        lines.push_back(std::to_string(i) + ": " + c.name + " (" + typeName(c.type) + ")");
    }
    vkDestroyInstance(instance, nullptr);
    return lines;
}

} // namespace gt::vk
