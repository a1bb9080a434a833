#pragma once
// The command line's option values and the environment's settings as the libraries' typed
// settings (renderer/settings.hpp and the structs below): every string an option or variable
// takes becomes an enum, a number or a struct here, and only here. A bad option value throws
// ArgumentError naming the option and the values it takes.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core/types.hpp>

#include "denoise/denoise.hpp"
#include "integrator_args.hpp"
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
// --integrator direct | path with --bounces (1 to trace::kMaxBounces) and --sequence.
[[nodiscard]] render::IntegratorSettings parseIntegrator(const IntegratorArgs& args);
// --denoise on: the denoiser's settings (passes::DenoiseSettings' defaults); off: none.
[[nodiscard]] std::optional<passes::DenoiseSettings> parseDenoise(const IntegratorArgs& args);
// The integrator as the JSON summaries name it: {integrator, bounces, sequence, denoise}.
[[nodiscard]] nlohmann::json integratorJson(const IntegratorArgs& args);
// --slope: "A", "B" (Guenter et al. 2012's quality levels) or a positive MAR slope.
[[nodiscard]] double parseSlope(const std::string& text);
// Every numeric option's text, checked before CLI11 converts it (commands/shared_options.cpp
// applies these to every option of every command): "" when acceptable, else why not. CLI11's
// conversion takes "nan", "inf" and "1e400" (infinite as a double), and turns "-5" into
// 2^64 - 5 for a 64-bit unsigned option; its ranges let NaN through.
[[nodiscard]] std::string finiteNumberProblem(const std::string& text);
[[nodiscard]] std::string nonNegativeIntegerProblem(const std::string& text);
// A whole number of digits only (no sign, no blanks), or nullopt: sscanf's %d and %u wrapped
// 4294967328 to 32. "WxH" as two of them.
[[nodiscard]] std::optional<uint32_t> parseWholeNumber(const std::string& text);
[[nodiscard]] std::optional<std::pair<uint32_t, uint32_t>> parseSizeText(const std::string& text);
// --present fifo | mailbox | immediate.
[[nodiscard]] render::PresentMode parsePresentMode(const std::string& name);

// --hmd: a known headset (hmdProfileNames: fove, vive, rift-cv1, vive-pro-eye, quest-pro,
// psvr2, pimax-crystal, varjo-xr4, vision-pro) or custom:WxH@HFOVxVFOV[,HZ] (parseCustomHmd).
[[nodiscard]] render::HmdModel parseHmd(const std::string& name);
[[nodiscard]] display::HmdProfile hmdProfile(const std::string& name);
[[nodiscard]] std::vector<std::string> hmdProfileNames();
// Every --hmd choice joined by `separator`, the custom syntax last (help and error texts).
[[nodiscard]] std::string hmdChoicesText(const char* separator = " | ");
// custom:WxH@HFOVxVFOV[,HZ], e.g. custom:3840x3744@120x105,90: W x H pixels per eye (16..16384)
// spanning HFOV x VFOV degrees (each above 0 and below 170) symmetrically, at HZ (above 0;
// 90 when left out). Numbers are decimal digits with an optional point. Anything else throws
// ArgumentError naming the value.
inline constexpr const char* kCustomHmdPrefix = "custom:";
inline constexpr uint32_t kCustomHmdMinPixels = 16, kCustomHmdMaxPixels = 16384;
inline constexpr double kCustomHmdMaxFovDeg = 170.0;
[[nodiscard]] display::HmdProfile parseCustomHmd(const std::string& text);
// --profile: fove | vive | desktop.
[[nodiscard]] render::DisplayModel parseDisplay(const std::string& name);
[[nodiscard]] foveation::DisplayProfile displayProfile(const std::string& name);
[[nodiscard]] std::vector<std::string> displayProfileNames();

// Where point sets are cached unless --cache-dir says: $GAZETRACE_CACHE, else
// $XDG_CACHE_HOME/gazetrace, else ~/.cache/gazetrace.
[[nodiscard]] std::filesystem::path defaultCacheDir();

// GAZETRACE_DEVICE: a decimal index among the Vulkan devices or a substring of a device's
// name; unset or empty: the automatic choice. A number past kMaxDeviceIndex (no machine has
// that many devices) or a negative one is an ArgumentError naming the variable.
inline constexpr std::size_t kMaxDeviceIndex = 9999;
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
