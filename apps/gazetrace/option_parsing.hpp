#pragma once
// The command line's option values and the environment's settings as the libraries' typed
// settings (renderer/settings.hpp and the structs below): every string an option or variable
// takes becomes an enum, a number or a struct here, and only here. A bad option value throws
// ArgumentError naming the option and the values it takes.
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core/types.hpp>

#include "net/udp_emitter.hpp"
#include "scene/gltf_loader.hpp"
#include "settings.hpp"
#include "vk/device_selector.hpp"

namespace gt::app {

// --interp nn | msm | rbf, --kernel multiquadric | gaussian, --knn lists | table,
// --view points | cells | eccentricity, --reconstruction gazetrace | thesis.
[[nodiscard]] render::Interpolation parseInterpolation(const std::string& name);
[[nodiscard]] render::RbfKernel parseKernel(const std::string& name);
[[nodiscard]] render::KnnIndex parseKnnIndex(const std::string& name);
[[nodiscard]] render::Interpolation parseView(const std::string& name);
[[nodiscard]] render::Reconstruction parseReconstruction(const std::string& name);
// --slope: "A", "B" (Guenter et al. 2012's quality levels) or a positive MAR slope.
[[nodiscard]] double parseSlope(const std::string& text);
// --present fifo | mailbox | immediate.
[[nodiscard]] render::PresentMode parsePresentMode(const std::string& name);

// --hmd: fove | vive | rift-cv1.
[[nodiscard]] render::HmdModel parseHmd(const std::string& name);
[[nodiscard]] display::HmdProfile hmdProfile(const std::string& name);
[[nodiscard]] std::vector<std::string> hmdProfileNames();
// --profile: fove | vive | desktop.
[[nodiscard]] render::DisplayModel parseDisplay(const std::string& name);
[[nodiscard]] foveation::DisplayProfile displayProfile(const std::string& name);
[[nodiscard]] std::vector<std::string> displayProfileNames();

// Where point sets are cached unless --cache-dir says: $GAZETRACE_CACHE, else
// $XDG_CACHE_HOME/gazetrace, else ~/.cache/gazetrace.
[[nodiscard]] std::filesystem::path defaultCacheDir();

// GAZETRACE_DEVICE: a decimal index among the Vulkan devices or a substring of a device's
// name; unset or empty: the automatic choice.
[[nodiscard]] vk::DeviceRequest deviceRequest();
[[nodiscard]] vk::DeviceRequest parseDeviceRequest(const std::string& text);

// The scene loader's limits as the environment sets them: GAZETRACE_MAX_TRIANGLES,
// GAZETRACE_MAX_INSTANCES and GAZETRACE_MAX_TEXTURE_BYTES (whole numbers from 1; anything else
// throws ArgumentError naming the variable and the value) and GAZETRACE_GLTF_ANY_PATH=1
// (buffers and images anywhere).
[[nodiscard]] scene::GltfLoadOptions gltfLoadOptions();

// --regions "X,Y,W,H;X,Y,W,H": the left eye's region of the camera, then the right eye's.
[[nodiscard]] std::pair<cv::Rect, cv::Rect> parseEyeRegions(const std::string& text);
// --emit udp://IPV4:PORT or udp://localhost:PORT.
[[nodiscard]] eyetrack::UdpEndpoint parseUdpEndpoint(const std::string& url);

} // namespace gt::app
