#pragma once
// `gazetrace xr`: gazetrace as an OpenXR application. The runtime creates the Vulkan instance
// and device (XR_KHR_vulkan_enable2); each frame both eyes' views (pose and asymmetric field of
// view from xrLocateViews at the predicted display time) are rendered foveated in one render
// graph into the eyes' swapchain images and submitted as one projection layer. Gaze comes from
// the runtime (XR_EXT_eye_gaze_interaction) where it offers a valid pose, else from one of
// gazetrace's own sources.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "integrator_args.hpp"

namespace gt::app {

struct XrOptions {
    std::string scene = "builtin:market";
    std::string animation = "all";   // an animated glTF's animation: NAME, INDEX, all or none
    double time = 0.0;               // scene time at the first frame, seconds
    std::string camera;              // start view (render's --camera): where the viewer stands
    std::string origin;              // --xr-origin X,Y,Z: the reference space's origin in the scene
    std::string yawDeg;              // --xr-yaw DEG: the direction the viewer faces (scene yaw)
    double worldScale = 1.0;         // --xr-scale: scene units per metre
    std::string space = "local";     // local | stage
    double resolutionScale = 1.0;    // of the runtime's recommended eye size
    std::string method = "foveated"; // foveated | reference
    std::string slope = "A";         // --method layers: MAR slope
    uint32_t layers = 3;             // --method layers: how many
    std::string interp = "nn";
    // gazetrace | thesis: the thesis's interpolation and TAA as published
    // (render::useThesisReconstruction).
    std::string reconstruction = "gazetrace";
    uint32_t k = 10;
    double pointScale = 1.0;   // the point set's scaling value
    uint32_t raysPerPoint = 1; // as the demo: real time first (the thesis traced up to 32)
    uint32_t spp = 1;          // reference: rays per pixel
    IntegratorArgs integrator; // foveated and reference: --integrator, --bounces, --sequence
    bool taa = true;
    std::string gaze = "ahead"; // fallback: ahead | fixed:X,Y | trace:FILE | track:SRC | udp:PORT
    std::string calibration;    // for track:
    double vergenceM = 0.0;     // fixation distance for a combined gaze; 0: infinity
    bool runtimeGaze = true;    // use XR_EXT_eye_gaze_interaction where valid
    uint32_t frames = 0; // rendered frames, then end the session; 0: until the runtime ends it
    std::string screenshotEye;   // left | right
    std::string screenshot;      // FILE.png: that eye's image of the last frame
    double startTimeoutS = 30.0; // for the session to start running
    bool validate = false;
    std::string cacheDir;
};

nlohmann::json runXr(const XrOptions& options);

} // namespace gt::app
