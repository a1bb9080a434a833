#pragma once
// `gazetrace render`: one frame of a scene, headless, to a PNG.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "integrator_args.hpp"

namespace gt::app {

struct RenderOptions {
    std::string scene = "builtin:market";
    std::string animation = "all"; // an animated glTF's animation: NAME, INDEX, all or none
    double time = 0.0;             // scene time of the first frame, seconds
    uint32_t width = 1280;
    uint32_t height = 720;
    uint32_t spp = 1;
    uint32_t seed = 0;
    std::string method = "reference";
    std::string out = "out/render.png";
    std::string graphDot;   // --graph FILE.dot
    std::string camera;     // "X,Y,Z,TX,TY,TZ[,FOV_DEG]"; empty = the scene's own camera
    std::string cameraPath; // CSV t_ms,ex,ey,ez,tx,ty,tz: one frame every frameMs along it
    bool validate = false;  // Khronos validation layer
    // --method foveated (the thesis):
    std::string profile = "fove";
    std::string interp = "nn";
    uint32_t k = 10;
    double scale = 1.0;
    uint32_t raysPerPoint = 32;
    std::string gaze; // "X,Y" in pixels; empty = screen centre
    uint32_t frames = 1;
    bool taa = true;
    std::string kernel = "multiquadric";
    std::string knn = "table";
    double rbfShape = 1.0;
    // gazetrace: display-referred, guided interpolation, rays rotated every frame, adaptive TAA;
    // thesis: the thesis as published (render::useThesisReconstruction).
    std::string reconstruction = "gazetrace";
    // reference and foveated: direct | path (render::Integrator), and the path's scattering
    // vertices.
    IntegratorArgs integrator;      // --integrator, --bounces, --sequence
    std::string gazeTrace;          // CSV t_ms,x,y; excludes --gaze
    std::string gazeSource;         // eye tracker frame source: live gaze; excludes --gaze
    std::string calibration;        // for gazeSource
    double frameMs = 1000.0 / 90.0; // time between frames along the trace (FOVE: 90 Hz)
    std::string view;               // debug view: points | cells | eccentricity
    bool framesGiven = false;
    std::string cacheDir;
    bool sizeGiven = false; // --width/--height were on the command line
    // The HMD path: both eyes of this profile in one graph, side by side.
    std::string hmd;           // a known headset or custom:WxH@HFOVxVFOV[,HZ]
    bool distortion = true;    // --no-distortion: the eyes' images as rendered
    double vergenceM = 0.0;    // distance the eyes converge at; 0: infinity (parallel)
    bool displaySpace = false; // foveated --hmd: the point set laid on the panel after the lens
    // --method layers (Guenter et al. 2012): MAR slope, layer count, half-rate outer layers, grid
    // jitter.
    // --spp is the rays per layer pixel, --taa the per-layer history.
    std::string slope = "A";
    uint32_t layers = 3;
    bool halfRate = true;
    bool jitter = true;
    // Geometric LOD for scenes with subdivision cages: coarser layers and sparser points trace
    // coarser refinements (foveated and layers).
    bool lod = true;
};

// Renders and writes the PNG; returns the JSON summary (device, width, height, method, rays,
// gpu_ms per pass, total_ms, output, ...). Throws gt::Error on any failure.
nlohmann::json runRender(const RenderOptions& options);

} // namespace gt::app
