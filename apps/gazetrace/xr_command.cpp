#include "xr_command.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <thread>
#include <tuple>

#include "action_sets.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "eccentricity_layers.hpp"
#include "external_image_target.hpp"
#include "eye_gaze.hpp"
#include "foveation/neighbour_index.hpp"
#include "frame_loop.hpp"
#include "full_resolution.hpp"
#include "gaze_input.hpp"
#include "layers_command.hpp"
#include "method_choice.hpp"
#include "option_parsing.hpp"
#include "point_set_method.hpp"
#include "renderer.hpp"
#include "scene/image_io.hpp"
#include "scene/start_view.hpp"
#include "stereo_rig.hpp"
#include "stop_request.hpp"
#include "view_args.hpp"
#include "xr_error.hpp"
#include "xr_gaze.hpp"
#include "xr_run_stats.hpp"
#include "xr_runtime.hpp"
#include "xr_session.hpp"
#include "xr_views.hpp"

namespace gt::app {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

glm::vec3 parseVec3(const std::string& text, const char* flag) {
    glm::vec3 v(0.0f);
    char extra = 0;
    if (std::sscanf(text.c_str(), "%f,%f,%f%c", &v.x, &v.y, &v.z, &extra) != 3 ||
        !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) ||
        glm::any(glm::greaterThan(glm::abs(v), glm::vec3(1e12f)))) {
        throw ArgumentError(std::string(flag) + ": expected X,Y,Z (finite, within 1e12), got '" +
                            text + "'");
    }
    return v;
}

void checkOptions(const XrOptions& o) {
    if (o.method != "foveated" && o.method != "reference" && o.method != "layers") {
        throw ArgumentError("--method: '" + o.method + "' (known: foveated, layers, reference)");
    }
    (void)parseSlope(o.slope);
    (void)parseInterpolation(o.interp);
    if (o.k == 0 || o.k > foveation::NeighbourIndex::kMaxNeighbours) {
        throw ArgumentError("--k must be 1..20");
    }
    if (parseIntegrator(o.integrator).integrator != render::Integrator::Direct &&
        o.method == "layers") {
        throw ArgumentError("--integrator " + o.integrator.integrator +
                            ": foveated and reference only (layers trace the direct integrator)");
    }
    if (o.space != "local" && o.space != "stage") {
        throw ArgumentError("--xr-space: '" + o.space + "' (known: local, stage)");
    }
    if (!(o.worldScale > 0.0) || o.worldScale > 1e6) {
        throw ArgumentError("--xr-scale must be above 0 and at most 1e6");
    }
    if (!(o.resolutionScale >= 0.05 && o.resolutionScale <= 4.0)) {
        throw ArgumentError("--resolution-scale must be 0.05..4");
    }
    if (o.screenshotEye.empty() != o.screenshot.empty()) {
        throw ArgumentError("--screenshot-eye: give an eye and a file, e.g. left eye.png");
    }
    if (!o.screenshotEye.empty()) {
        if (o.screenshotEye != "left" && o.screenshotEye != "right") {
            throw ArgumentError("--screenshot-eye: '" + o.screenshotEye + "' (known: left, right)");
        }
        if (std::filesystem::path(o.screenshot).extension() != ".png") {
            throw ArgumentError("--screenshot-eye: give a .png file, got '" + o.screenshot + "'");
        }
        if (o.frames == 0) {
            throw ArgumentError("--screenshot-eye needs --frames N");
        }
    }
    if (!(o.vergenceM >= 0.0) || o.vergenceM > 1e6) {
        throw ArgumentError("--vergence-m must be 0 (infinity) to 1e6");
    }
    if (!(o.startTimeoutS > 0.0)) {
        throw ArgumentError("--start-timeout must be above 0");
    }
}

// The foveation method of an eye image (its size and field of view as the runtime reports them),
// built on first use and shared by every eye with the same display; the reference method for
// --method reference. An open-ended session generates the point set off the frame thread and
// shows the full-resolution reference until it is ready, so the first frames reach the headset
// at once; a run of --frames N waits for it. The layers follow each view's frustum (XrFovf) and
// size.
class EyeMethods {
public:
    EyeMethods(render::Renderer& r, const XrOptions& o)
        : mChoice(r, o.cacheDir), mOptions(o),
          mKind(methodKindOf(o.method).value_or(MethodKind::Foveated)),
          mLayerSettings(layerSettings(o.slope, o.layers, o.spp)),
          mInterp(interpolationOf(o.interp, o.k, "")),
          mThesis((parseReconstruction(o.reconstruction) == render::Reconstruction::Thesis)),
          mIntegrator(parseIntegrator(o.integrator)) {}
    render::FoveationMethod& forEye(const XrFovf& fov, VkExtent2D size) {
        if (mKind == MethodKind::Reference)
            return mChoice.reference({mOptions.spp, 0, mIntegrator});
        // One method for both eyes: each eye's layers follow its own frustum (XrFovf).
        if (mKind == MethodKind::Layers) return mChoice.layers(mLayerSettings);
        foveation::PointSetParams params;
        params.display = xr::eyeDisplay(fov, size.width, size.height);
        params.scale = mOptions.pointScale;
        const auto built = [&](render::PointSetMethod& m, double ms) {
            m.settings = {mOptions.raysPerPoint, mInterp, false};
            m.settings.integrator = mIntegrator;
            m.settings.foveaRaysPerPoint = mOptions.integrator.foveaRays;
            if (mThesis) {
                passes::TaaSettings unused; // the views' TAA follows in eyeViews
                render::useThesisReconstruction(m.settings, unused);
            }
            log::info("xr: point set for " + std::to_string(size.width) + "x" +
                      std::to_string(size.height) +
                      " eyes (v = " + std::to_string(params.display.viewingDistance) +
                      " widths) ready in " + std::to_string(static_cast<int>(ms)) + " ms");
        };
        if (mOptions.frames != 0) return mChoice.pointSet(params, built);
        render::PointSetMethod* const ready = mChoice.pointSetIfReady(params, built);
        return ready ? static_cast<render::FoveationMethod&>(*ready)
                     : mChoice.reference({mOptions.spp, 0, mIntegrator});
    }
    // --denoise: the views' denoiser (none for layers).
    [[nodiscard]] std::optional<passes::DenoiseSettings> denoise() const {
        return mKind == MethodKind::Layers ? std::nullopt : parseDenoise(mOptions.integrator);
    }
    // --reconstruction thesis: the thesis's TAA in the views too.
    [[nodiscard]] bool thesis() const noexcept { return mThesis; }

private:
    MethodChoice mChoice;
    const XrOptions& mOptions;
    MethodKind mKind;
    render::EccentricityLayerSettings mLayerSettings;
    passes::InterpolateSettings mInterp;
    bool mThesis;
    render::IntegratorSettings mIntegrator; // foveated and reference
};

// Both eyes' views of a frame: each eye's reported pose through the scene placement, its own
// field of view, and the gaze seen through that eye.
std::array<render::View, 2> eyeViews(const xr::FrameInfo& frame, const HeadGaze& gaze,
                                     const xr::ScenePlacement& placement,
                                     const xr::Session& session, EyeMethods& methods, bool taa,
                                     float exposure, bool thesis) {
    std::array<render::View, 2> views;
    for (uint32_t e = 0; e < 2; ++e) {
        render::View& v = views[e];
        const XrView& eye = frame.views[e];
        const VkExtent2D size = session.eyeExtent(e);
        v = eyeView(frame, e, gaze, placement, size);
        v.method = &methods.forEye(eye.fov, size);
        v.post.taa = taa;
        v.post.denoise = methods.denoise();
        if (thesis) {
            render::PointSetSettings unused; // the method's part is set where it is built
            render::useThesisReconstruction(unused, v.post.taaSettings);
        }
        v.exposure = exposure;
    }
    return views;
}

// What --screenshot-eye wrote, with everything a test needs to render the same view headless:
// the camera gazetrace used and the pose and field of view the runtime reported.
nlohmann::json screenshotJson(const XrOptions& o, uint32_t frameNumber, const render::View& v,
                              const XrView& reported) {
    const XrPosef& p = reported.pose;
    const XrFovf& f = reported.fov;
    return {{"eye", o.screenshotEye},
            {"file", o.screenshot},
            {"frame", frameNumber},
            {"width", v.width},
            {"height", v.height},
            {"camera",
             {{"position", {v.camera.position.x, v.camera.position.y, v.camera.position.z}},
              {"forward", {v.camera.forward.x, v.camera.forward.y, v.camera.forward.z}},
              {"up", {v.camera.up.x, v.camera.up.y, v.camera.up.z}}}},
            {"tangents", {v.frustum->left, v.frustum->right, v.frustum->up, v.frustum->down}},
            {"gaze", {v.gaze.x, v.gaze.y}},
            {"xr_pose",
             {{"position", {p.position.x, p.position.y, p.position.z}},
              {"orientation_xyzw",
               {p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w}}}},
            {"xr_fov_rad", {f.angleLeft, f.angleRight, f.angleUp, f.angleDown}}};
}

void checkOwnValidation(const vk::Context& ctx) {
    if (ctx.validationErrors() > 0) {
        throw Error(std::to_string(ctx.validationErrors()) +
                    " Vulkan validation error(s) in gazetrace's own calls");
    }
}

// Where the viewer starts: --camera, --xr-origin and --xr-yaw, parsed and checked (with the
// --screenshot-eye folder) before the runtime is touched.
struct StartArgs {
    std::optional<CameraArg> camera;
    std::optional<glm::vec3> origin;
    std::optional<float> yaw;
};

StartArgs parseStartArgs(const XrOptions& o) {
    StartArgs a;
    a.camera = parseCamera(o.camera);
    if (!o.origin.empty()) {
        a.origin = parseVec3(o.origin, "--xr-origin");
    }
    if (!o.yawDeg.empty()) {
        char* end = nullptr;
        const double d = std::strtod(o.yawDeg.c_str(), &end);
        if (end == o.yawDeg.c_str() || *end != '\0' || !std::isfinite(d) || std::abs(d) > 360.0) {
            throw ArgumentError("--xr-yaw: expected degrees within +-360, got '" + o.yawDeg + "'");
        }
        a.yaw = static_cast<float>(glm::radians(d));
    }
    if (!o.screenshot.empty()) {
        const auto dir = std::filesystem::path(o.screenshot).parent_path();
        std::error_code ec;
        if (!dir.empty() && !std::filesystem::is_directory(dir, ec)) {
            throw ArgumentError("--screenshot-eye: folder " + dir.string() + " does not exist");
        }
    }
    return a;
}

// One OpenXR session of `gazetrace xr`: the runtime, the renderer on its Vulkan device, the
// session and where the scene stands in it, and the frame loop's stages over them: begin (the
// runtime's events and frame), gaze (the runtime's or gazetrace's own), views (both eyes),
// targets (the swapchain images) and done (release, submit, figures).
class XrRun {
public:
    explicit XrRun(const XrOptions& o);
    nlohmann::json run();

private:
    void openSession(const StartArgs& args);
    FrameStart begin(const FrameTick& t);
    HeadGaze gaze();
    std::vector<render::OutputTarget*> targets(const FrameTick& t);
    bool done(const FrameTick& t, const HeadGaze& gaze, std::span<const render::View> views,
              const render::FrameResult& result);
    // After every frame of the runtime's, shown or not: the frame interval, and the end of the
    // session once --frames were rendered.
    void frameEnded(bool rendered, uint32_t renderedFrames);
    nlohmann::json summary(uint32_t rendered);
    [[nodiscard]] bool lastFrame(const FrameTick& t) const {
        return mOptions.frames != 0 && t.index + 1 == mOptions.frames;
    }

    const XrOptions& mOptions;
    std::unique_ptr<GazeInput> mOwnGaze;
    std::optional<xr::Runtime> mRuntime;
    std::optional<render::Renderer> mRenderer;
    std::optional<xr::Session> mSession;
    xr::ScenePlacement mPlacement;
    // Before the inputs whose actions it holds: they go first.
    std::optional<xr::ActionSets> mActions;
    std::optional<xr::EyeGaze> mEyeGaze;
    std::string mEyeGazeStatus = "not offered by the runtime";
    std::optional<EyeMethods> mMethods;
    std::array<std::optional<render::ExternalImageTarget>, 2> mTargets;
    uint32_t mShotEye = 0;
    RunStats mStats;
    uint32_t mRuntimeGazeFrames = 0, mEmptyFrames = 0;
    nlohmann::json mShotInfo;
    Clock::time_point mT0, mLastFrameEnd, mRenderStart;
    std::optional<Clock::time_point> mExitAsked;
    bool mExited = false;
    xr::FrameInfo mFrame;
    XrTime mFirstDisplayTime = 0; // animation: scene time runs with the predicted display time
};

XrRun::XrRun(const XrOptions& o) : mOptions(o) {
    checkOptions(o);
    const StartArgs args = parseStartArgs(o);
    // Gaze source first: a bad one fails before the runtime is touched.
    if (o.gaze != "ahead") {
        GazeInputContext gc;
        gc.calibration = o.calibration;
        mOwnGaze = openGazeInput(o.gaze, gc);
    }
    xr::RuntimeOptions rto;
    rto.eyeGaze = o.runtimeGaze;
    if (const char* manifest = std::getenv("XR_RUNTIME_JSON")) rto.runtimeManifest = manifest;
    mRuntime.emplace(rto);
    log::info("xr: runtime " + mRuntime->runtimeName() + ", system " + mRuntime->systemName());

    render::RendererOptions ro;
    ro.scene = o.scene;
    ro.validate = o.validate;
    ro.framesInFlight = 1; // each frame's images are released right after its submit
    ro.deviceOverride = deviceRequest();
    ro.sceneLoad = gltfLoadOptions();
    ro.animation = o.animation;
    ro.display = mRuntime->vulkanHooks();
    mRenderer.emplace(ro);
    openSession(args);
    mMethods.emplace(*mRenderer, o);
    for (auto& t : mTargets)
        t.emplace(mRenderer->context());
    mShotEye = o.screenshotEye == "right" ? 1 : 0;
}

void XrRun::openSession(const StartArgs& args) {
    const scene::Scene& sc = mRenderer->scene();
    scene::Camera start = sc.camera;
    if (args.camera) {
        start = args.camera->camera(sc.camera.yfov);
    } else if (sc.cameraFramed) {
        if (const auto inside = scene::insideStartView(sc, mRenderer->bvh())) {
            start = *inside;
        }
    }
    mSession.emplace(*mRuntime, mRenderer->context(),
                     xr::SessionOptions{mOptions.space == "stage", mOptions.resolutionScale});
    mPlacement = xr::ScenePlacement::facing(start, static_cast<float>(mOptions.worldScale));
    if (mSession->spaceName() == "STAGE" && !args.origin) {
        // STAGE's origin is on the floor: the start view's eye stands 1.6 m above it.
        mPlacement.origin.y -= 1.6f * mPlacement.scale;
    }
    if (args.origin) {
        mPlacement.origin = *args.origin;
    }
    if (args.yaw) {
        mPlacement.yawRad = *args.yaw;
    }
    if (!mOptions.runtimeGaze) {
        mEyeGazeStatus = "not used (--no-runtime-gaze)";
    } else if (mRuntime->eyeGazeOffered() && !mRuntime->eyeGazeSupported()) {
        mEyeGazeStatus = "offered, but the system reports no eye tracker";
    } else if (mRuntime->eyeGazeSupported()) {
        mActions.emplace(*mSession);
        mEyeGaze.emplace(*mActions);
        mActions->attach();
        mEyeGazeStatus = "offered";
    }
}

FrameStart XrRun::begin(const FrameTick& t) {
    if (!mSession->pollEvents()) {
        mExited = true;
        return FrameStart::Stop;
    }
    const auto now = Clock::now();
    if (stopRequested() && !mExitAsked) {
        // SIGINT or SIGTERM end the session as --frames does: asked to exit, the runtime ends it
        // and the summary is written. A session that never started has nothing to end.
        if (!mSession->running()) return FrameStart::Stop;
        mSession->requestExit();
        mExitAsked = now;
    }
    if (mExitAsked && msSince(*mExitAsked, now) > 5000.0) {
        log::warn("xr: the runtime did not end the session within 5 s of the request");
        return FrameStart::Stop;
    }
    if (!mSession->running()) {
        if (!mExitAsked && t.index == 0 && msSince(mT0, now) > mOptions.startTimeoutS * 1000.0) {
            throw Error("the OpenXR session did not start within " +
                        std::to_string(static_cast<int>(mOptions.startTimeoutS)) +
                        " s (last state " + xr::stateName(mSession->lifecycle().state()) +
                        "): is the headset on and the runtime's compositor running?");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        return FrameStart::Skip;
    }
    mFrame = mSession->beginFrame();
    const bool wanted = !mExitAsked && (mOptions.frames == 0 || t.index < mOptions.frames);
    if (!(wanted && mFrame.shouldRender && mFrame.posesValid)) {
        mSession->endFrame(mFrame, false);
        ++mEmptyFrames;
        frameEnded(false, t.index);
        return FrameStart::Skip;
    }
    mRenderStart = Clock::now();
    return FrameStart::Render;
}

HeadGaze XrRun::gaze() {
    if (mActions) mActions->sync();
    const std::optional<xr::EyeGazeSample> sample =
        mEyeGaze ? mEyeGaze->locate(mFrame.displayTime) : std::nullopt;
    mRuntimeGazeFrames += sample ? 1 : 0;
    if (sample) return runtimeHeadGaze(*sample, mOptions.vergenceM, *mRuntime);
    return ownHeadGaze(mOwnGaze.get(), msSince(mT0, mRenderStart), mFrame, mSession->eyeExtent(0),
                       mOptions.vergenceM)
        .value_or(HeadGaze{});
}

std::vector<render::OutputTarget*> XrRun::targets(const FrameTick& t) {
    if (lastFrame(t) && !mOptions.screenshot.empty()) {
        mTargets[mShotEye]->requestScreenshot();
    }
    for (uint32_t e = 0; e < 2; ++e) {
        const xr::EyeImage img = mSession->acquire(e);
        mTargets[e]->setImage({img.image, img.format, img.extent, 0});
    }
    return {&*mTargets[0], &*mTargets[1]};
}

bool XrRun::done(const FrameTick& t, const HeadGaze& gaze, std::span<const render::View> views,
                 const render::FrameResult& result) {
    mSession->release(0);
    mSession->release(1);
    mSession->endFrame(mFrame, true);
    checkOwnValidation(mRenderer->context());
    mStats.addFrame(result, msSince(mRenderStart, Clock::now()));
    if (gaze.sampled) {
        mStats.addGazeAge(msSince(*gaze.sampled, mRuntime->fromXrTime(mFrame.displayTime)));
    }
    if (lastFrame(t) && !mOptions.screenshot.empty()) {
        const auto& px = mTargets[mShotEye]->screenshot();
        if (!px) {
            throw Error("--screenshot-eye: the eye image was not read back");
        }
        const render::View& v = views[mShotEye];
        image::writePngAtomic(mOptions.screenshot, v.width, v.height, *px);
        mShotInfo = screenshotJson(mOptions, t.index, v, mFrame.views[mShotEye]);
    }
    frameEnded(true, t.index + 1);
    return true;
}

void XrRun::frameEnded(bool rendered, uint32_t renderedFrames) {
    const auto end = Clock::now();
    if (rendered) {
        mStats.addInterval(msSince(mLastFrameEnd, end));
    }
    mLastFrameEnd = end;
    if (mOptions.frames != 0 && renderedFrames >= mOptions.frames && !mExitAsked) {
        mSession->requestExit();
        mExitAsked = Clock::now();
    }
}

nlohmann::json XrRun::run() {
    const float exposure = mRenderer->scene().exposure;
    FrameStages<HeadGaze> stages;
    stages.begin = [this](const FrameTick& t) { return begin(t); };
    stages.gaze = [this](const FrameTick&) { return gaze(); };
    stages.views = [this, exposure](const FrameTick&, const HeadGaze& g) {
        const auto eyes = eyeViews(mFrame, g, mPlacement, *mSession, *mMethods, mOptions.taa,
                                   exposure, mMethods->thesis());
        return std::vector<render::View>(eyes.begin(), eyes.end());
    };
    stages.targets = [this](const FrameTick& t, std::span<const render::View>) {
        return targets(t);
    };
    stages.done = [this](const FrameTick& t, const HeadGaze& g, std::span<const render::View> v,
                         const render::FrameResult& result) { return done(t, g, v, result); };
    stages.onStop = OnStopRequest::BeginStageEnds;
    // An animated scene is posed for when the frame will be seen: the runtime's predicted
    // display time, counted from the first frame's.
    stages.sceneTime = [this](const FrameTick&) {
        if (mFirstDisplayTime == 0) mFirstDisplayTime = mFrame.displayTime;
        return mOptions.time + static_cast<double>(mFrame.displayTime - mFirstDisplayTime) * 1e-9;
    };
    const FrameClock clock;
    mT0 = clock.start();
    mLastFrameEnd = mT0;
    const uint32_t rendered = runFrameLoop(*mRenderer, clock, 0, stages);
    return summary(rendered);
}

nlohmann::json XrRun::summary(uint32_t rendered) {
    mRenderer->waitIdle();
    vk::Context& ctx = mRenderer->context();
    nlohmann::json eyes = nlohmann::json::array();
    for (uint32_t e = 0; e < 2; ++e) {
        const VkExtent2D size = mSession->eyeExtent(e),
                         recommended = mSession->recommendedExtent(e);
        eyes.push_back({{"name", e == 0 ? "left" : "right"},
                        {"width", size.width},
                        {"height", size.height},
                        {"recommended", {recommended.width, recommended.height}},
                        {"gpu_ms_median", mStats.eyeGpuMs(e)}});
    }
    nlohmann::json summary = {{"runtime", mRuntime->runtimeName()},
                              {"system", mRuntime->systemName()},
                              {"device", ctx.deviceName()},
                              {"space", mSession->spaceName()},
                              {"swapchain_format", static_cast<int>(mSession->format())},
                              {"session_states", mSession->lifecycle().history()},
                              // An animated scene's time at the last frame (its predicted
                              // display time since the first frame's, plus --time).
                              {"animated", mRenderer->animated()},
                              {"scene_time_s", mRenderer->sceneTime()}};
    const std::string ownGazeName = mOwnGaze ? mOwnGaze->describe() : "ahead";
    const uint32_t ownGazeFrames = rendered - mRuntimeGazeFrames;
    std::string gazeUsed;
    if (mRuntimeGazeFrames > 0 && ownGazeFrames == 0) {
        gazeUsed = "XR_EXT_eye_gaze_interaction";
    } else if (mRuntimeGazeFrames > 0) {
        gazeUsed = "XR_EXT_eye_gaze_interaction, else " + ownGazeName;
    } else {
        gazeUsed = ownGazeName;
        if (mEyeGaze) {
            mEyeGazeStatus = "offered, but no valid gaze pose was reported";
        }
    }
    // The action sets before the session they belong to.
    mEyeGaze.reset();
    mActions.reset();
    mSession.reset();
    checkOwnValidation(ctx);
    if (mOptions.frames != 0 && rendered < mOptions.frames && !stopRequested()) {
        throw Error("the OpenXR runtime ended the session after " + std::to_string(rendered) +
                    " of " + std::to_string(mOptions.frames) + " frames");
    }
    summary.update(mStats.json());
    summary.update({{"placement",
                     {{"origin", {mPlacement.origin.x, mPlacement.origin.y, mPlacement.origin.z}},
                      {"yaw_deg", glm::degrees(mPlacement.yawRad)},
                      {"scale", mPlacement.scale}}},
                    {"method", mOptions.method},
                    {"eye_gaze_extension", mEyeGazeStatus},
                    {"gaze_source", gazeUsed},
                    {"frames", rendered},
                    {"frames_with_runtime_gaze", mRuntimeGazeFrames},
                    {"frames_not_shown", mEmptyFrames},
                    {"session_ended_by_runtime", mExited},
                    {"eyes", eyes},
                    {"validation_errors", ctx.validationErrors()},
                    {"validation_errors_in_runtime_calls", ctx.runtimeValidationErrors()},
                    {"screenshot", mShotInfo}});
    return summary;
}

} // namespace

nlohmann::json runXr(const XrOptions& o) {
    XrRun run(o);
    return run.run();
}

} // namespace gt::app
