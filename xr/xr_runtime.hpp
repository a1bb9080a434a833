#pragma once
// The OpenXR instance and system: which runtime answers (Monado, SteamVR, a vendor's), the
// head-mounted display it drives, the extensions gazetrace uses where offered, and the hooks
// through which the runtime creates gazetrace's Vulkan instance and device
// (XR_KHR_vulkan_enable2), so the device is the one the headset is connected to and carries what
// the runtime's compositor needs.
#include <chrono>
#include <cstdint>
#include <string>

#include "openxr.hpp"
#include "vk/context.hpp"

namespace gt::xr {

struct RuntimeOptions {
    std::string applicationName = "gazetrace";
    bool eyeGaze = true; // enable XR_EXT_eye_gaze_interaction when the runtime offers it
    // The runtime manifest the OpenXR loader was pointed at (XR_RUNTIME_JSON), named in the
    // error when no runtime loads; empty: none was.
    std::string runtimeManifest;
};

class Runtime {
public:
    // Throws gt::Error with one line naming the problem and what to install or set: no runtime,
    // a runtime without Vulkan, no headset.
    explicit Runtime(const RuntimeOptions& options = {});
    ~Runtime();
    Runtime(const Runtime&) = delete;
    Runtime& operator=(const Runtime&) = delete;

    [[nodiscard]] XrInstance instance() const noexcept { return mInstance; }
    [[nodiscard]] XrSystemId system() const noexcept { return mSystem; }
    [[nodiscard]] const std::string& runtimeName() const noexcept { return mRuntimeName; }
    [[nodiscard]] const std::string& systemName() const noexcept { return mSystemName; }
    // XR_EXT_eye_gaze_interaction is enabled and the system says it supports eye gaze.
    [[nodiscard]] bool eyeGazeOffered() const noexcept { return mEyeGazeExtension; }
    [[nodiscard]] bool eyeGazeSupported() const noexcept { return mEyeGazeSupported; }

    // The context options that let the runtime create the Vulkan instance and device and name
    // the physical device. The Runtime must outlive the context.
    [[nodiscard]] vk::ContextOptions vulkanHooks() const;

    // XrTime <-> steady_clock (CLOCK_MONOTONIC): exact with XR_KHR_convert_timespec_time, else
    // assumed equal to CLOCK_MONOTONIC in nanoseconds (what Monado and SteamVR use on Linux).
    [[nodiscard]] XrTime toXrTime(std::chrono::steady_clock::time_point t) const;
    [[nodiscard]] std::chrono::steady_clock::time_point fromXrTime(XrTime t) const;

    // An instance function (extensions' functions are not exported by the loader).
    template <typename F> [[nodiscard]] F function(const char* name) const {
        return reinterpret_cast<F>(rawFunction(name));
    }

private:
    [[nodiscard]] PFN_xrVoidFunction rawFunction(const char* name) const;

    XrInstance mInstance = XR_NULL_HANDLE;
    XrSystemId mSystem = XR_NULL_SYSTEM_ID;
    std::string mRuntimeName, mSystemName;
    bool mEyeGazeExtension = false, mEyeGazeSupported = false;
    // XR_KHR_convert_timespec_time's functions, looked up once (they run every frame); null
    // when the runtime does not offer it.
    PFN_xrConvertTimespecTimeToTimeKHR mTimeOfTimespec = nullptr;
    PFN_xrConvertTimeToTimespecTimeKHR mTimespecOfTime = nullptr;
};

} // namespace gt::xr
