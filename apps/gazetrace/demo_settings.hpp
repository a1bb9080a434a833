#pragma once
// What the demo's overlay shows and may change, and the defaults the demo starts from on the
// device it runs on.
#include <cstdint>
#include <optional>
#include <string>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

namespace gt::app {

// What the overlay shows and may change; the demo applies the changes before the next frame.
struct DemoSettings {
    std::string method = "foveated"; // foveated | layers | reference
    std::string interp = "nn";       // nn | msm | rbf
    uint32_t k = 5;
    uint32_t raysPerPoint = 1;
    double scale = 2.0;
    bool taa = true;
    std::string view; // "" | points | cells | eccentricity
    // The light transport of the foveated and reference methods (layers trace direct light).
    std::string integrator = "direct"; // direct | path
    uint32_t bounces = 4;
    std::string sequence = "sobol"; // sobol | independent (command line only)
    bool denoise = false;           // the post chain's denoiser
};

struct DemoStats {
    double frameMs = 0.0;
    // From the gaze sample a frame used to the moment the frame was known finished on the
    // device (its submit waited idle): no present timing is offered, so not gaze-to-photon.
    double latencyMs = 0.0;
    uint64_t pointsSampled = 0;
    uint64_t rays = 0;
    std::string gazeSource;
    std::string device;
    std::string defaults;          // which device defaults are active (DemoDefaults::label)
    std::optional<glm::vec2> gaze; // this frame's, window pixels: the overlay keeps off it
};

// The foveated method's settings the demo starts with on a kind of device.
struct DemoDefaults {
    std::string interp;
    uint32_t k = 5;
    double scale = 1.0;
    uint32_t raysPerPoint = 1;
    std::string label; // "GPU quality" | "CPU fast"
};

// A GPU (discrete, integrated, virtual or other): what `eval` scores best, its own defaults
// (scale 1, Modified Shepard with k = 10, 4 rays per point). A CPU driver (lavapipe): the fast
// trade-off, nearest neighbour at scale 2 with one ray per point (at the desktop screen's
// pixels per degree a 640x360 window spans 18 degrees: scale 1 samples 155,000 of its 230,000
// pixels, 5.4 fps on lavapipe; scale 2 samples 61,000, 11.5 fps).
[[nodiscard]] DemoDefaults demoDefaults(VkPhysicalDeviceType type);

// The method options given on the command line: they keep their value over the device's.
struct GivenMethodOptions {
    bool interp = false;
    bool k = false;
    bool scale = false;
    bool raysPerPoint = false;
};

// `settings` with the device defaults where no option was given. Rays per point only for the
// foveated method (the others' rays are --spp).
void applyDemoDefaults(DemoSettings& settings, const DemoDefaults& defaults,
                       const GivenMethodOptions& given);

} // namespace gt::app
