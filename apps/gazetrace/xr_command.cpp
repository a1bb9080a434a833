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

#include "core/error.hpp"
#include "core/log.hpp"
#include "eccentricity_layers.hpp"
#include "external_image_target.hpp"
#include "eye_gaze.hpp"
#include "foveation/neighbour_index.hpp"
#include "foveation/point_set_cache.hpp"
#include "full_resolution.hpp"
#include "gaze_input.hpp"
#include "layers_command.hpp"
#include "method_factory.hpp"
#include "option_parsing.hpp"
#include "point_set_method.hpp"
#include "renderer.hpp"
#include "scene/image_io.hpp"
#include "scene/start_view.hpp"
#include "stereo_rig.hpp"
#include "view_args.hpp"
#include "xr_error.hpp"
#include "xr_runtime.hpp"
#include "xr_session.hpp"
#include "xr_views.hpp"

namespace gt::app {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

double medianOf(std::vector<double> v) {
    if (v.empty()) {
        return 0.0;
    }
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
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

// The foveation method of an eye image (its size and field of view), built on first use and
// shared by every eye with the same display; the reference method for --method reference.
class EyeMethods {
public:
    EyeMethods(render::Renderer& r, const XrOptions& o) : mRenderer(r), mOptions(o) {}
    render::FoveationMethod& forEye(const XrFovf& fov, VkExtent2D size) {
        if (mOptions.method == "reference") {
            if (!mReference) {
                mReference.emplace(mRenderer.methodContext());
                mReference->settings = {mOptions.spp, 0};
            }
            return *mReference;
        }
        if (mOptions.method == "layers") {
            // One method for both eyes: each eye's layers follow its own frustum (XrFovf).
            if (!mLayers) {
                mLayers.emplace(mRenderer.methodContext(),
                                layerSettings(mOptions.slope, mOptions.layers, mOptions.spp));
            }
            return *mLayers;
        }
        const foveation::DisplayProfile display = xr::eyeDisplay(fov, size.width, size.height);
        // v to 1e-4 display widths: a runtime's per-frame float noise must not rebuild the set.
        const auto key =
            std::make_tuple(size.width, size.height, std::lround(display.viewingDistance * 1e4));
        auto& slot = mPointSets[key];
        if (!slot) {
            foveation::PointSetParams params;
            params.display = display;
            params.scale = mOptions.pointScale;
            const auto t = Clock::now();
            passes::InterpolateSettings interp;
            interp.method = parseInterpolation(mOptions.interp);
            interp.k = mOptions.k;
            slot = render::makeMethod(
                render::PointSetConfig{params,
                                       mOptions.cacheDir.empty()
                                           ? defaultCacheDir()
                                           : std::filesystem::path(mOptions.cacheDir),
                                       {mOptions.raysPerPoint, interp, false}},
                mRenderer.methodContext());
            if (parseReconstruction(mOptions.reconstruction) == render::Reconstruction::Thesis) {
                passes::TaaSettings unused; // the views' TAA follows in eyeViews
                render::useThesisReconstruction(slot->settings, unused);
            }
            log::info("xr: point set for " + std::to_string(size.width) + "x" +
                      std::to_string(size.height) + " eyes (v = " +
                      std::to_string(display.viewingDistance) + " widths) ready in " +
                      std::to_string(static_cast<int>(msSince(t, Clock::now()))) + " ms");
        }
        return *slot;
    }

private:
    render::Renderer& mRenderer;
    const XrOptions& mOptions;
    std::optional<render::FullResolution> mReference;
    std::optional<render::EccentricityLayers> mLayers;
    std::map<std::tuple<uint32_t, uint32_t, long>, std::unique_ptr<render::PointSetMethod>>
        mPointSets;
};

// The gaze of one frame in the head frame (OpenXR axes): a fixation point, or a direction
// when the eyes look at infinity.
struct HeadGaze {
    glm::vec3 point{0.0f, 0.0f, -1.0f}; // straight ahead
    bool atInfinity = true;
    // Each tracked eye's own direction (per-eye angle traces, UDP): replaces `point` for it.
    std::optional<glm::vec3> eyeDirection[2];
    bool saccade = false;
    std::optional<Clock::time_point> sampled; // when the sample was taken
};

// The gaze ray from `origin` along `direction`, fixated at `vergenceM` (0: infinity).
HeadGaze fixation(const glm::vec3& origin, const glm::vec3& direction, double vergenceM) {
    HeadGaze g;
    g.atInfinity = vergenceM <= 0.0;
    g.point = g.atInfinity ? direction : origin + direction * static_cast<float>(vergenceM);
    return g;
}

// gazetrace's own angles (yaw right, pitch up; +Z ahead) in OpenXR's axes (-Z ahead).
glm::vec3 xrDirectionOfAngles(glm::vec2 anglesDeg) {
    const glm::vec3 d = render::directionOfAngles(anglesDeg);
    return {d.x, d.y, -d.z};
}

HeadGaze runtimeHeadGaze(const xr::EyeGazeSample& s, double vergenceM, const xr::Runtime& rt) {
    HeadGaze g = fixation(s.origin, s.direction, vergenceM);
    if (s.time != 0) {
        g.sampled = rt.fromXrTime(s.time);
    }
    return g;
}

// From one of gazetrace's sources (none: straight ahead). Pixels are the left eye's image's.
HeadGaze ownHeadGaze(GazeInput* input, double tMs, const xr::FrameInfo& frame, VkExtent2D left,
                     double vergenceM) {
    const std::optional<GazeReading> r = input ? input->read(tMs) : std::nullopt;
    if (!r) {
        return {};
    }
    const glm::vec3 dir =
        r->anglesDeg ? xrDirectionOfAngles(*r->anglesDeg)
                     : xr::directionOfPixel(r->screenPx, frame.headViews[0].pose,
                                            frame.headViews[0].fov, left.width, left.height);
    HeadGaze g = fixation(glm::vec3(0.0f), dir, vergenceM);
    for (int e = 0; e < 2; ++e) {
        if (r->eyeAnglesDeg[e]) {
            g.eyeDirection[e] = xrDirectionOfAngles(*r->eyeAnglesDeg[e]);
        }
    }
    g.saccade = r->saccade;
    g.sampled = r->sampled;
    return g;
}

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
        v.name = e == 0 ? "left" : "right";
        v.camera = xr::cameraOfPose(eye.pose, placement);
        v.camera.yfov = eye.fov.angleUp - eye.fov.angleDown;
        v.frustum = xr::tangentsOfFov(eye.fov);
        v.width = size.width;
        v.height = size.height;
        const bool own = gaze.eyeDirection[e].has_value();
        v.gaze =
            xr::gazePixel(own ? *gaze.eyeDirection[e] : gaze.point, own || gaze.atInfinity,
                          frame.headViews[e].pose, frame.headViews[e].fov, size.width, size.height);
        v.saccade = gaze.saccade;
        v.method = &methods.forEye(eye.fov, size);
        v.post.taa = taa;
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

// The median of all but the first value: the first frame compiles pipelines and builds tables.
double steadyMedian(std::vector<double> v) {
    if (v.size() > 1) {
        v.erase(v.begin());
    }
    return medianOf(std::move(v));
}

// The run's figures: per-pass and per-eye GPU times, wall times, rays and gaze ages.
class RunStats {
public:
    void addFrame(const render::FrameResult& result, double renderMs) {
        mRenderMs.push_back(renderMs);
        for (const auto& v : result.views) {
            mRays += v.rays;
        }
        if (!result.timings) {
            return;
        }
        std::array<double, 2> eyeSum{0.0, 0.0};
        for (const rg::PassTiming& p : result.timings->passes) {
            mPassMs[p.name].push_back(p.gpuMs);
            for (std::size_t e = 0; e < 2; ++e) {
                if (p.name.starts_with(e == 0 ? "left." : "right.")) {
                    eyeSum[e] += p.gpuMs;
                }
            }
        }
        mEyeGpuMs[0].push_back(eyeSum[0]);
        mEyeGpuMs[1].push_back(eyeSum[1]);
    }
    void addInterval(double ms) { mFrameMs.push_back(ms); }
    void addGazeAge(double ms) { mGazeToDisplayMs.push_back(ms); }

    [[nodiscard]] uint64_t rays() const noexcept { return mRays; }
    [[nodiscard]] double eyeGpuMs(std::size_t eye) const { return steadyMedian(mEyeGpuMs[eye]); }
    [[nodiscard]] nlohmann::json json() const {
        nlohmann::json passes = nlohmann::json::object();
        for (const auto& [name, times] : mPassMs) {
            passes[name] = steadyMedian(times);
        }
        return {{"rays", mRays},
                {"gpu_ms", passes},
                {"frame_ms_median", steadyMedian(mFrameMs)},
                {"render_ms_median", steadyMedian(mRenderMs)},
                {"gaze_to_display_ms_median", medianOf(mGazeToDisplayMs)}};
    }

private:
    std::vector<double> mFrameMs, mRenderMs, mGazeToDisplayMs;
    std::map<std::string, std::vector<double>> mPassMs;
    std::array<std::vector<double>, 2> mEyeGpuMs;
    uint64_t mRays = 0;
};

void checkOwnValidation(const vk::Context& ctx) {
    if (ctx.validationErrors() > 0) {
        throw Error(std::to_string(ctx.validationErrors()) +
                    " Vulkan validation error(s) in gazetrace's own calls");
    }
}

} // namespace

nlohmann::json runXr(const XrOptions& o) {
    checkOptions(o);
    const std::optional<CameraArg> cameraArg = parseCamera(o.camera);
    std::optional<glm::vec3> origin;
    if (!o.origin.empty()) {
        origin = parseVec3(o.origin, "--xr-origin");
    }
    std::optional<float> yaw;
    if (!o.yawDeg.empty()) {
        char* end = nullptr;
        const double d = std::strtod(o.yawDeg.c_str(), &end);
        if (end == o.yawDeg.c_str() || *end != '\0' || !std::isfinite(d) || std::abs(d) > 360.0) {
            throw ArgumentError("--xr-yaw: expected degrees within +-360, got '" + o.yawDeg + "'");
        }
        yaw = static_cast<float>(glm::radians(d));
    }
    if (!o.screenshot.empty()) {
        const auto dir = std::filesystem::path(o.screenshot).parent_path();
        std::error_code ec;
        if (!dir.empty() && !std::filesystem::is_directory(dir, ec)) {
            throw ArgumentError("--screenshot-eye: folder " + dir.string() + " does not exist");
        }
    }
    // Gaze source first: a bad one fails before the runtime is touched.
    std::unique_ptr<GazeInput> ownGaze;
    if (o.gaze != "ahead") {
        GazeInputContext gc;
        gc.calibration = o.calibration;
        ownGaze = openGazeInput(o.gaze, gc);
    }

    xr::RuntimeOptions rto;
    rto.eyeGaze = o.runtimeGaze;
    if (const char* manifest = std::getenv("XR_RUNTIME_JSON")) rto.runtimeManifest = manifest;
    const xr::Runtime runtime(rto);
    log::info("xr: runtime " + runtime.runtimeName() + ", system " + runtime.systemName());

    render::RendererOptions ro;
    ro.scene = o.scene;
    ro.validate = o.validate;
    ro.framesInFlight = 1; // each frame's images are released right after its submit
    ro.deviceOverride = deviceRequest();
    ro.sceneLoad = gltfLoadOptions();
    ro.display = runtime.vulkanHooks();
    render::Renderer renderer(ro);
    vk::Context& ctx = renderer.context();

    const scene::Scene& sc = renderer.scene();
    scene::Camera start = sc.camera;
    if (cameraArg) {
        start = cameraArg->camera(sc.camera.yfov);
    } else if (sc.cameraFramed) {
        if (const auto inside = scene::insideStartView(sc, renderer.bvh())) {
            start = *inside;
        }
    }

    std::optional<xr::Session> session;
    session.emplace(runtime, ctx, xr::SessionOptions{o.space == "stage", o.resolutionScale});
    xr::ScenePlacement placement =
        xr::ScenePlacement::facing(start, static_cast<float>(o.worldScale));
    if (session->spaceName() == "STAGE" && !origin) {
        // STAGE's origin is on the floor: the start view's eye stands 1.6 m above it.
        placement.origin.y -= 1.6f * placement.scale;
    }
    if (origin) {
        placement.origin = *origin;
    }
    if (yaw) {
        placement.yawRad = *yaw;
    }

    std::optional<xr::EyeGaze> eyeGaze;
    std::string eyeGazeStatus = "not offered by the runtime";
    if (!o.runtimeGaze) {
        eyeGazeStatus = "not used (--no-runtime-gaze)";
    } else if (runtime.eyeGazeOffered() && !runtime.eyeGazeSupported()) {
        eyeGazeStatus = "offered, but the system reports no eye tracker";
    } else if (runtime.eyeGazeSupported()) {
        eyeGaze.emplace(*session);
        eyeGazeStatus = "offered";
    }

    EyeMethods methods(renderer, o);
    std::array<render::ExternalImageTarget, 2> targets{render::ExternalImageTarget(ctx),
                                                       render::ExternalImageTarget(ctx)};
    const std::array<render::OutputTarget*, 2> targetPtrs{&targets[0], &targets[1]};
    const uint32_t shotEye = o.screenshotEye == "right" ? 1 : 0;

    RunStats stats;
    uint32_t rendered = 0, runtimeGazeFrames = 0, emptyFrames = 0;
    nlohmann::json shotInfo;
    const auto t0 = Clock::now();
    auto lastFrameEnd = t0;
    std::optional<Clock::time_point> exitAsked;
    bool exited = false;
    while (true) {
        if (!session->pollEvents()) {
            exited = true;
            break;
        }
        const auto now = Clock::now();
        if (exitAsked && msSince(*exitAsked, now) > 5000.0) {
            log::warn("xr: the runtime did not end the session within 5 s of the request");
            break;
        }
        if (!session->running()) {
            if (!exitAsked && rendered == 0 && msSince(t0, now) > o.startTimeoutS * 1000.0) {
                throw Error("the OpenXR session did not start within " +
                            std::to_string(static_cast<int>(o.startTimeoutS)) + " s (last state " +
                            xr::stateName(session->lifecycle().state()) +
                            "): is the headset on and the runtime's compositor running?");
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
            continue;
        }
        const xr::FrameInfo frame = session->beginFrame();
        const bool wanted = !exitAsked && (o.frames == 0 || rendered < o.frames);
        const bool render = wanted && frame.shouldRender && frame.posesValid;
        if (!render) {
            session->endFrame(frame, false);
            ++emptyFrames;
        } else {
            const auto renderStart = Clock::now();
            const std::optional<xr::EyeGazeSample> sample =
                eyeGaze ? eyeGaze->locate(frame.displayTime) : std::nullopt;
            const HeadGaze gaze = sample ? runtimeHeadGaze(*sample, o.vergenceM, runtime)
                                         : ownHeadGaze(ownGaze.get(), msSince(t0, renderStart),
                                                       frame, session->eyeExtent(0), o.vergenceM);
            runtimeGazeFrames += sample ? 1 : 0;
            const std::array<render::View, 2> views =
                eyeViews(frame, gaze, placement, *session, methods, o.taa, sc.exposure,
                         parseReconstruction(o.reconstruction) == render::Reconstruction::Thesis);
            const bool lastFrame = o.frames != 0 && rendered + 1 == o.frames;
            if (lastFrame && !o.screenshot.empty()) {
                targets[shotEye].requestScreenshot();
            }
            for (uint32_t e = 0; e < 2; ++e) {
                const xr::EyeImage img = session->acquire(e);
                targets[e].setImage({img.image, img.format, img.extent, 0});
            }
            const render::FrameResult result = renderer.renderFrame(views, targetPtrs);
            session->release(0);
            session->release(1);
            session->endFrame(frame, true);
            checkOwnValidation(ctx);
            stats.addFrame(result, msSince(renderStart, Clock::now()));
            if (gaze.sampled) {
                stats.addGazeAge(msSince(*gaze.sampled, runtime.fromXrTime(frame.displayTime)));
            }
            if (lastFrame && !o.screenshot.empty()) {
                const auto& px = targets[shotEye].screenshot();
                if (!px) {
                    throw Error("--screenshot-eye: the eye image was not read back");
                }
                const render::View& v = views[shotEye];
                image::writePngAtomic(o.screenshot, v.width, v.height, *px);
                shotInfo = screenshotJson(o, rendered, v, frame.views[shotEye]);
            }
            ++rendered;
        }
        const auto end = Clock::now();
        if (render) {
            stats.addInterval(msSince(lastFrameEnd, end));
        }
        lastFrameEnd = end;
        if (o.frames != 0 && rendered >= o.frames && !exitAsked) {
            session->requestExit();
            exitAsked = Clock::now();
        }
    }
    renderer.waitIdle();
    nlohmann::json eyes = nlohmann::json::array();
    for (uint32_t e = 0; e < 2; ++e) {
        const VkExtent2D size = session->eyeExtent(e), recommended = session->recommendedExtent(e);
        eyes.push_back({{"name", e == 0 ? "left" : "right"},
                        {"width", size.width},
                        {"height", size.height},
                        {"recommended", {recommended.width, recommended.height}},
                        {"gpu_ms_median", stats.eyeGpuMs(e)}});
    }
    nlohmann::json summary = {{"runtime", runtime.runtimeName()},
                              {"system", runtime.systemName()},
                              {"device", ctx.deviceName()},
                              {"space", session->spaceName()},
                              {"swapchain_format", static_cast<int>(session->format())},
                              {"session_states", session->lifecycle().history()}};
    const std::string ownGazeName = ownGaze ? ownGaze->describe() : "ahead";
    const uint32_t ownGazeFrames = rendered - runtimeGazeFrames;
    std::string gazeUsed;
    if (runtimeGazeFrames > 0 && ownGazeFrames == 0) {
        gazeUsed = "XR_EXT_eye_gaze_interaction";
    } else if (runtimeGazeFrames > 0) {
        gazeUsed = "XR_EXT_eye_gaze_interaction, else " + ownGazeName;
    } else {
        gazeUsed = ownGazeName;
        if (eyeGaze) {
            eyeGazeStatus = "offered, but no valid gaze pose was reported";
        }
    }
    // The action set before the session it belongs to.
    eyeGaze.reset();
    session.reset();
    checkOwnValidation(ctx);
    if (o.frames != 0 && rendered < o.frames) {
        throw Error("the OpenXR runtime ended the session after " + std::to_string(rendered) +
                    " of " + std::to_string(o.frames) + " frames");
    }

    summary.update(stats.json());
    summary.update({{"placement",
                     {{"origin", {placement.origin.x, placement.origin.y, placement.origin.z}},
                      {"yaw_deg", glm::degrees(placement.yawRad)},
                      {"scale", placement.scale}}},
                    {"method", o.method},
                    {"eye_gaze_extension", eyeGazeStatus},
                    {"gaze_source", gazeUsed},
                    {"frames", rendered},
                    {"frames_with_runtime_gaze", runtimeGazeFrames},
                    {"frames_not_shown", emptyFrames},
                    {"session_ended_by_runtime", exited},
                    {"eyes", eyes},
                    {"validation_errors", ctx.validationErrors()},
                    {"validation_errors_in_runtime_calls", ctx.runtimeValidationErrors()},
                    {"screenshot", shotInfo}});
    return summary;
}

} // namespace gt::app
