// A stand-in OpenXR runtime for the error paths a real one does not take: the loader finds it
// through a manifest (XR_RUNTIME_JSON), negotiates, and it offers only OpenGL
// (XR_KHR_opengl_enable), so gazetrace must say it needs XR_KHR_vulkan_enable2.
// The negotiation structures are the loader-runtime interface of the OpenXR loader
// specification (1.0), declared here because Debian's headers do not ship loader_interfaces.h.
#include <cstring>

#include <openxr/openxr.h>

namespace {

enum FakeLoaderStruct : int {
    kLoaderInfo = 1,     // XR_LOADER_INTERFACE_STRUCT_LOADER_INFO
    kRuntimeRequest = 3, // XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST
};

struct NegotiateLoaderInfo {
    int structType;
    uint32_t structVersion;
    size_t structSize;
    uint32_t minInterfaceVersion;
    uint32_t maxInterfaceVersion;
    XrVersion minApiVersion;
    XrVersion maxApiVersion;
};

struct NegotiateRuntimeRequest {
    int structType;
    uint32_t structVersion;
    size_t structSize;
    uint32_t runtimeInterfaceVersion;
    XrVersion runtimeApiVersion;
    PFN_xrGetInstanceProcAddr getInstanceProcAddr;
};

XRAPI_ATTR XrResult XRAPI_CALL enumerateExtensions(const char* layer, uint32_t capacity,
                                                   uint32_t* count, XrExtensionProperties* props) {
    if (layer != nullptr) return XR_ERROR_API_LAYER_NOT_PRESENT;
    *count = 1;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < 1) return XR_ERROR_SIZE_INSUFFICIENT;
    std::strncpy(props[0].extensionName, "XR_KHR_opengl_enable", XR_MAX_EXTENSION_NAME_SIZE - 1);
    props[0].extensionVersion = 1;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL createInstance(const XrInstanceCreateInfo*, XrInstance*) {
    return XR_ERROR_EXTENSION_NOT_PRESENT;
}

XRAPI_ATTR XrResult XRAPI_CALL getInstanceProcAddr(XrInstance, const char* name,
                                                   PFN_xrVoidFunction* function) {
    if (std::strcmp(name, "xrEnumerateInstanceExtensionProperties") == 0) {
        *function = reinterpret_cast<PFN_xrVoidFunction>(&enumerateExtensions);
    } else if (std::strcmp(name, "xrCreateInstance") == 0) {
        *function = reinterpret_cast<PFN_xrVoidFunction>(&createInstance);
    } else {
        *function = nullptr;
        return XR_ERROR_FUNCTION_UNSUPPORTED;
    }
    return XR_SUCCESS;
}

} // namespace

extern "C" __attribute__((visibility("default"))) XrResult
xrNegotiateLoaderRuntimeInterface(const NegotiateLoaderInfo* info,
                                  NegotiateRuntimeRequest* request) {
    if (info == nullptr || request == nullptr || info->structType != kLoaderInfo ||
        request->structType != kRuntimeRequest || info->minInterfaceVersion > 1) {
        return XR_ERROR_INITIALIZATION_FAILED;
    }
    request->runtimeInterfaceVersion = 1;
    request->runtimeApiVersion = XR_CURRENT_API_VERSION;
    request->getInstanceProcAddr = &getInstanceProcAddr;
    return XR_SUCCESS;
}
