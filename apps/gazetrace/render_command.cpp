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
#include "core/progress.hpp"
#include "display/hmd_profile.hpp"
#include "eccentricity_layers.hpp"
#include "eye_source_parsing.hpp"
#include "foveation/gaze_trace.hpp"
#include "foveation/neighbour_index.hpp"
#include "frame_loop.hpp"
#include "full_resolution.hpp"
#include "gaze/gaze_tracker.hpp"
#include "gaze_bounds.hpp"
#include "gaze_mapping.hpp"
#include "gaze_view.hpp"
#include "layers_command.hpp"
#include "method_choice.hpp"
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

// One frame at a time (each is written before the next), on GAZETRACE_DEVICE if set.
render::RendererOptions rendererOptions(const RenderOptions& o) {
    return {.scene = o.scene,
            .validate = o.validate,
            .framesInFlight = 1,
            .deviceOverride = deviceRequest(),
            .sceneLoad = gltfLoadOptions(),
            .animation = o.animation};
}

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
void checkOutput(const std::filesystem::path& outPath, bool toFolder, const std::string& out,
                 uint32_t frames) {
    if (!toFolder && frames > 1) {
        throw ArgumentError("--out: give a folder for --frames > 1");
    }
    std::error_code folderEc;
    if (!toFolder && std::filesystem::is_directory(outPath, folderEc)) {
        throw ArgumentError("--out: " + out + " is a folder; give a file name ending in .png");
    }
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

// One frame every --frame-ms along `spanMs` of a trace or path in `file`, held to the bound
// --frames has: a span of years (times may reach io::limits::kTableTimeMs) overflowed the
// uint32 frame count, and a typo in one time would render for days.
uint32_t framesAlong(double spanMs, const RenderOptions& o, const std::string& file) {
    constexpr double kMaxFrames = 100000.0; // --frames' own range
    const double frames = 1.0 + std::floor(spanMs / o.frameMs);
    if (!(frames <= kMaxFrames)) {
        char text[160];
        std::snprintf(text, sizeof text,
                      ": %.0f ms long, %.4g frames of --frame-ms %g; over 100000 (give --frames)",
                      spanMs, frames, o.frameMs);
        throw ArgumentError(file + text);
    }
    return static_cast<uint32_t>(frames);
}

// --gaze-trace, loaded: pixel traces are checked against the w x h screen they are clamped to;
// without --frames, one frame every --frame-ms from its first sample to its last.
foveation::GazeTrace loadGazeTrace(const RenderOptions& o, uint32_t w, uint32_t h,
                                   uint32_t& frameCount) {
    foveation::GazeTrace trace = foveation::GazeTrace::load(o.gazeTrace);
    if (trace.units() == foveation::GazeUnits::Pixels) {
        warnOffScreen(trace, o.gazeTrace, w, h);
    }
    if (!o.framesGiven) {
        frameCount = framesAlong(trace.endMs() - trace.startMs(), o, o.gazeTrace);
    }
    return trace;
}

// A run's frames on disk: each frame's PNG as soon as it is rendered (--out: one file, or a
// folder of frame_NNNN.png), the first frame's render graph (--graph). Until commit() they are
// staged beside their targets (io::StagedFile, io::StagedFolder): a run that fails or is
// interrupted removes only what it wrote and leaves an earlier run's files as they were.
class FrameFiles {
public:
    FrameFiles(const RenderOptions& o, uint32_t frameCount)
        : mOut(o.out), mToFolder(outIsFolder(mOut)) {
        checkOutput(mOut, mToFolder, o.out, frameCount);
        if (!o.graphDot.empty()) mGraph.emplace(o.graphDot);
        if (mToFolder) {
            mFolder.emplace(mOut);
        } else {
            mFile.emplace(mOut);
        }
    }
    [[nodiscard]] render::FrameOptions options(uint32_t frame) const {
        return {.graphviz = mGraph.has_value() && frame == 0};
    }
    void write(uint32_t frame, const render::FrameResult& result, uint32_t w, uint32_t h,
               const std::vector<uint8_t>& pixels) {
        mFrameMs.push_back(result.wallMs);
        if (options(frame).graphviz) writeText(mGraph->temp().string(), result.dot);
        const std::filesystem::path file = frameFile(mOut, mToFolder, frame);
        image::writePngAtomic(mToFolder ? mFolder->file(file.filename().string()) : mFile->temp(),
                              w, h, pixels);
        mOutputs.push_back(file.string());
    }
    // The median wall time of a frame.
    [[nodiscard]] double medianMs() const {
        std::vector<double> sorted = mFrameMs;
        std::sort(sorted.begin(), sorted.end());
        return sorted[sorted.size() / 2];
    }
    [[nodiscard]] std::string output() const {
        return mToFolder ? mOut.string() : mOutputs.front();
    }
    // The run succeeded: its files replace the earlier run's.
    void commit() {
        if (mGraph) mGraph->commit();
        if (mFolder) mFolder->commit();
        if (mFile) mFile->commit();
    }

private:
    std::filesystem::path mOut;
    bool mToFolder;
    std::optional<io::StagedFile> mGraph;
    std::optional<io::StagedFolder> mFolder;
    std::optional<io::StagedFile> mFile;
    std::vector<double> mFrameMs;
    std::vector<std::string> mOutputs;
};

void checkHmdOptions(const RenderOptions& o, const display::HmdProfile& profile) {
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
}

// The HMD path's method, shared by both eyes, and the post settings of its views.
render::FoveationMethod& hmdMethod(const RenderOptions& o, const display::HmdProfile& profile,
                                   MethodChoice& methods, render::PostSettings& post) {
    post.taa = o.method == "foveated" && o.taa && o.view.empty();
    post.denoise = parseDenoise(o.integrator);
    if (o.method == "layers") {
        // Each eye's layers from its own frustum: the HMD image fills the eye's field of view.
        return methods.layers(renderLayerSettings(o, std::nullopt));
    }
    if (o.method != "foveated")
        return methods.reference({o.spp, o.seed, parseIntegrator(o.integrator)});
    foveation::PointSetParams params;
    params.display = profile.pointSetProfile;
    params.scale = o.scale;
    if (o.k == 0 || o.k > foveation::NeighbourIndex::kMaxNeighbours) {
        throw ArgumentError("--k must be 1..20");
    }
    render::PointSetMethod& pointSet = methods.pointSet(params);
    passes::InterpolateSettings interp = interpolationOf(o.interp, o.k, o.view);
    interp.kernel = parseKernel(o.kernel);
    interp.rbfShape = static_cast<float>(o.rbfShape);
    interp.knn = parseKnnIndex(o.knn);
    pointSet.settings = {o.raysPerPoint, interp, o.displaySpace && o.distortion, o.lod};
    pointSet.settings.integrator = parseIntegrator(o.integrator);
    pointSet.settings.foveaRaysPerPoint = o.integrator.foveaRays;
    if ((parseReconstruction(o.reconstruction) == render::Reconstruction::Thesis)) {
        render::useThesisReconstruction(pointSet.settings, post.taaSettings);
    }
    return pointSet;
}

// Both eyes' gaze at time `tMs` along the trace (none: the fixed --gaze pixel of the left eye).
render::StereoGaze hmdGaze(const std::optional<foveation::GazeTrace>& trace, double tMs,
                           const render::StereoRig& rig, glm::vec2 gazePx, double vergenceM) {
    render::StereoGaze gaze;
    const double t = trace ? trace->startMs() + tMs : 0.0;
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
        const display::HmdProfile& p = rig.profile();
        if (trace) gazePx = clampToImage(trace->at(t), p.eyeWidth, p.eyeHeight);
        gaze.direction = rig.directionOfLeftPixel(gazePx);
    }
    if (vergenceM > 0.0) gaze.vergenceM = static_cast<float>(vergenceM);
    return gaze;
}

nlohmann::json hmdSummary(const RenderOptions& o, const display::HmdProfile& profile,
                          render::Renderer& renderer, const render::FrameResult& frame,
                          std::span<const render::View> views, const FrameFiles& files,
                          uint32_t frameCount, const scene::Camera& head) {
    vk::Context& ctx = renderer.context();
    const nlohmann::json gpu = checkedPassTimes(ctx, frame.timings);
    const rg::FrameTimings timings = frame.timings.value_or(rg::FrameTimings{});
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
    if (o.method == "layers") {
        for (std::size_t e = 0; e < 2; ++e)
            eyes[e]["layers"] =
                layersJson(*static_cast<render::EccentricityLayers*>(views[e].method), views[e]);
    }
    const uint32_t w = profile.eyeWidth, h = profile.eyeHeight;
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
            {"total_ms", files.medianMs()},
            {"camera", cameraJson(head)},
            {"output", files.output()}};
}

// `render --hmd NAME`: both eyes of the profile in one render graph (scopes left., right.), each
// with its off-axis frustum, its own gaze and its lens, composed into the side-by-side frame an
// extended-mode HMD shows. --gaze and --gaze-trace are pixels of the left eye's image.
nlohmann::json runRenderHmd(const RenderOptions& o) {
    const display::HmdProfile profile = hmdProfile(o.hmd);
    checkHmdOptions(o, profile);
    const uint32_t w = profile.eyeWidth, h = profile.eyeHeight;
    const glm::vec2 gazePx = parseGaze(o.gaze, w, h);
    std::optional<foveation::GazeTrace> trace;
    uint32_t frameCount = o.frames;
    if (!o.gazeTrace.empty()) {
        if (!o.gaze.empty()) throw ArgumentError("--gaze and --gaze-trace exclude each other");
        if (!(o.frameMs > 0.0)) throw ArgumentError("--frame-ms must be positive");
        trace = loadGazeTrace(o, w, h, frameCount);
    }
    FrameFiles files(o, frameCount);
    const std::optional<CameraArg> cameraArg = parseCamera(o.camera);
    render::Renderer renderer(rendererOptions(o));
    scene::Camera head = renderer.scene().camera;
    if (cameraArg) head = cameraArg->camera(head.yfov);
    MethodChoice methods(renderer, o.cacheDir);
    render::PostSettings post;
    render::FoveationMethod& method = hmdMethod(o, profile, methods, post);
    auto* const reference = dynamic_cast<render::FullResolution*>(&method);
    const render::StereoRig rig(profile, o.distortion);
    render::CompositeReadbackTarget composite(renderer.context(), 2 * w, h);
    composite.place("left", {{0, 0}, {w, h}});
    composite.place("right", {{static_cast<int32_t>(w), 0}, {w, h}});
    render::FrameResult last;
    std::vector<render::View> lastViews;
    progress::Step frameProgress("render: frames", frameCount);
    FrameStages<render::StereoGaze> stages;
    stages.gaze = [&](const FrameTick& t) {
        return hmdGaze(trace, t.timeMs, rig, gazePx, o.vergenceM);
    };
    stages.views = [&](const FrameTick& t, const render::StereoGaze& gaze) {
        if (reference) reference->settings.frameSeed = o.seed + t.index;
        if (!cameraArg && renderer.animated()) head = renderer.sceneCamera();
        const auto eyes = rig.views(head, gaze, method, post, renderer.scene().exposure);
        return std::vector<render::View>(eyes.begin(), eyes.end());
    };
    stages.targets = [&](const FrameTick&, std::span<const render::View>) {
        return std::vector<render::OutputTarget*>{&composite, &composite};
    };
    stages.options = [&](const FrameTick& t) { return files.options(t.index); };
    stages.done = [&](const FrameTick& t, const render::StereoGaze&,
                      std::span<const render::View> views, const render::FrameResult& result) {
        files.write(t.index, result, 2 * w, h, composite.pixels());
        (void)frameProgress.advance();
        last = result;
        lastViews.assign(views.begin(), views.end());
        return true;
    };
    stages.sceneStartSeconds = o.time;
    (void)runFrameLoop(renderer, FrameClock(o.frameMs), frameCount, stages);
    nlohmann::json j = hmdSummary(o, profile, renderer, last, lastViews, files, frameCount, head);
    files.commit();
    return j;
}

// The flat path's image and method settings, from the profile and the command line.
struct FlatSetup {
    uint32_t width = 0, height = 0;
    foveation::PointSetParams pointSet;
    passes::InterpolateSettings interp;
    glm::vec2 gaze{};
};

FlatSetup flatSetup(const RenderOptions& o) {
    FlatSetup s{o.width, o.height, {}, {}, {}};
    if (o.method == "foveated") {
        s.pointSet.display = displayProfile(o.profile);
        s.pointSet.scale = o.scale;
        if (o.sizeGiven && o.profile == "desktop") {
            // A window on the desktop screen: its own point set at the screen's pixels per degree.
            s.pointSet.display = foveation::windowProfile(s.pointSet.display, o.width, o.height);
        } else if (o.sizeGiven &&
                   (o.width != s.pointSet.display.width || o.height != s.pointSet.display.height)) {
            throw ArgumentError("--width/--height: the " + o.profile + " profile renders " +
                                std::to_string(s.pointSet.display.width) + "x" +
                                std::to_string(s.pointSet.display.height));
        }
        s.width = s.pointSet.display.width;
        s.height = s.pointSet.display.height;
        s.interp = interpolationOf(o.interp, o.k, "");
        s.interp.kernel = parseKernel(o.kernel);
        s.interp.rbfShape = static_cast<float>(o.rbfShape);
        s.interp.knn = parseKnnIndex(o.knn);
        if (o.k == 0 || o.k > foveation::NeighbourIndex::kMaxNeighbours) {
            throw ArgumentError("--k must be 1..20");
        }
        s.gaze = parseGaze(o.gaze, s.width, s.height);
        if (!o.view.empty()) {
            s.interp.method = parseView(o.view);
        }
    } else if (o.method == "layers") {
        // The profile's screen (or a window on it, with --width/--height): layer sizes follow
        // its viewing geometry, as the point set's do.
        const foveation::DisplayProfile screen = displayProfile(o.profile);
        if (!o.sizeGiven) {
            s.width = screen.width;
            s.height = screen.height;
        }
        s.gaze = parseGaze(o.gaze, s.width, s.height);
    } else {
        s.gaze = parseGaze(o.gaze, s.width, s.height); // the denoiser's (--denoise on)
    }
    return s;
}

// What moves the flat path's frames: a gaze trace or the live eye tracker (opened now, so a bad
// one fails before any work; the tracker thread starts with the first frame), a camera path,
// and the frame count they imply.
struct FlatInputs {
    std::optional<foveation::GazeTrace> trace;
    std::unique_ptr<eyetrack::FrameSource> gazeSource;
    std::optional<eyetrack::Calibration> calibration;
    std::optional<scene::CameraPath> path;
    uint32_t frameCount = 1;
};

FlatInputs flatInputs(const RenderOptions& o, const FlatSetup& s) {
    const bool foveated = o.method == "foveated";
    // The denoiser's strength follows the gaze, so the reference takes one with it.
    const bool gazeDriven =
        foveated || o.method == "layers" || parseDenoise(o.integrator).has_value();
    FlatInputs in;
    in.frameCount = o.frames;
    if (!o.gazeTrace.empty()) {
        if (!gazeDriven)
            throw ArgumentError("--gaze-trace needs --method foveated or layers (or --denoise on)");
        if (!(o.frameMs > 0.0)) throw ArgumentError("--frame-ms must be positive");
        if (!o.gaze.empty()) throw ArgumentError("--gaze and --gaze-trace exclude each other");
        in.trace = loadGazeTrace(o, s.width, s.height, in.frameCount);
    }
    if (!o.gazeSource.empty()) {
        if (!gazeDriven)
            throw ArgumentError(
                "--gaze-source needs --method foveated or layers (or --denoise on)");
        if (in.trace) throw ArgumentError("--gaze-source and --gaze-trace exclude each other");
        if (!o.gaze.empty()) throw ArgumentError("--gaze and --gaze-source exclude each other");
        if (o.calibration.empty()) {
            throw ArgumentError("--gaze-source needs --calibration (see gazetrace calibrate)");
        }
        in.calibration = eyetrack::Calibration::load(o.calibration);
        in.gazeSource = openFrameSource(o.gazeSource);
    } else if (!o.calibration.empty()) {
        throw ArgumentError("--calibration is for --gaze-source");
    }
    if (!foveated && !o.view.empty()) throw ArgumentError("--view needs --method foveated");
    if (!gazeDriven && !o.gaze.empty()) {
        throw ArgumentError("--gaze needs --method foveated or layers (or --denoise on)");
    }
    // --camera-path: the camera follows a recorded path, one frame every --frame-ms.
    if (!o.cameraPath.empty()) {
        if (!(o.frameMs > 0.0)) throw ArgumentError("--frame-ms must be positive");
        in.path = scene::CameraPath::load(o.cameraPath);
        if (!o.framesGiven) {
            in.frameCount =
                std::max(in.trace ? in.frameCount : 1u,
                         framesAlong(in.path->endMs() - in.path->startMs(), o, o.cameraPath));
        }
    }
    return in;
}

// The flat path's gaze source: the fixed --gaze, the trace at each frame's time, or the eye
// tracker's newest sample (the last one while none is new), with the saccades it saw.
class FlatGazeSource {
public:
    FlatGazeSource(const RenderOptions& o, FlatInputs& in, glm::vec2 fixed)
        : mOptions(o), mTrace(in.trace), mPixel(fixed) {
        if (in.gazeSource) {
            mTracker.emplace(std::move(in.gazeSource), *in.calibration);
            (void)mTracker->waitForFirstSample(2000.0); // a camera may take a moment to stream
        }
    }
    struct Gaze {
        glm::vec2 pixel{};
        bool saccade = false;
    };
    Gaze at(const FrameTick& t, const render::View& view) {
        const bool desktop = mOptions.profile == "desktop";
        if (mTrace) {
            glm::vec2 px = mTrace->at(mTrace->startMs() + t.timeMs);
            if (mTrace->units() == foveation::GazeUnits::AnglesDeg) {
                px = renderPixelOfAngles(px, desktop, view);
            }
            mPixel = clampToImage(px, view.width, view.height);
        }
        if (!mTracker) return {mPixel, false};
        if (const auto e = mTracker->error()) {
            throw Error("--gaze-source " + mOptions.gazeSource + ": " + *e);
        }
        if (const auto g = mTracker->mailbox().latest()) {
            // The calibration fits gaze angles: back from its screen's pixels to angles, then
            // onto this render as an angle trace lands.
            const cv::Point2d a = mTracker->display().anglesDeg({g->x, g->y});
            mPixel = clampToImage(
                renderPixelOfAngles(glm::vec2(static_cast<float>(a.x), static_cast<float>(a.y)),
                                    desktop, view),
                view.width, view.height);
        }
        // A saccade since the last frame: the TAA history is dropped (thesis, 3.1).
        const std::uint64_t saccades = mTracker->saccades();
        const bool saccade = saccades != mSaccadesSeen;
        mSaccadesSeen = saccades;
        return {mPixel, saccade};
    }
    [[nodiscard]] const std::optional<eyetrack::GazeTracker>& tracker() const { return mTracker; }

private:
    const RenderOptions& mOptions;
    const std::optional<foveation::GazeTrace>& mTrace;
    std::optional<eyetrack::GazeTracker> mTracker;
    glm::vec2 mPixel;
    std::uint64_t mSaccadesSeen = 0;
};

// The flat path's view and its method.
render::View flatView(const RenderOptions& o, const FlatSetup& s, render::Renderer& renderer,
                      MethodChoice& methods) {
    render::View view;
    view.width = s.width;
    view.height = s.height;
    view.exposure = renderer.scene().exposure;
    view.post.taa = false;
    view.post.denoise = parseDenoise(o.integrator);
    view.gaze = s.gaze;
    if (o.method == "layers") {
        view.method = &methods.layers(renderLayerSettings(o, displayProfile(o.profile)));
    } else if (o.method == "foveated") {
        render::PointSetMethod& pointSet = methods.pointSet(s.pointSet);
        pointSet.settings = {o.raysPerPoint, s.interp, false, o.lod};
        pointSet.settings.integrator = parseIntegrator(o.integrator);
        pointSet.settings.foveaRaysPerPoint = o.integrator.foveaRays;
        view.method = &pointSet;
        view.post.taa = o.taa && o.view.empty(); // debug views show one frame's data as is
        if ((parseReconstruction(o.reconstruction) == render::Reconstruction::Thesis)) {
            render::useThesisReconstruction(pointSet.settings, view.post.taaSettings);
        }
    } else {
        view.method = &methods.reference({o.spp, o.seed, parseIntegrator(o.integrator)});
        if (!view.post.denoise) view.gaze = {}; // the denoiser's strength follows the gaze
    }
    return view;
}

// The foveated part of the summary: the last frame's points, the interpolation, the tables.
void addPointSetJson(nlohmann::json& j, const RenderOptions& o, const FlatSetup& s,
                     const render::PointSetMethod& pointSet, const render::View& view,
                     uint64_t& rays) {
    const passes::InterpolateSettings& interp = s.interp;
    const bool neighbours = interp.method == passes::Interpolation::Shepard ||
                            interp.method == passes::Interpolation::Rbf;
    // The last frame's, as gpu_ms is; a trace or live gaze moves it from frame to frame.
    const std::size_t sampled = pointSet.pointsSampled(view.gaze);
    rays = pointSet.rays(view); // with --fovea-rays, the fovea's points' own count
    j["points_sampled"] = sampled;
    j["points_total"] = pointSet.pointSet().points().size();
    j["rays_per_point"] = o.raysPerPoint;
    if (o.integrator.foveaRays > 0) {
        j["fovea_rays_per_point"] = o.integrator.foveaRays;
        j["fovea_radius_px"] = pointSet.foveaRadiusPx();
    }
    j["interp"] = o.interp;
    j["k"] = neighbours ? o.k : 1u;
    if (interp.method == passes::Interpolation::Rbf) {
        j["kernel"] = o.kernel;
        j["rbf_c"] = o.rbfShape;
    }
    j["scale"] = o.scale;
    j["profile"] = o.profile;
    j["taa"] = o.taa;
    j["gaze"] = {view.gaze.x, view.gaze.y};
}

void addPointSetTablesJson(nlohmann::json& j, const RenderOptions& o,
                           const passes::InterpolateSettings& interp,
                           const render::PointSetMethod& pointSet) {
    if (!o.view.empty()) {
        j["view"] = o.view;
    }
    j["point_set_ms"] = pointSet.pointSetMs();
    j["neighbour_index_ms"] = pointSet.neighbourIndexMs();
    j["neighbour_index_mb"] = pointSet.neighbourIndexMb();
    if (interp.method == passes::Interpolation::Shepard ||
        interp.method == passes::Interpolation::Rbf) {
        j["knn"] = o.knn;
    }
    if (passes::usesPixelTable(interp)) {
        j["knn_table_ms"] = pointSet.knnTablePrepared().ms;
        j["knn_table_mb"] = pointSet.knnTablePrepared().mb;
    }
    if (interp.method == passes::Interpolation::Rbf) {
        // Built once for these settings: per-pixel weights (table) or inverses (lists).
        j["rbf_prepared"] = passes::usesPixelTable(interp) ? "pixel_weights" : "inverses";
        j["rbf_prepared_ms"] = pointSet.rbfPrepared().ms;
        j["rbf_prepared_mb"] = pointSet.rbfPrepared().mb;
    }
}

// What a flat run did, for --json.
struct FlatRun {
    const render::FrameResult& frame;
    const render::View& view;
    const FrameFiles& files;
    const FlatGazeSource& gaze;
    const nlohmann::json& gazes; // per frame, when a trace or the tracker moved it
    uint32_t frameCount = 0;
    bool traced = false;
};

nlohmann::json flatSummary(const RenderOptions& o, const FlatSetup& s, render::Renderer& renderer,
                           const FlatRun& run) {
    vk::Context& ctx = renderer.context();
    const nlohmann::json gpu = checkedPassTimes(ctx, run.frame.timings);
    const rg::FrameTimings timings = run.frame.timings.value_or(rg::FrameTimings{});
    const double totalMs = run.files.medianMs();
    uint64_t rays = static_cast<uint64_t>(s.width) * s.height * o.spp;
    nlohmann::json j = {{"device", ctx.deviceName()},
                        {"device_type", ctx.deviceDescription()},
                        {"scene", o.scene},
                        {"triangles", renderer.scene().triangleCount()},
                        {"lod_triangles", renderer.lodTriangles()},
                        {"lod", o.lod},
                        {"width", s.width},
                        {"height", s.height},
                        {"method", o.method},
                        {"gpu_ms", gpu},
                        {"gpu_total_ms", timings.gpuMs},
                        {"total_ms", totalMs},
                        {"frames", run.frameCount},
                        {"load_ms", renderer.loadMs()},
                        {"bvh_ms", renderer.bvhMs()},
                        {"bvh_nodes", renderer.bvhStats().nodes},
                        {"bvh_sah_cost", renderer.bvhStats().sahCost},
                        {"camera", cameraJson(run.view.camera)},
                        {"output", run.files.output()}};
    const auto& tracker = run.gaze.tracker();
    if (o.method == "foveated") {
        const auto& pointSet = *static_cast<const render::PointSetMethod*>(run.view.method);
        addPointSetJson(j, o, s, pointSet, run.view, rays);
        if (run.traced || tracker) {
            j["gaze_per_frame"] = run.gazes;
        }
        if (tracker) {
            j["gaze_source"] = o.gazeSource;
            j["tracker_frames"] = tracker->frames();
            j["saccades"] = tracker->saccades();
        }
        addPointSetTablesJson(j, o, s.interp, pointSet);
    } else if (o.method == "layers") {
        rays = run.frame.views.front().rays; // the last frame's: half-rate layers alternate
        j["spp"] = o.spp;
        j["profile"] = o.profile;
        j["gaze"] = {run.view.gaze.x, run.view.gaze.y};
        if (run.traced || tracker) j["gaze_per_frame"] = run.gazes;
        j["layers"] =
            layersJson(*static_cast<render::EccentricityLayers*>(run.view.method), run.view);
    } else {
        j["spp"] = o.spp;
    }
    if (o.integrator.integrator != "direct") {
        j["integrator"] = o.integrator.integrator;
        j["bounces"] = o.integrator.bounces;
        j["sequence"] = o.integrator.sequence;
        j["denoise"] = o.integrator.denoise;
    }
    j["rays"] = rays;
    j["rays_per_second"] = totalMs > 0.0 ? static_cast<double>(rays) / (totalMs * 1e-3) : 0.0;
    return j;
}

} // namespace

nlohmann::json runRender(const RenderOptions& o) {
    if (o.method == "layers") (void)parseSlope(o.slope); // before any work
    if (parseIntegrator(o.integrator).integrator != render::Integrator::Direct &&
        o.method == "layers") {
        throw ArgumentError("--integrator " + o.integrator.integrator +
                            ": reference and foveated only (layers trace the direct integrator)");
    }
    if (parseDenoise(o.integrator) && o.method == "layers") {
        throw ArgumentError("--denoise on: reference and foveated only");
    }
    if (!o.hmd.empty()) {
        return runRenderHmd(o);
    }
    if (!methodKindOf(o.method)) {
        throw ArgumentError("--method: '" + o.method +
                            "' is not available (known: reference, foveated, layers)");
    }
    if (o.out.empty()) {
        throw ArgumentError("--out: empty path");
    }
    const bool gazeDriven = o.method == "foveated" || o.method == "layers";
    const FlatSetup s = flatSetup(o);
    FlatInputs in = flatInputs(o, s);
    FrameFiles files(o, in.frameCount);
    const std::optional<CameraArg> cameraArg = parseCamera(o.camera);
    render::Renderer renderer(rendererOptions(o));
    MethodChoice methods(renderer, o.cacheDir);
    render::View view = flatView(o, s, renderer, methods);
    view.camera = renderer.scene().camera;
    if (cameraArg) view.camera = cameraArg->camera(renderer.scene().camera.yfov);
    auto* const reference = dynamic_cast<render::FullResolution*>(view.method);
    FlatGazeSource gazeSource(o, in, view.gaze);
    render::ReadbackTarget readback(renderer.context());
    render::FrameResult last;
    nlohmann::json gazes = nlohmann::json::array();
    progress::Step frameProgress("render: frames", in.frameCount);
    FrameStages<FlatGazeSource::Gaze> stages;
    stages.gaze = [&](const FrameTick& t) { return gazeSource.at(t, view); };
    stages.views = [&](const FrameTick& t, const FlatGazeSource::Gaze& g) {
        if (in.path) {
            view.camera = in.path->at(in.path->startMs() + t.timeMs, view.camera.yfov);
        } else if (!cameraArg && renderer.animated()) {
            view.camera = renderer.sceneCamera(); // the file's camera, moved by its animation
        }
        view.gaze = g.pixel;
        view.saccade = g.saccade;
        if (gazeDriven) gazes.push_back({view.gaze.x, view.gaze.y});
        if (reference) reference->settings.frameSeed = o.seed + t.index;
        return std::vector<render::View>{view};
    };
    stages.targets = [&](const FrameTick&, std::span<const render::View>) {
        return std::vector<render::OutputTarget*>{&readback};
    };
    stages.options = [&](const FrameTick& t) { return files.options(t.index); };
    stages.done = [&](const FrameTick& t, const FlatGazeSource::Gaze&,
                      std::span<const render::View>, const render::FrameResult& result) {
        files.write(t.index, result, s.width, s.height, readback.pixels());
        (void)frameProgress.advance();
        last = result;
        return true;
    };
    stages.sceneStartSeconds = o.time;
    (void)runFrameLoop(renderer, FrameClock(o.frameMs), in.frameCount, stages);
    const FlatRun run{last, view, files, gazeSource, gazes, in.frameCount, in.trace.has_value()};
    nlohmann::json j = flatSummary(o, s, renderer, run);
    files.commit();
    return j;
}

} // namespace gt::app
