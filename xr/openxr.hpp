#pragma once
// The OpenXR headers with the platform parts gazetrace uses: Vulkan (XR_KHR_vulkan_enable2) and
// timespec time conversion (XR_KHR_convert_timespec_time), which relates XrTime to the monotonic
// clock that std::chrono::steady_clock reads on Linux.
#include <time.h>

#include <vulkan/vulkan.h>

#define XR_USE_GRAPHICS_API_VULKAN
#define XR_USE_TIMESPEC
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>
