#include "render_command.hpp"
#include "view_args.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "atomic_write.hpp"
#include "capture/frame_source.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "display/hmd_profile.hpp"
#include "eccentricity_layers.hpp"
#include "foveation/gaze_trace.hpp"
#include "foveation/neighbour_index.hpp"
#include "foveation/point_set_cache.hpp"
#include "full_resolution.hpp"
#include "gaze/gaze_tracker.hpp"
#include "gaze_mapping.hpp"
#include "layers_command.hpp"
#include "method_factory.hpp"
#include "option_parsing.hpp"
#include "output_target.hpp"
#include "point_set_method.hpp"
#include "renderer.hpp"
#include "scene/camera_path.hpp"
#include "scene/image_io.hpp"
#include "scene/scene.hpp"
#include "stereo_rig.hpp"
#include "vk/context.hpp"

namespace gt::app {

namespace {

// The camera as --camera takes it, so a framing found here can be given back.
nlohmann::json cameraJson(const scene::Camera& c) {
    const glm::vec3 target = c.position + glm::normalize(c.forward);
    return {{"position", {c.position.x, c.position.y, c.position.z}},
            {"target", {target.x, target.y, target.z}},
            {"yfov_deg", glm::degrees(c.yfov)}};
}

// Frames clamp a trace's gaze to the screen; say so when samples lie outside it, since many
// of them usually mean the trace was recorded for another screen.
void warnOffScreen(const foveation::GazeTrace& trace, const std::string& file, uint32_t w,
                   uint32_t h) {
    const auto& samples = trace.samples();
    const auto outside = std::count_if(samples.begin(), samples.end(), [&](const auto& s) {
        return s.position.x < 0.0f || s.position.y < 0.0f ||
               s.position.x >= static_cast<float>(w) || s.position.y >= static_cast<float>(h);
    });
    if (outside == 0) {
        return;
    }
    log::warn(file + ": " + std::to_string(outside) + " of " + std::to_string(samples.size()) +
              " gaze samples lie outside the " + std::to_string(w) + "x" + std::to_string(h) +
              " screen; the gaze is clamped to its edge there");
}

// One frame at a time (each is written before the next), on GAZETRACE_DEVICE if set.
render::RendererOptions rendererOptions(const RenderOptions& o) {
    return {.scene = o.scene,
            .validate = o.validate,
            .framesInFlight = 1,
            .deviceOverride = deviceRequest(),
            .sceneLoad = gltfLoadOptions()};
}

// What this run wrote: removed again unless the run succeeds, so a failed run (a full disk at
// frame 7, a tracker clip cut short, validation errors at the end) leaves none of its outputs.
bool prepareOutput(const std::filesystem::path& outPath, bool toFolder, const std::string& out,
                   uint32_t frames);

class RunOutputs {
public:
    // Checks --out before any work (prepareOutput); a folder it makes is this run's output too,
    // removed again if it is empty after a failure.
    RunOutputs(const std::filesystem::path& out, bool toFolder, const std::string& text,
               uint32_t frames) {
        if (prepareOutput(out, toFolder, text, frames)) add(out);
    }
    RunOutputs(const RunOutputs&) = delete;
    RunOutputs& operator=(const RunOutputs&) = delete;
    ~RunOutputs() {
        if (mKeep) return;
        // Newest first: the frames, then the folder they were written into (only if empty).
        for (auto it = mFiles.rbegin(); it != mFiles.rend(); ++it) {
            std::error_code ec;
            std::filesystem::remove(*it, ec);
        }
    }
    void add(const std::filesystem::path& f) { mFiles.push_back(f); }
    void keep() noexcept { mKeep = true; }

private:
    std::vector<std::filesystem::path> mFiles;
    bool mKeep = false;
};

// --out: a .png file (any case) for one frame, else a folder for frame_NNNN.png.
bool outIsFolder(const std::filesystem::path& out) {
    std::string ext = out.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext != ".png";
}

// Frame i's file: the PNG itself, or frame_NNNN.png in the output folder.
std::filesystem::path frameFile(const std::filesystem::path& out, bool toFolder, uint32_t i) {
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%04u.png", i);
    return toFolder ? out / name : out;
}

// A run with validation errors has failed, whatever it wrote; else the last frame's GPU times.
nlohmann::json checkedPassTimes(const vk::Context& ctx, const std::optional<rg::FrameTimings>& t) {
    if (ctx.validationErrors() > 0) {
        throw Error(std::to_string(ctx.validationErrors()) + " Vulkan validation error(s)");
    }
    nlohmann::json gpu = nlohmann::json::object();
    if (t) {
        for (const auto& p : t->passes) {
            gpu[p.name] = p.gpuMs;
        }
    }
    return gpu;
}

// Fail before any work when the output could not be written anyway.
// Returns whether it created the output folder.
bool prepareOutput(const std::filesystem::path& outPath, bool toFolder, const std::string& out,
                   uint32_t frames) {
    if (!toFolder && frames > 1) {
        throw ArgumentError("--out: give a folder for --frames > 1");
    }
    std::error_code folderEc;
    if (!toFolder && std::filesystem::is_directory(outPath, folderEc)) {
        throw ArgumentError("--out: " + out + " is a folder; give a file name ending in .png");
    }
    const std::filesystem::path dir = toFolder                        ? outPath
                                      : outPath.parent_path().empty() ? "."
                                                                      : outPath.parent_path();
    std::error_code ec;
    const bool existed = std::filesystem::is_directory(dir, ec);
    if (toFolder && !existed) {
        std::filesystem::create_directories(dir, ec);
    }
    if (!std::filesystem::is_directory(dir, ec)) {
        throw ArgumentError("--out: cannot write " + out + ": folder " + dir.string() +
                            " does not exist");
    }
    return toFolder && !existed;
}

void writeText(const std::string& path, const std::string& text) {
    io::writeFileAtomic(path, text);
}

} // namespace

namespace {

render::EccentricityLayerSettings
renderLayerSettings(const RenderOptions& o, std::optional<foveation::DisplayProfile> display) {
    render::EccentricityLayerSettings s = layerSettings(o.slope, o.layers, o.spp);
    s.halfRate = o.halfRate;
    s.jitter = o.jitter;
    s.temporal = o.taa;
    s.lod = o.lod;
    s.display = std::move(display);
    return s;
}

nlohmann::json layersJson(render::EccentricityLayers& layers, const render::View& view) {
    const render::LayerLayout& lay = layers.layout(view);
    const std::vector<bool> traced = layers.tracedLastFrame(view);
    nlohmann::json list = nlohmann::json::array();
    for (std::size_t i = 0; i < lay.grids.size(); ++i) {
        const render::LayerGrid& g = lay.grids[i];
        list.push_back({{"e_deg", lay.plan.layers[i].radiusDeg},
                        {"s", g.pitch},
                        {"width", g.width},
                        {"height", g.height},
                        {"radius_px", g.radiusPx},
                        {"traced", i < traced.size() && traced[i]}});
    }
    return {{"slope", layers.settings().slope},
            {"layers", list},
            {"layer_pixels", lay.pixels()},
            {"predicted_P", lay.plan.work},
            {"predicted_P_star", lay.plan.displayPixels},
            {"predicted_speedup", lay.plan.speedup()},
            {"half_rate", layers.settings().halfRate},
            {"jitter", layers.settings().jitter},
            {"temporal", layers.settings().temporal}};
}

// `render --hmd NAME`: both eyes of the profile in one render graph (scopes left., right.), each
// with its off-axis frustum, its own gaze and its lens, composed into the side-by-side frame an
// extended-mode HMD shows. --gaze and --gaze-trace are pixels of the left eye's image.
nlohmann::json runRenderHmd(const RenderOptions& o) {
    const display::HmdProfile profile = hmdProfile(o.hmd);
    const bool foveated = o.method == "foveated";
    if (o.method != "reference" && o.method != "layers" && !foveated) {
        throw ArgumentError("--method: '" + o.method + "' (known: reference, foveated, layers)");
    }
    if (o.sizeGiven) {
        throw ArgumentError("--width/--height: --hmd " + o.hmd + " renders " +
                            std::to_string(profile.eyeWidth) + "x" +
                            std::to_string(profile.eyeHeight) + " per eye");
    }
    if (!o.gazeSource.empty()) {
        throw ArgumentError("--gaze-source is not available with --hmd yet (use --gaze-trace)");
    }
    if (o.displaySpace && (!foveated || !o.distortion)) {
        throw ArgumentError("--display-space needs --method foveated and the lens (no "
                            "--no-distortion)");
    }
    if (!(o.vergenceM >= 0.0) || !std::isfinite(o.vergenceM)) {
        throw ArgumentError("--vergence-m must be 0 (infinity) or a positive distance");
    }
    const uint32_t w = profile.eyeWidth, h = profile.eyeHeight;
    glm::vec2 gazePx = parseGaze(o.gaze, w, h);
    std::optional<foveation::GazeTrace> trace;
    uint32_t frameCount = o.frames;
    if (!o.gazeTrace.empty()) {
        if (!o.gaze.empty()) throw ArgumentError("--gaze and --gaze-trace exclude each other");
        if (!(o.frameMs > 0.0)) throw ArgumentError("--frame-ms must be positive");
        trace = foveation::GazeTrace::load(o.gazeTrace);
        if (trace->units() == foveation::GazeUnits::Pixels) {
            warnOffScreen(*trace, o.gazeTrace, w, h);
        }
        if (!o.framesGiven) {
            frameCount = 1 + static_cast<uint32_t>((trace->endMs() - trace->startMs()) / o.frameMs);
        }
    }
    const std::filesystem::path outPath(o.out);
    const bool toFolder = outIsFolder(outPath);
    RunOutputs written(outPath, toFolder, o.out, frameCount);
    const std::optional<CameraArg> cameraArg = parseCamera(o.camera);
    render::Renderer renderer(rendererOptions(o));
    scene::Camera head = renderer.scene().camera;
    if (cameraArg) head = cameraArg->camera(head.yfov);
    std::unique_ptr<render::FullResolution> reference;
    std::unique_ptr<render::PointSetMethod> pointSet;
    std::unique_ptr<render::EccentricityLayers> layers;
    render::FoveationMethod* method = nullptr;
    if (o.method == "layers") {
        // Each eye's layers from its own frustum: the HMD image fills the eye's field of view.
        layers = render::makeMethod(render::LayersConfig{renderLayerSettings(o, std::nullopt)},
                                    renderer.methodContext());
        method = &*layers;
    } else if (foveated) {
        foveation::PointSetParams params;
        params.display = foveation::displayProfile(profile.pointSetProfile);
        params.scale = o.scale;
        if (o.k == 0 || o.k > foveation::NeighbourIndex::kMaxNeighbours) {
            throw ArgumentError("--k must be 1..20");
        }
        passes::InterpolateSettings interp;
        interp.method = o.view.empty() ? parseInterpolation(o.interp) : parseView(o.view);
        interp.k = o.k;
        interp.kernel = parseKernel(o.kernel);
        interp.rbfShape = static_cast<float>(o.rbfShape);
        interp.knn = parseKnnIndex(o.knn);
        pointSet = render::makeMethod(
            render::PointSetConfig{params,
                                   o.cacheDir.empty() ? defaultCacheDir()
                                                      : std::filesystem::path(o.cacheDir),
                                   {o.raysPerPoint, interp, o.displaySpace && o.distortion, o.lod}},
            renderer.methodContext());
        method = &*pointSet;
    } else {
        reference = render::makeMethod(
            render::FullResolutionConfig{passes::ReferenceSettings{o.spp, o.seed}},
            renderer.methodContext());
        method = &*reference;
    }
    const render::StereoRig rig(profile, o.distortion);
    render::PostSettings post;
    post.taa = foveated && o.taa && o.view.empty();
    if (pointSet && parseReconstruction(o.reconstruction) == render::Reconstruction::Thesis) {
        render::useThesisReconstruction(pointSet->settings, post.taaSettings);
    }
    render::CompositeReadbackTarget composite(renderer.context(), 2 * w, h);
    composite.place("left", {{0, 0}, {w, h}});
    composite.place("right", {{static_cast<int32_t>(w), 0}, {w, h}});
    render::OutputTarget* const targets[2] = {&composite, &composite};
    render::FrameResult frame;
    std::array<render::View, 2> views;
    std::vector<double> frameMs;
    std::vector<std::string> outputs;
    const glm::vec2 lastPixel(static_cast<float>(w) - 1.0f, static_cast<float>(h) - 1.0f);
    for (uint32_t i = 0; i < frameCount; ++i) {
        render::StereoGaze gaze;
        const double t = trace ? trace->startMs() + i * o.frameMs : 0.0;
        if (trace && trace->units() == foveation::GazeUnits::AnglesDeg) {
            // Angles: one direction for both eyes, or each tracked eye its own.
            gaze.direction = render::directionOfAngles(trace->at(t));
            for (const auto eye : {foveation::GazeEye::Left, foveation::GazeEye::Right}) {
                if (trace->hasEye(eye)) {
                    gaze.eyeDirection[eye == foveation::GazeEye::Left ? 0 : 1] =
                        render::directionOfAngles(trace->at(t, eye));
                }
            }
        } else {
            if (trace) gazePx = glm::clamp(trace->at(t), glm::vec2(0.0f), lastPixel);
            gaze.direction = rig.directionOfLeftPixel(gazePx);
        }
        if (reference) reference->settings.frameSeed = o.seed + i;
        if (o.vergenceM > 0.0) gaze.vergenceM = static_cast<float>(o.vergenceM);
        views = rig.views(head, gaze, *method, post, renderer.scene().exposure);
        const bool dot = !o.graphDot.empty() && i == 0;
        frame = renderer.renderFrame(views, targets, {.graphviz = dot});
        frameMs.push_back(frame.wallMs);
        if (dot) {
            writeText(o.graphDot, frame.dot);
            written.add(o.graphDot);
        }
        const std::filesystem::path file = frameFile(outPath, toFolder, i);
        image::writePngAtomic(file, 2 * w, h, composite.pixels());
        written.add(file);
        outputs.push_back(file.string());
    }
    vk::Context& ctx = renderer.context();
    const nlohmann::json gpu = checkedPassTimes(ctx, frame.timings);
    const rg::FrameTimings timings = frame.timings.value_or(rg::FrameTimings{});
    std::sort(frameMs.begin(), frameMs.end());
    nlohmann::json eyes = nlohmann::json::array();
    uint64_t rays = 0;
    for (std::size_t e = 0; e < 2; ++e) {
        rays += frame.views[e].rays;
        eyes.push_back({{"name", views[e].name},
                        {"gaze", {views[e].gaze.x, views[e].gaze.y}},
                        {"rays", frame.views[e].rays},
                        {"tangents",
                         {views[e].frustum->left, views[e].frustum->right, views[e].frustum->up,
                          views[e].frustum->down}}});
    }
    if (layers) {
        for (std::size_t e = 0; e < 2; ++e)
            eyes[e]["layers"] = layersJson(*layers, views[e]);
    }
    written.keep();
    return {{"device", ctx.deviceName()},
            {"device_type", ctx.deviceDescription()},
            {"scene", o.scene},
            {"hmd", profile.name},
            {"hmd_sources", profile.sources},
            {"eye_width", w},
            {"eye_height", h},
            {"width", 2 * w},
            {"height", h},
            {"method", o.method},
            {"distortion", o.distortion},
            {"display_space", o.displaySpace},
            {"vergence_m", o.vergenceM},
            {"eyes", eyes},
            {"rays", rays},
            {"frames", frameCount},
            {"gpu_ms", gpu},
            {"gpu_total_ms", timings.gpuMs},
            {"total_ms", frameMs[frameMs.size() / 2]},
            {"camera", cameraJson(head)},
            {"output", toFolder ? outPath.string() : outputs.front()}};
}

} // namespace

nlohmann::json runRender(const RenderOptions& o) {
    if (o.method == "layers") (void)parseSlope(o.slope); // before any work
    if (!o.hmd.empty()) {
        return runRenderHmd(o);
    }
    if (o.method != "reference" && o.method != "foveated" && o.method != "layers") {
        throw ArgumentError("--method: '" + o.method +
                            "' is not available (known: reference, foveated, layers)");
    }
    if (o.out.empty()) {
        throw ArgumentError("--out: empty path");
    }
    const bool foveated = o.method == "foveated";
    const bool layered = o.method == "layers";
    const bool gazeDriven = foveated || layered;
    uint32_t width = o.width, height = o.height;
    foveation::PointSetParams psParams;
    passes::InterpolateSettings interp;
    glm::vec2 gaze{};
    if (foveated) {
        psParams.display = displayProfile(o.profile);
        psParams.scale = o.scale;
        if (o.sizeGiven && o.profile == "desktop") {
            // A window on the desktop screen: its own point set at the screen's pixels per degree.
            psParams.display = foveation::windowProfile(psParams.display, o.width, o.height);
        } else if (o.sizeGiven &&
                   (o.width != psParams.display.width || o.height != psParams.display.height)) {
            throw ArgumentError("--width/--height: the " + o.profile + " profile renders " +
                                std::to_string(psParams.display.width) + "x" +
                                std::to_string(psParams.display.height));
        }
        width = psParams.display.width;
        height = psParams.display.height;
        interp.method = parseInterpolation(o.interp);
        interp.k = o.k;
        interp.kernel = parseKernel(o.kernel);
        interp.rbfShape = static_cast<float>(o.rbfShape);
        interp.knn = parseKnnIndex(o.knn);
        if (o.k == 0 || o.k > foveation::NeighbourIndex::kMaxNeighbours) {
            throw ArgumentError("--k must be 1..20");
        }
        gaze = parseGaze(o.gaze, width, height);
        if (!o.view.empty()) {
            interp.method = parseView(o.view);
        }
    } else if (layered) {
        // The profile's screen (or a window on it, with --width/--height): layer sizes follow
        // its viewing geometry, as the point set's do.
        const foveation::DisplayProfile screen = displayProfile(o.profile);
        if (!o.sizeGiven) {
            width = screen.width;
            height = screen.height;
        }
        gaze = parseGaze(o.gaze, width, height);
    }
    std::optional<foveation::GazeTrace> trace;
    uint32_t frameCount = o.frames;
    if (!o.gazeTrace.empty()) {
        if (!gazeDriven) {
            throw ArgumentError("--gaze-trace needs --method foveated or layers");
        }
        if (!(o.frameMs > 0.0)) {
            throw ArgumentError("--frame-ms must be positive");
        }
        if (!o.gaze.empty()) {
            throw ArgumentError("--gaze and --gaze-trace exclude each other");
        }
        trace = foveation::GazeTrace::load(o.gazeTrace);
        if (trace->units() == foveation::GazeUnits::Pixels) {
            warnOffScreen(*trace, o.gazeTrace, width, height);
        }
        if (!o.framesGiven) {
            frameCount = 1 + static_cast<uint32_t>((trace->endMs() - trace->startMs()) / o.frameMs);
        }
    }
    // Live gaze: source and calibration are opened now, so a bad one fails before any work;
    // the tracker thread starts with the first frame.
    std::unique_ptr<eyetrack::FrameSource> gazeSource;
    std::optional<eyetrack::Calibration> calibration;
    if (!o.gazeSource.empty()) {
        if (!gazeDriven) {
            throw ArgumentError("--gaze-source needs --method foveated or layers");
        }
        if (trace) {
            throw ArgumentError("--gaze-source and --gaze-trace exclude each other");
        }
        if (!o.gaze.empty()) {
            throw ArgumentError("--gaze and --gaze-source exclude each other");
        }
        if (o.calibration.empty()) {
            throw ArgumentError("--gaze-source needs --calibration (see gazetrace calibrate)");
        }
        calibration = eyetrack::Calibration::load(o.calibration);
        gazeSource = eyetrack::openFrameSource(o.gazeSource);
    } else if (!o.calibration.empty()) {
        throw ArgumentError("--calibration is for --gaze-source");
    }
    if (!foveated && !o.view.empty()) {
        throw ArgumentError("--view needs --method foveated");
    }
    if (!gazeDriven && !o.gaze.empty()) {
        throw ArgumentError("--gaze needs --method foveated or layers");
    }
    // --camera-path: the camera follows a recorded path, one frame every --frame-ms.
    std::optional<scene::CameraPath> path;
    if (!o.cameraPath.empty()) {
        if (!(o.frameMs > 0.0)) throw ArgumentError("--frame-ms must be positive");
        path = scene::CameraPath::load(o.cameraPath);
        if (!o.framesGiven) {
            frameCount =
                std::max(trace ? frameCount : 1u,
                         1 + static_cast<uint32_t>((path->endMs() - path->startMs()) / o.frameMs));
        }
    }
    // --out: a .png file for one frame, else a folder for frame_NNNN.png.
    const std::filesystem::path outPath(o.out);
    const bool toFolder = outIsFolder(outPath);
    RunOutputs written(outPath, toFolder, o.out, frameCount);
    const std::optional<CameraArg> cameraArg = parseCamera(o.camera);
    render::Renderer renderer(rendererOptions(o));
    render::View view;
    view.camera = renderer.scene().camera;
    if (cameraArg) {
        view.camera = scene::lookAt(cameraArg->eye, cameraArg->target,
                                    cameraArg->yfovDeg ? glm::radians(*cameraArg->yfovDeg)
                                                       : renderer.scene().camera.yfov);
    }
    view.width = width;
    view.height = height;
    view.exposure = renderer.scene().exposure;
    view.post.taa = false;
    std::unique_ptr<render::FullResolution> reference;
    std::unique_ptr<render::PointSetMethod> pointSet;
    std::unique_ptr<render::EccentricityLayers> layers;
    if (layered) {
        layers = render::makeMethod(
            render::LayersConfig{renderLayerSettings(o, displayProfile(o.profile))},
            renderer.methodContext());
        view.method = &*layers;
        view.gaze = gaze;
    } else if (foveated) {
        pointSet = render::makeMethod(
            render::PointSetConfig{psParams,
                                   o.cacheDir.empty() ? defaultCacheDir()
                                                      : std::filesystem::path(o.cacheDir),
                                   {o.raysPerPoint, interp, false, o.lod}},
            renderer.methodContext());
        view.method = &*pointSet;
        view.gaze = gaze;
        view.post.taa = o.taa && o.view.empty(); // debug views show one frame's data as is
        if (parseReconstruction(o.reconstruction) == render::Reconstruction::Thesis) {
            render::useThesisReconstruction(pointSet->settings, view.post.taaSettings);
        }
    } else {
        reference = render::makeMethod(
            render::FullResolutionConfig{passes::ReferenceSettings{o.spp, o.seed}},
            renderer.methodContext());
        view.method = &*reference;
    }
    std::optional<eyetrack::GazeTracker> tracker;
    std::uint64_t saccadesSeen = 0;
    if (gazeSource) {
        tracker.emplace(std::move(gazeSource), *calibration);
        (void)tracker->waitForFirstSample(2000.0); // a camera may take a moment to stream
    }
    render::ReadbackTarget readback(renderer.context());
    render::OutputTarget* const target = &readback;
    render::FrameResult frame;
    std::vector<double> frameMs;
    std::vector<std::string> outputs;
    nlohmann::json gazes = nlohmann::json::array();
    const glm::vec2 lastPixel(static_cast<float>(width) - 1.0f, static_cast<float>(height) - 1.0f);
    // Gaze angles on this render. The desktop profile: the physical screen (1920 px, 51 cm wide,
    // 59 cm away), this render a window centred on it; an HMD eye (fove, vive) rendered on its
    // own: through the view's projection. No flat rescaling of pixels between screens.
    auto gazePixelOfAngles = [&](glm::vec2 angles) {
        const render::ScreenGeometry screen;
        return o.profile == "desktop" ? screen.pixelOfAngles(angles) -
                                            render::centredWindowOrigin(screen, {width, height})
                                      : render::pixelOfAnglesInView(angles, view);
    };
    for (uint32_t i = 0; i < frameCount; ++i) {
        const bool dot = !o.graphDot.empty() && i == 0;
        if (path) view.camera = path->at(path->startMs() + i * o.frameMs, view.camera.yfov);
        if (trace) {
            const glm::vec2 g = trace->at(trace->startMs() + i * o.frameMs);
            glm::vec2 px = g;
            if (trace->units() == foveation::GazeUnits::AnglesDeg) {
                px = gazePixelOfAngles(g);
            }
            view.gaze = glm::clamp(px, glm::vec2(0.0f), lastPixel);
        }
        if (tracker) {
            if (const auto e = tracker->error()) {
                throw Error("--gaze-source " + o.gazeSource + ": " + *e);
            }
            if (const auto g = tracker->mailbox().latest()) {
                // The calibration fits gaze angles: back from its screen's pixels to angles, then
                // onto this render as an angle trace lands (gazePixelOfAngles).
                const cv::Point2d a = tracker->display().anglesDeg({g->x, g->y});
                view.gaze = glm::clamp(
                    gazePixelOfAngles(glm::vec2(static_cast<float>(a.x), static_cast<float>(a.y))),
                    glm::vec2(0.0f), lastPixel);
            }
            // A saccade since the last frame: the TAA history is dropped (thesis, 3.1).
            const std::uint64_t saccades = tracker->saccades();
            view.saccade = saccades != saccadesSeen;
            saccadesSeen = saccades;
        }
        if (gazeDriven) {
            gazes.push_back({view.gaze.x, view.gaze.y});
        } else {
            reference->settings.frameSeed = o.seed + i;
        }
        frame = renderer.renderFrame(std::span(&view, 1), std::span(&target, 1), {.graphviz = dot});
        frameMs.push_back(frame.wallMs);
        if (dot) {
            writeText(o.graphDot, frame.dot);
            written.add(o.graphDot);
        }
        const std::filesystem::path file = frameFile(outPath, toFolder, i);
        image::writePngAtomic(file, width, height, readback.pixels());
        written.add(file);
        outputs.push_back(file.string());
    }
    vk::Context& ctx = renderer.context();
    const nlohmann::json gpu = checkedPassTimes(ctx, frame.timings);
    const rg::FrameTimings timings = frame.timings.value_or(rg::FrameTimings{});
    std::vector<double> sorted = frameMs;
    std::sort(sorted.begin(), sorted.end());
    const double totalMs = sorted[sorted.size() / 2];
    uint64_t rays = static_cast<uint64_t>(width) * height * o.spp;
    nlohmann::json j = {{"device", ctx.deviceName()},
                        {"device_type", ctx.deviceDescription()},
                        {"scene", o.scene},
                        {"triangles", renderer.scene().triangleCount()},
                        {"lod_triangles", renderer.lodTriangles()},
                        {"lod", o.lod},
                        {"width", width},
                        {"height", height},
                        {"method", o.method},
                        {"gpu_ms", gpu},
                        {"gpu_total_ms", timings.gpuMs},
                        {"total_ms", totalMs},
                        {"frames", frameCount},
                        {"load_ms", renderer.loadMs()},
                        {"bvh_ms", renderer.bvhMs()},
                        {"bvh_nodes", renderer.bvhStats().nodes},
                        {"bvh_sah_cost", renderer.bvhStats().sahCost},
                        {"camera", cameraJson(view.camera)},
                        {"output", toFolder ? outPath.string() : outputs.front()}};
    if (foveated) {
        // The last frame's, as gpu_ms is; a trace or live gaze moves it from frame to frame.
        const std::size_t sampled = pointSet->pointsSampled(view.gaze);
        rays = static_cast<uint64_t>(sampled) * o.raysPerPoint;
        j["points_sampled"] = sampled;
        j["points_total"] = pointSet->pointSet().points().size();
        j["rays_per_point"] = o.raysPerPoint;
        j["interp"] = o.interp;
        j["k"] = interp.method == passes::Interpolation::Shepard ||
                         interp.method == passes::Interpolation::Rbf
                     ? o.k
                     : 1u;
        if (interp.method == passes::Interpolation::Rbf) {
            j["kernel"] = o.kernel;
            j["rbf_c"] = o.rbfShape;
        }
        j["scale"] = o.scale;
        j["profile"] = o.profile;
        j["taa"] = o.taa;
        j["gaze"] = {view.gaze.x, view.gaze.y};
        if (trace || tracker) {
            j["gaze_per_frame"] = gazes;
        }
        if (tracker) {
            j["gaze_source"] = o.gazeSource;
            j["tracker_frames"] = tracker->frames();
            j["saccades"] = tracker->saccades();
        }
        if (!o.view.empty()) {
            j["view"] = o.view;
        }
        j["point_set_ms"] = pointSet->pointSetMs();
        j["neighbour_index_ms"] = pointSet->neighbourIndexMs();
        j["neighbour_index_mb"] = pointSet->neighbourIndexMb();
        if (interp.method == passes::Interpolation::Shepard ||
            interp.method == passes::Interpolation::Rbf) {
            j["knn"] = o.knn;
        }
        if (passes::usesPixelTable(interp)) {
            j["knn_table_ms"] = pointSet->knnTablePrepared().ms;
            j["knn_table_mb"] = pointSet->knnTablePrepared().mb;
        }
        if (interp.method == passes::Interpolation::Rbf) {
            // Built once for these settings: per-pixel weights (table) or inverses (lists).
            j["rbf_prepared"] = passes::usesPixelTable(interp) ? "pixel_weights" : "inverses";
            j["rbf_prepared_ms"] = pointSet->rbfPrepared().ms;
            j["rbf_prepared_mb"] = pointSet->rbfPrepared().mb;
        }
    } else if (layered) {
        rays = frame.views.front().rays; // the last frame's: half-rate layers alternate
        j["spp"] = o.spp;
        j["profile"] = o.profile;
        j["gaze"] = {view.gaze.x, view.gaze.y};
        if (trace || tracker) j["gaze_per_frame"] = gazes;
        j["layers"] = layersJson(*layers, view);
    } else {
        j["spp"] = o.spp;
    }
    j["rays"] = rays;
    j["rays_per_second"] = totalMs > 0.0 ? static_cast<double>(rays) / (totalMs * 1e-3) : 0.0;
    written.keep();
    return j;
}

} // namespace gt::app
