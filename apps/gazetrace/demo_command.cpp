#include "demo_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <tuple>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "atomic_write.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "demo_calibration.hpp"
#include "demo_overlay.hpp"
#include "display/hmd_profile.hpp"
#include "eccentricity_layers.hpp"
#include "foveation/contrast_sensitivity.hpp"
#include "foveation/neighbour_index.hpp"
#include "foveation/point_set_cache.hpp"
#include "full_resolution.hpp"
#include "gaze_input.hpp"
#include "gaze_mapping.hpp"
#include "layers_command.hpp"
#include "method_factory.hpp"
#include "option_parsing.hpp"
#include "point_set_method.hpp"
#include "renderer.hpp"
#include "scene/camera_path.hpp"
#include "scene/image_io.hpp"
#include "scene/start_view.hpp"
#include "stereo_rig.hpp"
#include "swapchain_target.hpp"
#include "view_args.hpp"
#include "vk/context.hpp"
#include "vk/swapchain.hpp"
#include "window.hpp"

namespace gt::app {

namespace {

double msBetween(SteadyClock::time_point a, SteadyClock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// Free flight: WASD (and Q/E down/up) move, the mouse turns the view while the right button is
// held, so the mouse can still be the gaze the rest of the time. Speed follows the scene's size.
class FlyCamera {
public:
    FlyCamera(const scene::Camera& start, float speed) : mCamera(start), mSpeed(speed) {}
    void update(Window& w, double dtS) {
        const glm::vec3 f = glm::normalize(mCamera.forward);
        const glm::vec3 r = glm::normalize(glm::cross(f, glm::vec3(0, 1, 0)));
        glm::vec3 move(0.0f);
        if (w.key(GLFW_KEY_W)) move += f;
        if (w.key(GLFW_KEY_S)) move -= f;
        if (w.key(GLFW_KEY_D)) move += r;
        if (w.key(GLFW_KEY_A)) move -= r;
        if (w.key(GLFW_KEY_E)) move += glm::vec3(0, 1, 0);
        if (w.key(GLFW_KEY_Q)) move -= glm::vec3(0, 1, 0);
        if (glm::length(move) > 0.0f) {
            const float boost = w.key(GLFW_KEY_LEFT_SHIFT) ? 4.0f : 1.0f;
            mCamera.position += glm::normalize(move) * mSpeed * boost * static_cast<float>(dtS);
            mMoved = true;
        }
        const glm::vec2 c = w.cursor();
        if (w.mouseButton(GLFW_MOUSE_BUTTON_RIGHT)) {
            if (mLook) {
                const glm::vec2 d = (c - *mLook) * 0.004f;
                mYaw -= d.x;
                mPitch = std::clamp(mPitch - d.y, -1.5f, 1.5f);
                if (d.x != 0.0f || d.y != 0.0f) mMoved = true;
            } else {
                mYaw = std::atan2(f.x, -f.z);
                mPitch = std::asin(std::clamp(f.y, -1.0f, 1.0f));
            }
            mLook = c;
            mCamera.forward = glm::vec3(std::sin(mYaw) * std::cos(mPitch), std::sin(mPitch),
                                        -std::cos(mYaw) * std::cos(mPitch));
            mCamera.up = glm::vec3(0, 1, 0);
        } else {
            mLook.reset();
        }
    }
    [[nodiscard]] const scene::Camera& camera() const noexcept { return mCamera; }
    void set(const scene::Camera& c) { mCamera = c; }
    [[nodiscard]] bool takeMoved() {
        const bool m = mMoved;
        mMoved = false;
        return m;
    }

private:
    scene::Camera mCamera;
    float mSpeed;
    std::optional<glm::vec2> mLook;
    float mYaw = 0.0f, mPitch = 0.0f;
    bool mMoved = false;
};

// The foveation method for the current window size: a point set per size, built on first use
// and cached on disk like the command line's (desktop screen, same pixels per degree); with an
// HMD, the point set of its eyes' display, shared by both eyes.
class Methods {
public:
    Methods(render::Renderer& r, const DemoSettings& s, std::string cacheDir, bool displaySpace,
            render::EccentricityLayerSettings layers)
        : mRenderer(r), mSettings(s), mCacheDir(std::move(cacheDir)), mDisplaySpace(displaySpace),
          mLayerSettings(std::move(layers)) {}
    render::FoveationMethod& forHmd(const display::HmdProfile& hmd) {
        // Layers: each eye's frustum is its field of view.
        if (mSettings.method == "layers") return layers(mHmdLayers, std::nullopt);
        return forDisplay(foveation::displayProfile(hmd.pointSetProfile));
    }
    render::FoveationMethod& forSize(uint32_t w, uint32_t h) {
        // Layers: the window on the desktop screen (the method sizes them per window).
        if (mSettings.method == "layers") {
            return layers(mWindowLayers,
                          foveation::displayProfile(foveation::DisplayModel::Desktop));
        }
        return forDisplay(foveation::windowProfile(
            foveation::displayProfile(foveation::DisplayModel::Desktop), w, h));
    }
    [[nodiscard]] double lastBuildMs() const noexcept { return mBuildMs; }
    // The point-set method last handed out (for the overlay's counts), or null.
    [[nodiscard]] const render::PointSetMethod* current() const noexcept { return mCurrent; }

private:
    render::FoveationMethod& layers(std::optional<render::EccentricityLayers>& slot,
                                    std::optional<foveation::DisplayProfile> display) {
        if (!slot) {
            render::EccentricityLayerSettings s = mLayerSettings;
            s.display = std::move(display);
            slot.emplace(mRenderer.methodContext(), s);
        }
        mCurrent = nullptr;
        return *slot;
    }
    render::FoveationMethod& forDisplay(const foveation::DisplayProfile& display) {
        if (mSettings.method == "reference") {
            if (!mReference) mReference.emplace(mRenderer.methodContext());
            mReference->settings = {mSettings.raysPerPoint, 0};
            mCurrent = nullptr;
            return *mReference;
        }
        auto& slot = mPointSets[{display.width, display.height, mSettings.scale}];
        if (!slot) build(slot, display);
        // The interpolation and rays follow the settings every frame (nothing to rebuild
        // except the k-NN table, which the method builds when k changes).
        passes::InterpolateSettings interp;
        interp.method = mSettings.view.empty() ? parseInterpolation(mSettings.interp)
                                               : parseView(mSettings.view);
        interp.k = mSettings.k;
        slot->settings = {mSettings.raysPerPoint, interp, mDisplaySpace};
        mCurrent = slot.get();
        return *slot;
    }
    void build(std::unique_ptr<render::PointSetMethod>& slot,
               const foveation::DisplayProfile& display) {
        const auto t = SteadyClock::now();
        foveation::PointSetParams params;
        params.display = display;
        params.scale = mSettings.scale;
        slot = render::makeMethod(
            render::PointSetConfig{params, mCacheDir.empty() ? defaultCacheDir()
                                                             : std::filesystem::path(mCacheDir)},
            mRenderer.methodContext());
        mBuildMs = msBetween(t, SteadyClock::now());
        log::info("point set for " + std::to_string(display.width) + "x" +
                  std::to_string(display.height) + " at scale " + std::to_string(params.scale) +
                  " ready in " + std::to_string(static_cast<int>(mBuildMs)) + " ms");
    }

    render::Renderer& mRenderer;
    const DemoSettings& mSettings;
    std::string mCacheDir;
    bool mDisplaySpace;
    render::EccentricityLayerSettings mLayerSettings;
    std::optional<render::FullResolution> mReference;
    std::optional<render::EccentricityLayers> mWindowLayers, mHmdLayers;
    std::map<std::tuple<uint32_t, uint32_t, double>, std::unique_ptr<render::PointSetMethod>>
        mPointSets;
    const render::PointSetMethod* mCurrent = nullptr;
    double mBuildMs = 0.0;
};

void checkOptions(const DemoOptions& o) {
    if (o.method != "foveated" && o.method != "reference" && o.method != "layers") {
        throw ArgumentError("--method: '" + o.method + "' (known: foveated, layers, reference)");
    }
    (void)parseSlope(o.slope);
    if (o.method == "foveated") {
        (void)parseInterpolation(o.interp);
        if (!o.view.empty()) (void)parseView(o.view);
        if (o.k == 0 || o.k > foveation::NeighbourIndex::kMaxNeighbours) {
            throw ArgumentError("--k must be 1..20");
        }
    }
    if (!(o.frameMs >= 0.0)) throw ArgumentError("--frame-ms must not be negative");
    if (o.framesInFlight > 4) {
        throw ArgumentError("--frames-in-flight must be 0 (automatic) to 4");
    }
    (void)parsePresentMode(o.present);
    if (!o.hmd.empty()) (void)hmdProfile(o.hmd); // a bad name fails before the window
    if (!o.screenshot.empty() && std::filesystem::path(o.screenshot).extension() != ".png") {
        throw ArgumentError("--screenshot: give a .png file, got '" + o.screenshot + "'");
    }
}

} // namespace

nlohmann::json runDemo(const DemoOptions& o) {
    checkOptions(o);
    // --resize FRAME:WxH (GCC warned about an optional<pair> here: plain values instead).
    bool resizePending = false;
    uint32_t resizeFrame = 0;
    VkExtent2D resizeTo{};
    if (!o.resize.empty()) {
        unsigned f = 0, w = 0, h = 0;
        char extra = 0;
        if (std::sscanf(o.resize.c_str(), "%u:%ux%u%c", &f, &w, &h, &extra) != 3 || w < 16 ||
            h < 16 || w > 8192 || h > 8192) {
            throw ArgumentError("--resize: expected FRAME:WxH (16..8192), got '" + o.resize + "'");
        }
        resizePending = true;
        resizeFrame = f;
        resizeTo = {w, h};
    }
    const std::optional<CameraArg> cameraArg = parseCamera(o.camera);
    std::optional<scene::CameraPath> path;
    if (!o.cameraPath.empty()) path = scene::CameraPath::load(o.cameraPath);
    std::optional<io::AtomicFile> logFile;
    std::ostream* log = nullptr;
    if (!o.log.empty()) {
        logFile.emplace(o.log); // a missing folder fails now, not after the run
        log = &logFile->stream();
        *log << "frame,t_ms,frame_ms,gpu_ms,gaze_x,gaze_y,gaze_sequence,gaze_t_ms,latency_ms\n";
    }

    // The gaze source first: a bad one fails before a window opens. The mouse reads the window
    // once it exists.
    std::optional<Window> window;
    GazeInputContext gazeContext;
    gazeContext.calibration = o.calibration;
    gazeContext.cursor = [&window] { return window ? window->cursor() : glm::vec2(0.0f); };
    std::optional<CalibrationSession> calibration;
    std::unique_ptr<GazeInput> gaze;
    if (o.calibrate) {
        calibration.emplace(o.gaze, o.calibration);
        gaze = openGazeInput("fixed:0,0", gazeContext); // the fovea follows the target instead
    } else {
        gaze = openGazeInput(o.gaze, gazeContext);
    }
    window.emplace("gazetrace", o.width, o.height);

    render::RendererOptions ro;
    ro.scene = o.scene;
    ro.validate = o.validate;
    ro.framesInFlight = o.framesInFlight;
    ro.deviceOverride = deviceRequest();
    ro.sceneLoad = gltfLoadOptions();
    ro.display.instanceExtensions = window->requiredInstanceExtensions();
    ro.display.deviceExtensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
    ro.display.createSurface = [&window](VkInstance i) { return window->createSurface(i); };
    render::Renderer renderer(ro);
    vk::Context& ctx = renderer.context();
    vk::Swapchain swapchain(ctx, window->framebufferSize(), parsePresentMode(o.present));
    render::SwapchainTarget target(ctx);
    render::OutputTarget* const targetPtr = &target;
    DemoSettings settings{
        o.method, o.interp, o.k,   o.method == "foveated" ? o.raysPerPoint : o.spp,
        o.scale,  o.taa,    o.view};
    Methods methods(renderer, settings, o.cacheDir,
                    o.displaySpace && !o.hmd.empty() && o.distortion,
                    layerSettings(o.slope, o.layers, o.spp));
    std::optional<DemoOverlay> overlay;
    if (o.overlay || calibration) {
        overlay.emplace(*window, ctx, swapchain.format(), swapchain.imageCount());
        if (calibration) overlay->toggle(); // the targets only: the panel would hide some
    }
    DemoStats stats;
    stats.gazeSource = gaze->describe();
    stats.device = ctx.deviceName();
    std::optional<render::StereoRig> rig;
    if (!o.hmd.empty()) rig.emplace(hmdProfile(o.hmd), o.distortion);

    const scene::Scene& sc = renderer.scene();
    const float sceneSize = glm::length(sc.boundsMax() - sc.boundsMin());
    scene::Camera start = sc.camera;
    if (cameraArg) {
        start = cameraArg->camera(sc.camera.yfov);
    } else if (sc.cameraFramed) {
        // No camera in the file: inside an enclosed scene, start inside rather than outside.
        if (const auto inside = scene::insideStartView(sc, renderer.bvh())) start = *inside;
    }
    FlyCamera fly(start, std::max(0.25f * sceneSize, 0.1f));
    std::optional<std::vector<scene::CameraKey>> recording;

    auto recreate = [&](VkExtent2D size) {
        swapchain.recreate(size);
        if (overlay) overlay->swapchainRecreated(swapchain.imageCount());
    };
    const auto t0 = SteadyClock::now();
    auto last = t0;
    std::vector<double> frameTimes, latencies;
    struct FrameGaze {
        SteadyClock::time_point sampled;
        uint64_t sequence;
        double sourceMs;
        glm::vec2 pixel;
    };
    std::map<uint64_t, FrameGaze> inFlight; // the gaze each frame in flight used
    std::optional<glm::vec2> gazePx;
    std::optional<GazeReading> lastReading;
    const render::ScreenGeometry screen; // the desktop profile's screen
    uint32_t frame = 0;
    int screenshotsTaken = 0;
    double fpsShown = 0.0;
    while (!window->shouldClose() && (o.frames == 0 || frame < o.frames)) {
        if (resizePending && frame == resizeFrame) {
            window->setSize(resizeTo.width, resizeTo.height);
            resizePending = false;
        }
        window->poll();
        VkExtent2D fb = window->framebufferSize();
        if (fb.width == 0 || fb.height == 0) {
            window->waitEvents(); // minimised: nothing to draw
            continue;
        }
        if (window->takeResized() || fb.width != swapchain.extent().width ||
            fb.height != swapchain.extent().height) {
            recreate(fb);
        }
        for (const int key : window->takePressedKeys()) {
            if (key == GLFW_KEY_ESCAPE) window->requestClose();
            if (key == GLFW_KEY_T) settings.taa = !settings.taa;
            if (key == GLFW_KEY_TAB && overlay) overlay->toggle();
            if (key == GLFW_KEY_M) {
                settings.method = settings.method == "foveated" ? "layers"
                                  : settings.method == "layers" ? "reference"
                                                                : "foveated";
            }
            if (key == GLFW_KEY_I) {
                settings.interp = settings.interp == "nn"    ? "msm"
                                  : settings.interp == "msm" ? "rbf"
                                                             : "nn";
            }
            if (key == GLFW_KEY_V) {
                settings.view = settings.view.empty()       ? "points"
                                : settings.view == "points" ? "cells"
                                : settings.view == "cells"  ? "eccentricity"
                                                            : "";
            }
            if (key == GLFW_KEY_LEFT_BRACKET && settings.raysPerPoint > 1) --settings.raysPerPoint;
            if (key == GLFW_KEY_RIGHT_BRACKET && settings.raysPerPoint < 64)
                ++settings.raysPerPoint;
            if (key == GLFW_KEY_P) target.requestScreenshot();
            if (key == GLFW_KEY_R) {
                if (recording) {
                    const std::string file = "camera_path.csv";
                    scene::CameraPath::fromKeys(std::move(*recording)).save(file);
                    log::info("recorded camera path written to " + file);
                    recording.reset();
                } else {
                    recording.emplace();
                    log::info("recording the camera path (R again to stop)");
                }
            }
        }
        const auto now = SteadyClock::now();
        const double dtS = std::min(msBetween(last, now) * 1e-3, 0.25);
        last = now;
        const double tMs = o.frameMs > 0.0 ? frame * o.frameMs : msBetween(t0, now);
        // Calibration: the target of this moment, from the desktop screen into the window (which
        // stands for the whole screen during a calibration: run it full screen).
        std::optional<glm::vec2> calibrationTarget;
        if (calibration) {
            const auto t = calibration->target(tMs);
            if (!t) break; // every target shown
            const eyetrack::DisplayGeometry& d = calibration->display();
            const VkExtent2D fbNow = window->framebufferSize();
            calibrationTarget =
                *t * glm::vec2(static_cast<float>(fbNow.width) / static_cast<float>(d.widthPx),
                               static_cast<float>(fbNow.height) / static_cast<float>(d.heightPx));
        }
        fly.update(*window, dtS);
        if (path) fly.set(path->at(path->startMs() + tMs, fly.camera().yfov));
        if (recording) {
            const scene::Camera& c = fly.camera();
            recording->push_back({tMs, c.position, c.position + glm::normalize(c.forward)});
        }

        const std::optional<vk::Swapchain::Image> image = swapchain.acquire();
        if (!image) {
            recreate(window->framebufferSize());
            continue;
        }
        const VkExtent2D ext = swapchain.extent();
        const std::optional<GazeReading> reading = gaze->read(tMs);
        if (reading) {
            lastReading = reading;
            // Desktop: angles land on the desktop profile's physical screen, screen pixels are
            // moved into the window; window pixels (mouse, pixel traces) are used as they are.
            const glm::vec2 origin(window->position());
            gazePx = reading->anglesDeg      ? screen.pixelOfAngles(*reading->anglesDeg) - origin
                     : reading->windowPixels ? reading->screenPx
                                             : reading->screenPx - origin;
        }
        std::vector<render::View> views;
        if (rig) {
            // Each eye in its half of the window; the gaze is a pixel of the left eye's image
            // (the mouse over either half counts as that point of the left eye).
            const display::HmdProfile& p = rig->profile();
            glm::vec2 g = gazePx.value_or(
                display::lensCentre(display::eyeTangents(p, 0)) *
                glm::vec2(static_cast<float>(p.eyeWidth), static_cast<float>(p.eyeHeight)));
            if (o.gaze == "mouse") {
                const float half = 0.5f * static_cast<float>(ext.width);
                const float x = std::fmod(g.x, half);
                g = glm::vec2(x / half * static_cast<float>(p.eyeWidth),
                              g.y / static_cast<float>(ext.height) *
                                  static_cast<float>(p.eyeHeight));
            }
            render::StereoGaze sg;
            sg.direction = rig->directionOfLeftPixel(g);
            if (lastReading && lastReading->anglesDeg) {
                sg.direction = render::directionOfAngles(*lastReading->anglesDeg);
            }
            for (int e = 0; e < 2 && lastReading; ++e) {
                if (lastReading->eyeAnglesDeg[e]) {
                    sg.eyeDirection[e] = render::directionOfAngles(*lastReading->eyeAnglesDeg[e]);
                }
            }
            if (o.vergenceM > 0.0) sg.vergenceM = static_cast<float>(o.vergenceM);
            sg.saccade = reading && reading->saccade;
            render::PostSettings post;
            post.taa = settings.taa && settings.view.empty();
            const auto eyes = rig->views(fly.camera(), sg, methods.forHmd(p), post, sc.exposure);
            views.assign(eyes.begin(), eyes.end());
            const uint32_t half = ext.width / 2;
            target.place("left", {{0, 0}, {half, ext.height}});
            target.place("right",
                         {{static_cast<int32_t>(half), 0}, {ext.width - half, ext.height}});
        } else {
            render::View view;
            view.camera = fly.camera();
            view.width = ext.width;
            view.height = ext.height;
            view.exposure = sc.exposure;
            view.method = &methods.forSize(ext.width, ext.height);
            view.post.taa = settings.taa && settings.view.empty();
            if (reading) view.saccade = reading->saccade;
            const glm::vec2 lastPixel(static_cast<float>(ext.width) - 1.0f,
                                      static_cast<float>(ext.height) - 1.0f);
            view.gaze = glm::clamp(calibrationTarget
                                       ? *calibrationTarget
                                       : gazePx.value_or(0.5f * glm::vec2(ext.width, ext.height)),
                                   glm::vec2(0.0f), lastPixel);
            views.push_back(view);
        }
        const std::vector<render::OutputTarget*> targets(views.size(), targetPtr);
        target.setImage(*image, swapchain.format(), ext);
        if (overlay) {
            stats.frameMs = frameTimes.empty()
                                ? 0.0
                                : median(std::vector<double>(
                                      frameTimes.end() -
                                          std::min<std::ptrdiff_t>(
                                              30, static_cast<std::ptrdiff_t>(frameTimes.size())),
                                      frameTimes.end()));
            stats.latencyMs = latencies.empty() ? 0.0 : latencies.back();
            stats.pointsSampled =
                methods.current() ? methods.current()->pointsSampled(views[0].gaze) : 0;
            (void)overlay->build(settings, stats, calibrationTarget);
            target.setOverlay(
                [&overlay](rg::RenderGraph& g, rg::TextureId img) { return overlay->add(g, img); });
        }
        const bool lastFrame = o.frames != 0 && frame + 1 == o.frames;
        if (lastFrame && !o.screenshot.empty()) target.requestScreenshot();
        const render::FrameResult result = renderer.renderFrame(views, targets);
        stats.rays = 0;
        for (const auto& v : result.views)
            stats.rays += v.rays;
        if (reading) {
            inFlight[result.number] = {reading->sampled, reading->sequence, reading->sourceMs,
                                       views[0].gaze};
        }
        if (!swapchain.present(*image)) recreate(window->framebufferSize());

        // Frames the GPU finished: their GPU time and the latency from their gaze sample to
        // the moment the frame was known finished (the driver offers no present timing here).
        std::vector<rg::CompletedFrame> done = renderer.takeCompleted();
        if (result.timings) done.push_back({result.number, *result.timings});
        const auto finishedAt = SteadyClock::now();
        for (const rg::CompletedFrame& c : done) {
            if (overlay) overlay->addTimings(c.timings);
            double latency = -1.0;
            FrameGaze used{{}, 0, 0.0, views[0].gaze};
            if (const auto it = inFlight.find(c.number); it != inFlight.end()) {
                used = it->second;
                latency = msBetween(used.sampled, finishedAt);
                latencies.push_back(latency);
                inFlight.erase(it);
            }
            if (log) {
                *log << c.number << "," << tMs << ","
                     << (frameTimes.empty() ? 0.0 : frameTimes.back()) << "," << c.timings.gpuMs
                     << "," << used.pixel.x << "," << used.pixel.y << "," << used.sequence << ","
                     << used.sourceMs << "," << latency << "\n";
            }
        }
        frameTimes.push_back(msBetween(now, SteadyClock::now()));
        ++frame;
        if (frame % 10 == 0) {
            fpsShown = 1000.0 / std::max(median(frameTimes), 1e-3);
            char title[160];
            std::snprintf(title, sizeof(title), "gazetrace - %.1f fps - %s - gaze %s", fpsShown,
                          views[0].method->name().data(), gaze->describe().c_str());
            glfwSetWindowTitle(window->handle(), title);
        }
        if (target.screenshot() && !lastFrame && o.screenshot.empty()) {
            const std::string file =
                "gazetrace_screenshot_" + std::to_string(++screenshotsTaken) + ".png";
            image::writePngAtomic(file, ext.width, ext.height, *target.screenshot());
            log::info("screenshot written to " + file);
        }
    }
    renderer.waitIdle();
    if (!o.screenshot.empty()) {
        if (!target.screenshot()) {
            throw Error("--screenshot: the window closed before the last frame was shown");
        }
        image::writePngAtomic(o.screenshot, target.extent().width, target.extent().height,
                              *target.screenshot());
    }
    if (ctx.validationErrors() > 0) {
        throw Error(std::to_string(ctx.validationErrors()) + " Vulkan validation error(s)");
    }
    if (logFile) logFile->commit();
    nlohmann::json calibrationSummary;
    if (calibration) calibrationSummary = calibration->finish();
    // Steady state: leave out the first frames (pipelines warming, point set building).
    const std::vector<double> steady =
        frameTimes.size() > 4 ? std::vector<double>(frameTimes.begin() + 2, frameTimes.end())
                              : frameTimes;
    const double frameMedian = median(steady);
    return {{"device", ctx.deviceName()},
            {"present_mode", vk::toString(swapchain.presentMode())},
            {"window", {swapchain.extent().width, swapchain.extent().height}},
            {"method", o.method},
            {"hmd", o.hmd},
            {"gaze_source", calibration ? o.gaze : gaze->describe()},
            {"frames", frame},
            {"frames_in_flight", renderer.framesInFlight()},
            {"frame_ms_median", frameMedian},
            {"fps", frameMedian > 0.0 ? 1000.0 / frameMedian : 0.0},
            {"latency_ms_median", median(latencies)},
            {"point_set_build_ms", methods.lastBuildMs()},
            {"screenshot", o.screenshot},
            {"calibration", calibrationSummary}};
}

} // namespace gt::app
