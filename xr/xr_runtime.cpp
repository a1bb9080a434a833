#include "xr_runtime.hpp"

#include <cstring>
#include <vector>

#include "core/log.hpp"
#include "xr_error.hpp"

namespace gt::xr {

namespace {

std::string runtimeHint(const std::string& manifest) {
    return !manifest.empty()
               ? "XR_RUNTIME_JSON is " + manifest +
                     ": check that file and that its "
                     "runtime's service is running"
               : "install an OpenXR runtime (Monado: apt-get install monado-service, then start "
                 "monado-service; or SteamVR) or set XR_RUNTIME_JSON to a runtime's manifest";
}

std::vector<std::string> instanceExtensions(const std::string& manifest) {
    uint32_t n = 0;
    XrResult r = xrEnumerateInstanceExtensionProperties(nullptr, 0, &n, nullptr);
    if (XR_FAILED(r)) {
        throw XrError(r, "xrEnumerateInstanceExtensionProperties",
                      "no OpenXR runtime could be loaded: " + runtimeHint(manifest));
    }
    std::vector<XrExtensionProperties> props(n, {XR_TYPE_EXTENSION_PROPERTIES});
    r = xrEnumerateInstanceExtensionProperties(nullptr, n, &n, props.data());
    if (XR_FAILED(r)) {
        throw XrError(r, "xrEnumerateInstanceExtensionProperties");
    }
    std::vector<std::string> names;
    for (uint32_t i = 0; i < n; ++i) {
        names.emplace_back(props[i].extensionName);
    }
    return names;
}

// Calls one of XR_KHR_vulkan_enable2's create functions, which answer twice: the runtime's
// XrResult, and the VkResult of the Vulkan call it made for us.
template <typename Handle, typename Create, typename Info>
Handle createThroughRuntime(Create create, XrInstance instance, const Info& info) {
    Handle handle = VK_NULL_HANDLE;
    VkResult vr = VK_SUCCESS;
    GT_XR_CHECK(create(instance, &info, &handle, &vr));
    GT_VK_CHECK(vr);
    return handle;
}

bool contains(const std::vector<std::string>& v, const char* name) {
    for (const std::string& s : v) {
        if (s == name) {
            return true;
        }
    }
    return false;
}

} // namespace

Runtime::Runtime(const RuntimeOptions& options) {
    // The loader prints its own errors on stderr; gazetrace says what went wrong in one line.
    // XR_LOADER_DEBUG set by the user (e.g. "all") still wins.
    setenv("XR_LOADER_DEBUG", "none", 0);
    const std::vector<std::string> offered = instanceExtensions(options.runtimeManifest);
    if (!contains(offered, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME)) {
        throw Error("the OpenXR runtime offers no Vulkan support (XR_KHR_vulkan_enable2); "
                    "gazetrace renders with Vulkan: use a runtime that has it (Monado, SteamVR) "
                    "and point XR_RUNTIME_JSON at its manifest");
    }
    std::vector<const char*> enabled = {XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME};
    mEyeGazeExtension =
        options.eyeGaze && contains(offered, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
    if (mEyeGazeExtension) {
        enabled.push_back(XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
    }
    const bool timespec = contains(offered, XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME);
    if (timespec) {
        enabled.push_back(XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME);
    }

    XrInstanceCreateInfo info{XR_TYPE_INSTANCE_CREATE_INFO};
    std::strncpy(info.applicationInfo.applicationName, options.applicationName.c_str(),
                 XR_MAX_APPLICATION_NAME_SIZE - 1);
    info.applicationInfo.applicationVersion = 1;
    std::strncpy(info.applicationInfo.engineName, "gazetrace", XR_MAX_ENGINE_NAME_SIZE - 1);
    info.applicationInfo.engineVersion = 1;
    info.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    info.enabledExtensionCount = static_cast<uint32_t>(enabled.size());
    info.enabledExtensionNames = enabled.data();
    const XrResult created = xrCreateInstance(&info, &mInstance);
    if (XR_FAILED(created)) {
        throw XrError(created, "xrCreateInstance",
                      "the OpenXR runtime could not start a session for gazetrace: " +
                          runtimeHint(options.runtimeManifest));
    }
    try {
        XrInstanceProperties props{XR_TYPE_INSTANCE_PROPERTIES};
        GT_XR_CHECK(xrGetInstanceProperties(mInstance, &props));
        mRuntimeName = props.runtimeName + std::string(" ") +
                       std::to_string(XR_VERSION_MAJOR(props.runtimeVersion)) + "." +
                       std::to_string(XR_VERSION_MINOR(props.runtimeVersion)) + "." +
                       std::to_string(XR_VERSION_PATCH(props.runtimeVersion));

        XrSystemGetInfo sys{XR_TYPE_SYSTEM_GET_INFO};
        sys.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
        const XrResult r = xrGetSystem(mInstance, &sys, &mSystem);
        if (r == XR_ERROR_FORM_FACTOR_UNAVAILABLE || r == XR_ERROR_FORM_FACTOR_UNSUPPORTED) {
            throw XrError(r, "xrGetSystem",
                          "the OpenXR runtime " + mRuntimeName +
                              " sees no head-mounted display: connect and switch on the "
                              "headset, or start the runtime with a simulated one");
        }
        GT_XR_CHECK(r);
        XrSystemEyeGazeInteractionPropertiesEXT eye{
            XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT};
        XrSystemProperties sp{XR_TYPE_SYSTEM_PROPERTIES};
        if (mEyeGazeExtension) {
            sp.next = &eye;
        }
        GT_XR_CHECK(xrGetSystemProperties(mInstance, mSystem, &sp));
        mSystemName = sp.systemName;
        if (timespec) {
            mTimeOfTimespec =
                function<PFN_xrConvertTimespecTimeToTimeKHR>("xrConvertTimespecTimeToTimeKHR");
            mTimespecOfTime =
                function<PFN_xrConvertTimeToTimespecTimeKHR>("xrConvertTimeToTimespecTimeKHR");
        }
        mEyeGazeSupported = mEyeGazeExtension && eye.supportsEyeGazeInteraction == XR_TRUE;

        // Must precede xrCreateSession; also where a runtime says which Vulkan it accepts.
        auto requirements = function<PFN_xrGetVulkanGraphicsRequirements2KHR>(
            "xrGetVulkanGraphicsRequirements2KHR");
        XrGraphicsRequirementsVulkanKHR req{XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN2_KHR};
        GT_XR_CHECK(requirements(mInstance, mSystem, &req));
        if (req.minApiVersionSupported > XR_MAKE_VERSION(1, 3, 0)) {
            throw Error("the OpenXR runtime " + mRuntimeName + " needs Vulkan " +
                        std::to_string(XR_VERSION_MAJOR(req.minApiVersionSupported)) + "." +
                        std::to_string(XR_VERSION_MINOR(req.minApiVersionSupported)) +
                        "; gazetrace uses Vulkan 1.3");
        }
    } catch (...) {
        xrDestroyInstance(mInstance);
        throw;
    }
}

Runtime::~Runtime() {
    if (mInstance != XR_NULL_HANDLE) {
        xrDestroyInstance(mInstance);
    }
}

PFN_xrVoidFunction Runtime::rawFunction(const char* name) const {
    PFN_xrVoidFunction f = nullptr;
    const XrResult r = xrGetInstanceProcAddr(mInstance, name, &f);
    if (XR_FAILED(r) || f == nullptr) {
        throw XrError(r, std::string("xrGetInstanceProcAddr ") + name);
    }
    return f;
}

vk::ContextOptions Runtime::vulkanHooks() const {
    vk::ContextOptions o;
    o.createInstance = [this](const VkInstanceCreateInfo& info) {
        auto create = function<PFN_xrCreateVulkanInstanceKHR>("xrCreateVulkanInstanceKHR");
        XrVulkanInstanceCreateInfoKHR ci{XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR};
        ci.systemId = mSystem;
        ci.pfnGetInstanceProcAddr = &vkGetInstanceProcAddr;
        ci.vulkanCreateInfo = &info;
        return createThroughRuntime<VkInstance>(create, mInstance, ci);
    };
    o.choosePhysicalDevice = [this](VkInstance instance) {
        auto get = function<PFN_xrGetVulkanGraphicsDevice2KHR>("xrGetVulkanGraphicsDevice2KHR");
        XrVulkanGraphicsDeviceGetInfoKHR gi{XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR};
        gi.systemId = mSystem;
        gi.vulkanInstance = instance;
        VkPhysicalDevice pd = VK_NULL_HANDLE;
        GT_XR_CHECK(get(mInstance, &gi, &pd));
        return pd;
    };
    o.createDevice = [this](VkPhysicalDevice pd, const VkDeviceCreateInfo& info) {
        auto create = function<PFN_xrCreateVulkanDeviceKHR>("xrCreateVulkanDeviceKHR");
        XrVulkanDeviceCreateInfoKHR ci{XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR};
        ci.systemId = mSystem;
        ci.pfnGetInstanceProcAddr = &vkGetInstanceProcAddr;
        ci.vulkanPhysicalDevice = pd;
        ci.vulkanCreateInfo = &info;
        return createThroughRuntime<VkDevice>(create, mInstance, ci);
    };
    return o;
}

XrTime Runtime::toXrTime(std::chrono::steady_clock::time_point t) const {
    const auto ns =
        std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
    if (mTimeOfTimespec == nullptr) {
        return static_cast<XrTime>(ns);
    }
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
    ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
    XrTime out = 0;
    GT_XR_CHECK(mTimeOfTimespec(mInstance, &ts, &out));
    return out;
}

std::chrono::steady_clock::time_point Runtime::fromXrTime(XrTime t) const {
    int64_t ns = t;
    if (mTimespecOfTime != nullptr) {
        timespec ts{};
        GT_XR_CHECK(mTimespecOfTime(mInstance, t, &ts));
        ns = static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
    }
    return std::chrono::steady_clock::time_point(std::chrono::nanoseconds(ns));
}

} // namespace gt::xr
