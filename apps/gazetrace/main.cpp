// The `gazetrace` command line. Every error reaches the user as one line on stderr and a
// non-zero exit status; stdout carries only what was asked for (--json).
#include <cmath>
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench_command.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "demo_command.hpp"
#include "eval_command.hpp"
#include "eye_commands.hpp"
#include "layers_command.hpp"
#include "pointset_command.hpp"
#include "render_command.hpp"
#include "scene/builtin_scenes.hpp"
#include "soak_command.hpp"
#include "vk/context.hpp"
#include "xr_command.hpp"

namespace {

// --width and --height, each checked to lie in [min, 16384] pixels.
void addSizeOptions(CLI::App* cmd, uint32_t& width, uint32_t& height, uint32_t min,
                    const std::string& what) {
    cmd->add_option("--width", width, what + " width in pixels")
        ->check(CLI::Range(min, 16384u))
        ->capture_default_str();
    cmd->add_option("--height", height, what + " height in pixels")
        ->check(CLI::Range(min, 16384u))
        ->capture_default_str();
}

// The method settings of the real-time front ends (demo, xr).
void addLiveMethodOptions(CLI::App* cmd, std::string& method, std::string& interp, uint32_t& k,
                          double& scale, uint32_t& raysPerPoint, uint32_t& spp, std::string& taa,
                          std::string& slope, uint32_t& layers) {
    cmd->add_option("--method", method, "foveated | layers | reference")->capture_default_str();
    cmd->add_option("--slope", slope, "Layers: MAR slope A | B | VALUE")->capture_default_str();
    cmd->add_option("--layers", layers, "Layers: number of eccentricity layers")
        ->check(CLI::Range(1u, 4u))
        ->capture_default_str();
    cmd->add_option("--interp", interp, "nn | msm | rbf")->capture_default_str();
    cmd->add_option("--k", k, "Neighbours for msm / rbf")->capture_default_str();
    cmd->add_option("--scale", scale, "Point-set scaling value (sparser above 1)")
        ->check(CLI::Range(0.25, 8.0))
        ->capture_default_str();
    cmd->add_option("--rays-per-point", raysPerPoint, "Rays traced per point")
        ->check(CLI::Range(1u, 1024u))
        ->capture_default_str();
    cmd->add_option("--spp", spp, "Rays per pixel (reference) or per layer pixel (layers)")
        ->check(CLI::Range(1u, 1024u))
        ->capture_default_str();
    cmd->add_option("--taa", taa, "on | off")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
}

int fail(const std::string& message) {
    std::fprintf(stderr, "gazetrace: error: %s\n", message.c_str());
    return 1;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"gazetrace — foveated ray tracing with eye tracking"};
    app.require_subcommand(1);
    bool quiet = false;
    app.add_flag("-q,--quiet", quiet, "Only print errors");
    app.fallthrough(); // -q works after the subcommand too

    gt::app::RenderOptions render;
    bool renderJson = false;
    CLI::App* renderCmd = app.add_subcommand("render", "Render one frame headless to a PNG");
    renderCmd
        ->add_option("--scene", render.scene,
                     "builtin:market | builtin:cornell | builtin:gallery | FILE.gltf | FILE.glb | "
                     "cubemap:FILE")
        ->capture_default_str();
    renderCmd->add_option("--camera", render.camera,
                          "Camera X,Y,Z,TX,TY,TZ[,FOV]: eye, look-at target (scene units), "
                          "vertical field of view in degrees (default: the scene's camera)");
    addSizeOptions(renderCmd, render.width, render.height, 1u, "Image");
    renderCmd->add_option("--spp", render.spp, "Rays per pixel (stratified, jittered)")
        ->check(CLI::Range(1u, 4096u))
        ->capture_default_str();
    renderCmd->add_option("--seed", render.seed, "Frame seed for the jitter")
        ->capture_default_str();
    renderCmd->add_option("--method", render.method, "reference | foveated | layers")
        ->capture_default_str();
    renderCmd->add_option("--slope", render.slope, "Layers: MAR slope A | B | VALUE")
        ->capture_default_str();
    renderCmd->add_option("--layers", render.layers, "Layers: number of eccentricity layers")
        ->check(CLI::Range(1u, 4u))
        ->capture_default_str();
    std::string renderHalfRate = "on", renderJitter = "on";
    renderCmd
        ->add_option("--half-rate", renderHalfRate,
                     "Layers: outer layers at half the frame rate, staggered (on | off)")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
    renderCmd->add_option("--jitter", renderJitter, "Layers: per-frame grid jitter (on | off)")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
    std::string renderLod = "on";
    renderCmd
        ->add_option("--lod", renderLod,
                     "Geometric LOD of subdivision cages by sampling pitch (on | off)")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
    renderCmd->add_option("--out", render.out, "Output PNG, or a folder for frame_NNNN.png")
        ->capture_default_str();
    renderCmd
        ->add_option("--profile", render.profile, "Foveated: display profile fove | vive | desktop")
        ->check(CLI::IsMember({"fove", "vive", "desktop"}))
        ->capture_default_str();
    renderCmd->add_option("--interp", render.interp, "Foveated: interpolation nn | msm | rbf")
        ->check(CLI::IsMember({"nn", "msm", "rbf"}))
        ->capture_default_str();
    renderCmd->add_option("--kernel", render.kernel, "Foveated RBF kernel: multiquadric | gaussian")
        ->check(CLI::IsMember({"multiquadric", "gaussian"}))
        ->capture_default_str();
    renderCmd
        ->add_option("--knn", render.knn,
                     "Foveated msm/rbf neighbours: table (the thesis's k nearest per canvas "
                     "pixel; rbf adds per-pixel weights) | lists (nearest point + its neighbour "
                     "list, rbf solved per point each frame: less memory, slower)")
        ->check(CLI::IsMember({"lists", "table"}))
        ->capture_default_str();
    renderCmd
        ->add_option("--rbf-c", render.rbfShape,
                     "Foveated RBF shape c, in units of the point spacing")
        ->check(CLI::Range(0.001, 1000.0))
        ->capture_default_str();
    renderCmd
        ->add_option("--reconstruction", render.reconstruction,
                     "Foveated: gazetrace | thesis (the thesis's interpolation and TAA as published)")
        ->check(CLI::IsMember({"gazetrace", "thesis"}))
        ->capture_default_str();
    renderCmd->add_option("--k", render.k, "Foveated: neighbours for msm and rbf (1-20)")
        ->check(CLI::Range(1u, 20u))
        ->capture_default_str();
    renderCmd->add_option("--scale", render.scale, "Foveated: point-set scaling value")
        ->check(CLI::Range(0.01, 100.0))
        ->capture_default_str();
    renderCmd->add_option("--rays-per-point", render.raysPerPoint, "Foveated: rays per point")
        ->check(CLI::Range(1u, 4096u))
        ->capture_default_str();
    renderCmd->add_option("--gaze", render.gaze,
                          "Foveated: gaze point X,Y in pixels (default: centre)");
    renderCmd->add_option("--frames", render.frames, "Frames to render")
        ->check(CLI::Range(1u, 100000u))
        ->capture_default_str();
    renderCmd->add_option("--cache", render.cacheDir, "Point-set cache folder");
    renderCmd->add_option("--camera-path", render.cameraPath,
                          "Camera path CSV t_ms,ex,ey,ez,tx,ty,tz (demo's R records one): a frame "
                          "every --frame-ms along it");
    renderCmd->add_option("--hmd", render.hmd,
                          "HMD path: fove | vive | rift-cv1 (both eyes, side by side, lens "
                          "pre-distortion; --gaze is a pixel of the left eye's image)");
    bool noDistortion = false;
    renderCmd->add_flag("--no-distortion", noDistortion, "--hmd: the eyes as rendered, no lens");
    renderCmd->add_flag("--display-space", render.displaySpace,
                        "--hmd, foveated: lay the point set on the panel after the lens");
    renderCmd->add_option("--vergence-m", render.vergenceM,
                          "--hmd: distance the eyes converge at in metres (0: infinity)");
    renderCmd->add_option("--gaze-trace", render.gazeTrace, "Foveated: gaze trace CSV (t_ms,x,y)")
        ->check(CLI::ExistingFile);
    renderCmd->add_option("--gaze-source", render.gazeSource,
                          "Foveated: live gaze from the eye tracker on this source "
                          "(v4l2:/dev/videoN, video:FILE, ...); needs --calibration");
    renderCmd->add_option("--calibration", render.calibration,
                          "Calibration JSON for --gaze-source (gazetrace calibrate)");
    renderCmd->add_option("--frame-ms", render.frameMs, "Time between frames along the gaze trace")
        ->check(CLI::Range(0.1, 10000.0))
        ->capture_default_str();
    renderCmd
        ->add_option("--view", render.view, "Foveated debug view: points | cells | eccentricity")
        ->check(CLI::IsMember({"points", "cells", "eccentricity"}));
    std::string taaFlag = "on";
    renderCmd->add_option("--taa", taaFlag, "Foveated: temporal anti-aliasing on | off")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
    renderCmd->add_option("--graph", render.graphDot,
                          "Write the compiled render graph as Graphviz");
    renderCmd->add_flag("--validate", render.validate, "Enable the Khronos validation layer");
    renderCmd->add_flag("--json", renderJson, "Print a JSON summary on stdout");

    gt::app::PointSetOptions pointset;
    bool pointsetJson = false;
    CLI::App* pointsetCmd =
        app.add_subcommand("pointset", "Generate the perceptual point set (thesis 4.1, Table 1)");
    pointsetCmd->add_option("--profile", pointset.profile, "fove | vive | desktop")
        ->check(CLI::IsMember({"fove", "vive", "desktop"}))
        ->capture_default_str();
    pointsetCmd->add_option("--scale", pointset.scale, "Eccentricity scaling value (thesis 4.1)")
        ->check(CLI::Range(0.01, 100.0))
        ->capture_default_str();
    pointsetCmd->add_option("--seed", pointset.seed, "Dart-throwing seed")->capture_default_str();
    pointsetCmd->add_option("--out", pointset.out, "Also write the point set to this file");
    pointsetCmd->add_option("--image", pointset.image,
                            "Draw every point into this PNG (Figure 12)");
    pointsetCmd->add_option("--cache", pointset.cacheDir,
                            "Cache folder (default $GAZETRACE_CACHE or ~/.cache/gazetrace)");
    pointsetCmd->add_option("--sweep", pointset.sweep,
                            "Scales to sweep, e.g. 1 1.5 2 2.5 3 (Figure 14)");
    pointsetCmd->add_flag("--json", pointsetJson, "Print a JSON summary on stdout");
    pointsetCmd->add_option("--hmd", pointset.hmd,
                            "fove | vive | rift-cv1: where the rays go with the set laid in the "
                            "eye's image and laid on the panel after the lens");

    gt::app::LayersOptions layers;
    bool layersJson = false;
    CLI::App* layersCmd = app.add_subcommand(
        "layers", "Eccentricity-layer optimisation and predicted speed-up (Guenter 2012, 4.3)");
    layersCmd->add_option("--profile", layers.profile, "desktop | fove | vive | paper")
        ->check(CLI::IsMember({"desktop", "fove", "vive", "paper"}))
        ->capture_default_str();
    layersCmd->add_option("--slope", layers.slope, "MAR slope: A (0.0275) | B (0.0220) | VALUE")
        ->capture_default_str();
    layersCmd->add_option("--layers", layers.layers, "Number of layers")
        ->check(CLI::Range(1u, 4u))
        ->capture_default_str();
    layersCmd->add_option("--weights", layers.weights, "unit | half-rate (eq. 5's w_i)")
        ->check(CLI::IsMember({"unit", "half-rate"}))
        ->capture_default_str();
    layersCmd->add_option("--steps", layers.steps, "Brute-force grid divisions of (0, e*)")
        ->check(CLI::Range(8u, 4000u))
        ->capture_default_str();
    layersCmd->add_flag("--fov-table", layers.fovTable,
                        "Figure 12: speed-up for 20..120 degrees at foveal sharpness");
    layersCmd->add_flag("--json", layersJson, "Print JSON instead of a table");

    gt::app::EvalOptions eval;
    bool evalJson = false;
    std::string evalTaa = "on";
    CLI::App* evalCmd = app.add_subcommand(
        "eval", "Picture quality: a foveated frame against a many-ray reference, per "
                "eccentricity band (FLIP, PSNR, SSIM), beside the uniform baseline at equal rays");
    evalCmd->add_option("--scene", eval.scene, "builtin:NAME | FILE.gltf | FILE.glb | cubemap:FILE")
        ->capture_default_str();
    evalCmd->add_option("--camera", eval.camera, "X,Y,Z,TX,TY,TZ[,FOV]");
    evalCmd->add_option("--profile", eval.profile, "Display geometry: fove | vive | desktop")
        ->capture_default_str();
    evalCmd->add_option("--width", eval.width, "A window this wide on the profile's screen")
        ->check(CLI::Range(16u, 16384u));
    evalCmd->add_option("--height", eval.height, "A window this high on the profile's screen")
        ->check(CLI::Range(16u, 16384u));
    evalCmd->add_option("--gaze", eval.gaze, "X,Y in pixels (default: the centre)");
    evalCmd->add_option("--interp", eval.interp, "Foveated: nn | msm | rbf")->capture_default_str();
    evalCmd->add_option("--k", eval.k, "Foveated: neighbours for msm and rbf (1-20)")
        ->capture_default_str();
    evalCmd->add_option("--scale", eval.scale, "Foveated: point-set scaling value")
        ->check(CLI::Range(0.25, 8.0))
        ->capture_default_str();
    evalCmd
        ->add_option("--rays-per-point", eval.raysPerPoint,
                     "Foveated: rays per point (the baseline: rays per pixel)")
        ->check(CLI::Range(1u, 1024u))
        ->capture_default_str();
    evalCmd->add_option("--taa", evalTaa, "Foveated: on | off")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
    evalCmd
        ->add_option("--reconstruction", eval.reconstruction,
                     "Foveated: gazetrace (the options below) | thesis (the thesis as published)")
        ->capture_default_str();
    evalCmd->add_option("--blend", eval.blend, "Foveated: interpolate display | linear radiance")
        ->capture_default_str();
    evalCmd
        ->add_option("--edge-tolerance", eval.edgeTolerance,
                     "Foveated msm: geometry-aware weights, relative depth tolerance (0: off)")
        ->capture_default_str();
    evalCmd
        ->add_option("--range-sigma", eval.rangeSigma,
                     "Foveated msm: colour-guided weights, display luminance sigma (0: off)")
        ->check(CLI::Range(0.0, 100.0))
        ->capture_default_str();
    evalCmd->add_option("--shepard-power", eval.shepardPower, "Foveated msm: q of eq. (6)")
        ->check(CLI::Range(0.5, 8.0))
        ->capture_default_str();
    evalCmd
        ->add_option("--still-clip", eval.stillClipGamma,
                     "TAA: clipping box in standard deviations with the camera still")
        ->check(CLI::Range(0.1, 100.0))
        ->capture_default_str();
    evalCmd
        ->add_option("--eccentric-radius", eval.eccentricRadius,
                     "TAA: share of the width beyond which a moving gaze leans on the history")
        ->check(CLI::Range(0.0, 10.0))
        ->capture_default_str();
    std::string evalJitter = "on";
    evalCmd->add_option("--jitter", evalJitter, "Foveated: rotate ray positions every frame")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
    evalCmd->add_option("--frames", eval.frames, "Frames of the still view before the measured one")
        ->check(CLI::Range(1u, 1000u))
        ->capture_default_str();
    evalCmd->add_option("--reference-spp", eval.referenceSpp, "Rays per pixel of the reference")
        ->check(CLI::Range(1u, 4096u))
        ->capture_default_str();
    evalCmd->add_option("--reference", eval.reference,
                        "A reference PNG of the same view rendered before (skips rendering it)");
    evalCmd->add_option("--baseline", eval.baseline, "uniform | none")->capture_default_str();
    evalCmd->add_flag("--temporal", eval.temporal,
                      "Also the frame-to-frame change of a still view");
    evalCmd->add_option("--camera-path", eval.cameraPath,
                        "A moving camera (CSV t_ms,ex,ey,ez,tx,ty,tz): change after reprojection");
    evalCmd->add_option("--pursuit", eval.pursuit,
                        "A gaze trace in pixels (CSV t_ms,x,y) followed over the still scene");
    evalCmd->add_option("--sequence-frames", eval.sequenceFrames, "Frames of each sequence")
        ->check(CLI::Range(2u, 10000u))
        ->capture_default_str();
    evalCmd->add_flag("--sweep", eval.sweep, "Quality against rays: point-set scales 1, 1.5, 2, 3");
    evalCmd->add_option("--out", eval.out, "Folder for eval.json and the PNGs")
        ->capture_default_str();
    evalCmd->add_option("--cache", eval.cacheDir, "Point-set cache folder");
    evalCmd->add_flag("--validate", eval.validate, "Enable the Khronos validation layer");
    evalCmd->add_flag("--json", evalJson, "Print the JSON summary instead of the table");

    gt::app::BenchOptions bench;
    CLI::App* benchCmd = app.add_subcommand(
        "bench", "Table 1, Table 2 and foveated vs reference on the market (Google Benchmark)");
    benchCmd->add_option("--json", bench.json, "Also write the results as JSON to this file");
    benchCmd->add_flag("--quick", bench.quick, "Smoke test: fewer frames, no 32-ray frames");
    benchCmd->add_option("--scene", bench.scene, "Scene for the headline comparison")
        ->capture_default_str();
    benchCmd->add_option("--cache", bench.cacheDir, "Point-set cache folder");
    std::string benchSuite = "render";
    benchCmd
        ->add_option("--suite", benchSuite,
                     "render (thesis tables, headline, layers) | eye (pupil detection speed) | "
                     "stereo | layers (Guenter et al. 2012 only)")
        ->check(CLI::IsMember({"render", "eye", "stereo", "layers"}))
        ->capture_default_str();

    gt::app::SoakOptions soak;
    bool soakJson = false;
    CLI::App* soakCmd = app.add_subcommand(
        "soak", "Many frames with changing gaze and settings under validation; fails on any "
                "validation error or resident memory growth");
    soakCmd->add_option("--scene", soak.scene, "Scene")->capture_default_str();
    soakCmd->add_option("--frames", soak.frames, "Frames to render")
        ->check(CLI::Range(1u, 1000000u))
        ->capture_default_str();
    addSizeOptions(soakCmd, soak.width, soak.height, 16u, "Frame (default: the desktop screen's)");
    soakCmd
        ->add_option("--max-growth", soak.maxGrowthPercent,
                     "Resident memory growth allowed from frame 100 to the last, in percent")
        ->check(CLI::Range(0.0, 1000.0))
        ->capture_default_str();
    soakCmd->add_option("--cache", soak.cacheDir, "Point-set cache folder");
    soakCmd->add_option("--json-file", soak.json, "Also write the results as JSON to this file");
    soakCmd->add_flag("--json", soakJson, "Print the results as JSON on stdout");

    gt::app::EyesimOptions eyesim;
    CLI::App* eyesimCmd =
        app.add_subcommand("eyesim", "Render a synthetic infrared eye clip with ground truth");
    eyesimCmd->add_option("--seed", eyesim.seed, "Random seed (eye, schedule, noise)")
        ->capture_default_str();
    eyesimCmd->add_option("--frames", eyesim.frames, "Frames to render")
        ->check(CLI::Range(1, 1000000))
        ->capture_default_str();
    eyesimCmd->add_option("--size", eyesim.size, "Image size WxH")->capture_default_str();
    eyesimCmd->add_option("--fps", eyesim.fps, "Camera frame rate")
        ->check(CLI::Range(1.0, 2000.0))
        ->capture_default_str();
    eyesimCmd
        ->add_option("--preset", eyesim.preset,
                     "clean | hard (lid occlusion, 4 glints, blur, noise, blinks) | wild "
                     "(perspective camera, mascara, shadows, low contrast... drawn per seed)")
        ->check(CLI::IsMember({"clean", "hard", "wild"}))
        ->capture_default_str();
    eyesimCmd->add_option("--grid", eyesim.grid, "Calibration targets: 5, 9 or 13")
        ->check(CLI::IsMember({5, 9, 13}))
        ->capture_default_str();
    eyesimCmd
        ->add_option("--target-ms", eyesim.targetMs, "Time on each calibration / validation target")
        ->check(CLI::Range(100.0, 10000.0))
        ->capture_default_str();
    eyesimCmd->add_option("--out", eyesim.out, "Video file (.mkv or .avi, lossless FFV1)")
        ->required();
    eyesimCmd->add_option("--truth", eyesim.truth, "Per-frame truth CSV")->required();
    eyesimCmd->add_flag("--perspective", eyesim.perspective,
                        "Pinhole camera (the wild preset always has one)");
    eyesimCmd->add_option("--intrinsics-out", eyesim.intrinsicsOut,
                          "Write the eye camera's intrinsics (JSON) for --model 3d");
    eyesimCmd->add_option("--slip-mm", eyesim.slipMm,
                          "Headset slippage X,Y,Z in mm (camera frame), from --slip-at-ms on");
    eyesimCmd->add_option("--slip-deg", eyesim.slipDeg, "Headset turn with the slippage (degrees)");
    eyesimCmd->add_option("--slip-at-ms", eyesim.slipAtMs, "When the headset slips (default 0)");
    eyesimCmd->add_option("--eye", eyesim.eye,
                          "left or right (binocular clips, one camera per eye), or both (one "
                          "frame with both eyes side by side; --truth-right for the right's)");
    eyesimCmd->add_option("--ipd-mm", eyesim.ipdMm, "Interpupillary distance")
        ->capture_default_str();
    eyesimCmd->add_option("--depth-cm", eyesim.depthCm,
                          "Free viewing converges at this distance (0: on the screen)");
    eyesimCmd->add_option("--truth-right", eyesim.truthRight, "--eye both: the right eye's truth");
    bool eyesimJson = false;
    eyesimCmd->add_flag("--json", eyesimJson, "Print a JSON summary on stdout");

    gt::app::TrackOptions track;
    bool trackJson = false;
    CLI::App* trackCmd = app.add_subcommand(
        "track", "Track the pupil (and gaze, when calibrated) from a frame source");
    trackCmd->add_option("--source", track.source,
                         "v4l2:/dev/videoN[?...] | video:FILE | images:DIR | synthetic:SEED[?...]");
    trackCmd->add_option("--source-left", track.sourceLeft, "Two eyes: the left eye's camera");
    trackCmd->add_option("--source-right", track.sourceRight, "Two eyes: the right eye's camera");
    trackCmd->add_option("--regions", track.regions,
                         "Two eyes in one --source: X,Y,W,H;X,Y,W,H (left eye; right eye)");
    trackCmd->add_option("--truth-right", track.truthRight,
                         "Two eyes: the right eye's truth (--truth: the left's)");
    trackCmd->add_option("--ipd-mm", track.ipdMm, "Two eyes: interpupillary distance")
        ->capture_default_str();
    trackCmd->add_option("--detector", track.detector, "Pupil detector: starburst or blob")
        ->capture_default_str();
    trackCmd->add_option("--calibration", track.calibration,
                         "Calibration JSON (gazetrace calibrate)");
    trackCmd->add_option("--truth", track.truth,
                         "Truth CSV (gazetrace eyesim) to score the detector");
    trackCmd->add_option("--out", track.out,
                         "Gaze CSV t_ms,x,y (replays with render --gaze-trace)");
    trackCmd->add_option("--pupils", track.pupils, "Per-frame pupil CSV");
    trackCmd->add_option("--emit", track.emit, "Send each gaze sample as JSON to udp://HOST:PORT");
    trackCmd->add_option("--contact-sheet", track.contactSheet,
                         "PNG of every --sheet-every-th frame (up to 48) with the fitted pupil");
    trackCmd->add_option("--sheet-every", track.sheetEvery, "Frames between contact-sheet tiles")
        ->check(CLI::Range(1, 1000000));
    trackCmd->add_option("--max-frames", track.maxFrames, "Stop after this many frames")
        ->check(CLI::Range(0, 100000000));
    trackCmd->add_option("--model", track.model, "Gaze model: 2d (polynomial) or 3d (eye model)")
        ->capture_default_str();
    trackCmd->add_option("--eye", track.eye, "Eye of the calibration file: both, left or right")
        ->capture_default_str();
    trackCmd->add_option("--intrinsics", track.camera.intrinsics,
                         "Eye camera intrinsics JSON for --model 3d (default: the calibration's)");
    trackCmd->add_option("--focal", track.camera.focal, "Eye camera focal length, pixels");
    trackCmd->add_option("--principal", track.camera.principal, "Eye camera principal point X,Y");
    trackCmd->add_flag("--json", trackJson, "Print a JSON summary on stdout");

    gt::app::EyescoreOptions eyescore;
    bool eyescoreJson = false;
    CLI::App* eyescoreCmd = app.add_subcommand(
        "eyescore", "Score the pupil detector on synthetic clips (detection, ROC area, speed)");
    eyescoreCmd->add_option("--preset", eyescore.preset, "eyesim preset: clean, hard or wild")
        ->capture_default_str();
    eyescoreCmd->add_option("--detector", eyescore.detector, "Pupil detector: starburst or blob")
        ->capture_default_str();
    eyescoreCmd->add_option("--seeds", eyescore.seeds, "Seed N or range A-B, one clip each")
        ->capture_default_str();
    eyescoreCmd->add_option("--frames", eyescore.frames, "Frames per clip")->capture_default_str();
    eyescoreCmd
        ->add_option("--skip", eyescore.skip,
                     "Frames to skip first (default: into free viewing, with blinks and pursuit)")
        ->capture_default_str();
    eyescoreCmd->add_option("--radius", eyescore.radiusPx, "Right answers: within this many pixels")
        ->capture_default_str();
    eyescoreCmd->add_option("--threshold", eyescore.threshold,
                            "Confidence gate to report (default: the gaze filter's)");
    eyescoreCmd->add_option("--misses", eyescore.misses,
                            "CSV of the wrong answers and missed visible frames");
    eyescoreCmd->add_option(
        "--misses-sheet", eyescore.missesSheet,
        "PNG contact sheet of the missed frames (tile label: seed*100000+frame)");
    eyescoreCmd->add_option("--answers", eyescore.answers,
                            "CSV of every answer, right or not, with what its confidence weighed "
                            "(scripts/fit_answer_confidence.py)");
    eyescoreCmd->add_option("--sheet-every", eyescore.sheetEvery, "Misses between sheet tiles")
        ->capture_default_str();
    eyescoreCmd->add_flag("--json", eyescoreJson, "Print JSON on one line");

    gt::app::SlippageOptions slippage;
    bool slippageJson = false;
    CLI::App* slippageCmd = app.add_subcommand(
        "slippage", "Accuracy of the 2D and 3D gaze models before and after the headset slips");
    slippageCmd->add_option("--seeds", slippage.seeds, "eyesim seeds N or A-B")
        ->capture_default_str();
    slippageCmd->add_option("--preset", slippage.preset, "eyesim preset")->capture_default_str();
    slippageCmd->add_option("--slips-mm", slippage.slipsMm, "Slippage magnitudes in mm, A,B,..")
        ->capture_default_str();
    slippageCmd->add_option("--slip-deg", slippage.slipDeg, "Headset turn with each slip")
        ->capture_default_str();
    slippageCmd->add_option("--detector", slippage.detector, "Pupil detector")
        ->capture_default_str();
    slippageCmd->add_flag("--json", slippageJson, "Print JSON on one line");

    gt::app::CalibrateOptions calibrate;
    bool calibrateJson = false;
    std::string screen = "1920x1080";
    CLI::App* calibrateCmd = app.add_subcommand(
        "calibrate", "Fit pupil-to-screen calibration from a recording with known targets");
    calibrateCmd->add_option("--source-left", calibrate.sourceLeft,
                             "Two eyes: the left eye's recording");
    calibrateCmd->add_option("--source-right", calibrate.sourceRight,
                             "Two eyes: the right eye's recording");
    calibrateCmd->add_option("--regions", calibrate.regions,
                             "Two eyes in one --source: X,Y,W,H;X,Y,W,H (left eye; right eye)");
    calibrateCmd->add_option("--source", calibrate.source, "Frame source of the recording");
    calibrateCmd->add_option("--detector", calibrate.detector, "Pupil detector: starburst or blob")
        ->capture_default_str();
    calibrateCmd
        ->add_option("--targets", calibrate.targets,
                     "Target schedule CSV (t_ms,target_x,target_y[,phase,target_index])")
        ->required();
    calibrateCmd->add_option("--out", calibrate.out, "Calibration JSON to write")->required();
    calibrateCmd->add_option("--intrinsics", calibrate.camera.intrinsics,
                             "Eye camera intrinsics JSON: also calibrate the 3D eye model");
    calibrateCmd->add_option("--focal", calibrate.camera.focal, "Eye camera focal length, pixels");
    calibrateCmd->add_option("--principal", calibrate.camera.principal,
                             "Eye camera principal point X,Y");
    calibrateCmd
        ->add_option("--settle-ms", calibrate.settleMs,
                     "Ignore this long after each target appears")
        ->check(CLI::Range(0.0, 10000.0))
        ->capture_default_str();
    calibrateCmd->add_option("--screen", screen, "Screen size in pixels WxH")
        ->capture_default_str();
    calibrateCmd->add_option("--screen-width-cm", calibrate.display.widthCm, "Screen width in cm")
        ->check(CLI::Range(1.0, 1000.0))
        ->capture_default_str();
    calibrateCmd
        ->add_option("--distance-cm", calibrate.display.distanceCm, "Viewing distance in cm")
        ->check(CLI::Range(1.0, 1000.0))
        ->capture_default_str();
    calibrateCmd->add_flag("--json", calibrateJson, "Print a JSON summary on stdout");

    gt::app::DemoOptions demo;
    std::string demoTaa = "on";
    bool demoJson = false;
    CLI::App* demoCmd = app.add_subcommand(
        "demo", "Real-time window: foveated rendering driven by the mouse, a trace or the tracker");
    demoCmd->add_option("--scene", demo.scene, "builtin:NAME | FILE.gltf | FILE.glb | cubemap:FILE")
        ->capture_default_str();
    demoCmd->add_option("--width", demo.width, "Window width at start")
        ->check(CLI::Range(16u, 8192u))
        ->capture_default_str();
    demoCmd->add_option("--height", demo.height, "Window height at start")
        ->check(CLI::Range(16u, 8192u))
        ->capture_default_str();
    addLiveMethodOptions(demoCmd, demo.method, demo.interp, demo.k, demo.scale, demo.raysPerPoint,
                         demo.spp, demoTaa, demo.slope, demo.layers);
    demoCmd->add_option("--view", demo.view, "Debug view: points | cells | eccentricity");
    demoCmd
        ->add_option("--gaze", demo.gaze,
                     "mouse | fixed:X,Y | trace:FILE.csv | track:SOURCE | udp:PORT")
        ->capture_default_str();
    demoCmd->add_option("--calibration", demo.calibration,
                        "Calibration file for --gaze track: (written by --calibrate)");
    demoCmd->add_flag("--calibrate", demo.calibrate,
                      "Show 3x3 calibration and 4 validation targets, fit --gaze track:SOURCE, "
                      "write --calibration");
    demoCmd->add_option("--frame-ms", demo.frameMs,
                        "Advance trace and camera-path time this much per frame (default: "
                        "wall clock)");
    demoCmd->add_option("--frames", demo.frames, "Render this many frames, then exit");
    demoCmd->add_option("--screenshot", demo.screenshot, "Save the last presented frame (PNG)");
    demoCmd->add_option("--camera", demo.camera, "Start camera X,Y,Z,TX,TY,TZ[,FOV]");
    demoCmd->add_option("--camera-path", demo.cameraPath,
                        "Play a camera path CSV t_ms,ex,ey,ez,tx,ty,tz (R records one)");
    demoCmd->add_option("--present", demo.present, "fifo | mailbox | immediate")
        ->capture_default_str();
    demoCmd
        ->add_option("--frames-in-flight", demo.framesInFlight,
                     "1..4; 0 = automatic (1 on a CPU driver, 2 on a GPU)")
        ->capture_default_str();
    demoCmd->add_flag("--validate", demo.validate, "Khronos validation layer");
    std::string demoOverlay = "on";
    demoCmd->add_option("--overlay", demoOverlay, "on | off: the settings and timings overlay")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
    demoCmd->add_option("--log", demo.log, "Per-frame CSV: GPU time, gaze, latency");
    demoCmd->add_option("--cache", demo.cacheDir, "Point-set cache folder");
    demoCmd->add_flag("--json", demoJson, "Print a JSON summary");
    demoCmd->add_option("--resize", demo.resize, "FRAME:WxH: resize the window then (tests)");
    demoCmd->add_option("--hmd", demo.hmd,
                        "HMD path: fove | vive | rift-cv1, both eyes side by side in the window");
    bool demoNoDistortion = false;
    demoCmd->add_flag("--no-distortion", demoNoDistortion, "--hmd: no lens pre-distortion");
    demoCmd->add_flag("--display-space", demo.displaySpace,
                      "--hmd: lay the point set on the panel after the lens");
    demoCmd->add_option("--vergence-m", demo.vergenceM,
                        "--hmd: distance the eyes converge at in metres (0: infinity)");

    gt::app::XrOptions xr;
    bool xrJson = false;
    CLI::App* xrCmd = app.add_subcommand(
        "xr", "OpenXR application: both eyes foveated into the runtime's swapchains, eye gaze "
              "from the runtime or gazetrace's own sources");
    xrCmd->add_option("--scene", xr.scene, "builtin:NAME | FILE.gltf | FILE.glb | cubemap:FILE")
        ->capture_default_str();
    xrCmd->add_option("--camera", xr.camera,
                      "Start view X,Y,Z,TX,TY,TZ[,FOV]: the viewer stands at X,Y,Z facing the "
                      "target (default: the scene's camera, or a view inside it)");
    xrCmd->add_option("--xr-origin", xr.origin,
                      "X,Y,Z: the scene point at the reference space's origin (default: the "
                      "start view's eye; with --xr-space stage, 1.6 m below it)");
    xrCmd->add_option("--xr-yaw", xr.yawDeg,
                      "Degrees: the scene direction the viewer faces (default: the start view's)");
    xrCmd->add_option("--xr-scale", xr.worldScale, "Scene units per metre the head moves")
        ->capture_default_str();
    xrCmd->add_option("--xr-space", xr.space, "local | stage (floor-level; LOCAL if not offered)")
        ->capture_default_str();
    xrCmd
        ->add_option("--resolution-scale", xr.resolutionScale,
                     "Eye image size as a share of the runtime's recommended size")
        ->capture_default_str();
    std::string xrTaa = "on";
    addLiveMethodOptions(xrCmd, xr.method, xr.interp, xr.k, xr.pointScale, xr.raysPerPoint, xr.spp,
                         xrTaa, xr.slope, xr.layers);
    xrCmd
        ->add_option("--reconstruction", xr.reconstruction,
                     "Foveated: gazetrace | thesis (the thesis's interpolation and TAA as published)")
        ->check(CLI::IsMember({"gazetrace", "thesis"}))
        ->capture_default_str();
    xrCmd
        ->add_option("--gaze", xr.gaze,
                     "Gaze when the runtime gives none: ahead | fixed:X,Y (left eye pixels) | "
                     "trace:FILE.csv | track:SOURCE | udp:PORT")
        ->capture_default_str();
    xrCmd->add_option("--calibration", xr.calibration, "Calibration file for --gaze track:");
    xrCmd
        ->add_option("--vergence-m", xr.vergenceM,
                     "Distance the eyes converge at in metres (0: infinity)")
        ->capture_default_str();
    bool xrNoRuntimeGaze = false;
    xrCmd->add_flag("--no-runtime-gaze", xrNoRuntimeGaze,
                    "Ignore XR_EXT_eye_gaze_interaction; use --gaze only");
    xrCmd->add_option("--frames", xr.frames, "Render this many frames, then end the session")
        ->check(CLI::Range(0u, 10000000u))
        ->capture_default_str();
    std::vector<std::string> xrShot;
    xrCmd->add_option("--screenshot-eye", xrShot, "left|right FILE.png: that eye's last image")
        ->expected(2);
    xrCmd
        ->add_option("--start-timeout", xr.startTimeoutS,
                     "Seconds the session may take to start running")
        ->capture_default_str();
    xrCmd->add_flag("--validate", xr.validate, "Khronos validation layer");
    xrCmd->add_option("--cache", xr.cacheDir, "Point-set cache folder");
    xrCmd->add_flag("--json", xrJson, "Print a JSON summary");

    CLI::App* devicesCmd = app.add_subcommand("devices", "List the Vulkan devices");
    CLI::App* scenesCmd = app.add_subcommand("scenes", "List the built-in scenes");

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        return fail(e.what());
    }
    if (quiet) gt::log::setLevel(gt::log::Level::Error);

    try {
        if (renderCmd->parsed()) {
            render.taa = taaFlag == "on";
            render.halfRate = renderHalfRate == "on";
            render.jitter = renderJitter == "on";
            render.lod = renderLod == "on";
            render.distortion = !noDistortion;
            render.framesGiven = renderCmd->count("--frames") > 0;
            render.sizeGiven = renderCmd->count("--width") + renderCmd->count("--height") > 0;
            const nlohmann::json result = gt::app::runRender(render);
            if (renderJson)
                std::cout << result.dump() << std::endl;
            else
                gt::log::info("wrote " + render.out);
        } else if (pointsetCmd->parsed()) {
            const nlohmann::json result = gt::app::runPointSet(pointset);
            std::cout << (pointsetJson ? result.dump() : result.dump(2)) << std::endl;
        } else if (layersCmd->parsed()) {
            const nlohmann::json result = gt::app::runLayers(layers);
            std::cout << (layersJson ? result.dump() : gt::app::layersText(result)) << std::flush;
        } else if (benchCmd->parsed()) {
            if (benchSuite == "eye") {
                (void)gt::app::runEyeBench();
            } else if (benchSuite == "layers") {
                (void)gt::app::runLayersBench(bench);
            } else if (benchSuite == "stereo") {
                (void)gt::app::runStereoBench(bench);
            } else {
                (void)gt::app::runBench(bench);
            }
        } else if (evalCmd->parsed()) {
            eval.taa = evalTaa == "on";
            eval.jitter = evalJitter == "on";
            const nlohmann::json result = gt::app::runEval(eval);
            std::cout << (evalJson ? result.dump() : gt::app::evalText(result)) << std::flush;
        } else if (soakCmd->parsed()) {
            soak.quiet = quiet;
            const nlohmann::json result = gt::app::runSoak(soak);
            if (soakJson) std::cout << result.dump() << std::endl;
        } else if (eyesimCmd->parsed()) {
            const nlohmann::json result = gt::app::runEyesim(eyesim);
            if (eyesimJson) std::cout << result.dump() << std::endl;
        } else if (trackCmd->parsed()) {
            if (track.source.empty() && track.sourceLeft.empty() && track.sourceRight.empty())
                throw gt::ArgumentError("track: --source (or --source-left and --source-right)");
            const nlohmann::json result = gt::app::runTrack(track);
            std::cout << (trackJson ? result.dump() : result.dump(2)) << std::endl;
        } else if (slippageCmd->parsed()) {
            const nlohmann::json result = gt::app::runSlippage(slippage);
            std::cout << (slippageJson ? result.dump() : result.dump(2)) << std::endl;
        } else if (eyescoreCmd->parsed()) {
            const nlohmann::json result = gt::app::runEyescore(eyescore);
            std::cout << (eyescoreJson ? result.dump() : result.dump(2)) << std::endl;
        } else if (calibrateCmd->parsed()) {
            // Range checks let NaN through (every comparison with it is false), and %d wrapped
            // 99999999999 to 1215752191: both are refused here.
            unsigned long w = 0, h = 0;
            char x = 0, extra = 0;
            if (std::sscanf(screen.c_str(), "%lu%c%lu%c", &w, &x, &h, &extra) != 3 || x != 'x' ||
                w == 0 || h == 0 || w > 32768 || h > 32768 || screen.find('-') != std::string::npos)
                throw gt::ArgumentError("--screen " + screen +
                                        ": expected WxH, each 1..32768 pixels");
            calibrate.display.widthPx = static_cast<int>(w);
            calibrate.display.heightPx = static_cast<int>(h);
            for (const auto& [name, value] :
                 {std::pair{"--screen-width-cm", calibrate.display.widthCm},
                  std::pair{"--distance-cm", calibrate.display.distanceCm}}) {
                if (!std::isfinite(value) || value < 1.0 || value > 1000.0)
                    throw gt::ArgumentError(std::string(name) + ": expected 1..1000 cm, got " +
                                            std::to_string(value));
            }
            const nlohmann::json result = gt::app::runCalibrate(calibrate);
            std::cout << (calibrateJson ? result.dump() : result.dump(2)) << std::endl;
        } else if (demoCmd->parsed()) {
            demo.taa = demoTaa == "on";
            demo.distortion = !demoNoDistortion;
            demo.overlay = demoOverlay == "on";
            demo.given = {demoCmd->count("--interp") > 0, demoCmd->count("--k") > 0,
                          demoCmd->count("--scale") > 0, demoCmd->count("--rays-per-point") > 0};
            const nlohmann::json result = gt::app::runDemo(demo);
            if (demoJson) std::cout << result.dump() << std::endl;
        } else if (xrCmd->parsed()) {
            xr.taa = xrTaa == "on";
            xr.runtimeGaze = !xrNoRuntimeGaze;
            if (xrShot.size() == 2) {
                xr.screenshotEye = xrShot[0];
                xr.screenshot = xrShot[1];
            }
            const nlohmann::json result = gt::app::runXr(xr);
            if (xrJson) std::cout << result.dump() << std::endl;
        } else if (devicesCmd->parsed()) {
            for (const std::string& line : gt::vk::Context::listDevices())
                std::cout << line << "\n";
        } else if (scenesCmd->parsed()) {
            for (const std::string& s : gt::scene::builtinSceneNames())
                std::cout << s << "\n";
        }
    } catch (const gt::Error& e) {
        return fail(e.what());
    } catch (const std::exception& e) {
        return fail(e.what());
    }
    // What was asked for on standard output (--json, a listing) must have got there: a full
    // disk or a closed pipe is a failed run, not a silent success.
    std::cout.flush();
    if (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout)) {
        return fail("cannot write to standard output (disk full or pipe closed?)");
    }
    return 0;
}
