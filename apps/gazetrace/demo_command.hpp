#pragma once
// `gazetrace demo`: the real-time window. A thin loop over the renderer library: poll input, move
// the camera, read the gaze, acquire a swapchain image, renderFrame into it, present.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "demo_settings.hpp"
#include "integrator_args.hpp"

namespace gt::app {

struct DemoOptions {
    std::string scene = "builtin:market";
    std::string animation = "all"; // an animated glTF's animation: NAME, INDEX, all or none
    double time = 0.0;             // scene time at start, seconds (Space pauses)
    uint32_t width = 640;          // window size at start; the view follows the window
    uint32_t height = 360;
    std::string method = "foveated"; // foveated | layers | reference
    std::string slope = "A";         // layers: MAR slope
    uint32_t layers = 3;             // layers: how many
    // The foveated method's settings where `given` says so; else the device's defaults
    // (demoDefaults: a GPU's best quality, a CPU driver's fast trade-off).
    std::string interp = "nn";
    uint32_t k = 5;
    double scale = 2.0;
    uint32_t raysPerPoint = 1;
    GivenMethodOptions given;
    uint32_t spp = 1; // reference method
    bool taa = true;
    std::string view;          // debug view: points | cells | eccentricity
    IntegratorArgs integrator; // foveated and reference: --integrator, --bounces, --sequence
    std::string gaze = "mouse";
    std::string calibration;
    double frameMs = 0.0; // > 0: trace and path time advance this much per frame (reproducible)
    uint32_t frames = 0;  // 0: until the window is closed
    std::string screenshot;
    std::string camera;
    std::string cameraPath;
    std::string present = "fifo";
    uint32_t framesInFlight = 0; // 0: the renderer picks (1 on a CPU driver, 2 on a GPU)
    bool validate = false;
    std::string log; // per-frame CSV
    std::string cacheDir;
    std::string resize; // "FRAME:WxH": resize the window after that many frames (tests)
    // The HMD path in the window: both eyes of this profile side by side (an extended-mode
    // HMD shows the window full screen). Gaze pixels are the left eye's image.
    std::string hmd;
    bool overlay = true; // the ImGui overlay (Tab toggles it)
    // Show calibration and validation targets, fit the tracker of --gaze track:SOURCE, and
    // write --calibration FILE (demo_calibration.hpp).
    bool calibrate = false;
    bool distortion = true;
    double vergenceM = 0.0;
    bool displaySpace = false; // the point set laid on the panel after the lens
};

// Runs until closed or --frames; returns the JSON summary. Throws gt::Error on failure.
nlohmann::json runDemo(const DemoOptions& options);

} // namespace gt::app
