#include "demo_command.hpp"

#include <algorithm>
#include <array>
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
#include "frame_loop.hpp"
#include "full_resolution.hpp"
#include "gaze_bounds.hpp"
#include "gaze_input.hpp"
#include "gaze_mapping.hpp"
#include "gaze_view.hpp"
#include "layers_command.hpp"
#include "method_choice.hpp"
#include "option_parsing.hpp"
#include "point_set_method.hpp"
#include "renderer.hpp"
#include "scene/camera_path.hpp"
#include "scene/image_io.hpp"
#include "scene/start_view.hpp"
#include "stereo_rig.hpp"
#include "stop_request.hpp"
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

// The demo's method settings as the renderer takes them. Keys and the overlay switch methods by
// changing this struct; the overlay's words (DemoSettings) are read back only when the overlay
// changed one, never while frames simply run.
struct LiveSettings {
    MethodKind method = MethodKind::Foveated;
    passes::Interpolation interp = passes::Interpolation::Nearest;
    std::optional<passes::Interpolation> view; // a debug view in the interpolation's place
    uint32_t k = 5;
    uint32_t raysPerPoint = 1; // the reference's and the layers' rays per pixel
    double scale = 2.0;
    bool taa = true;
    render::IntegratorSettings integrator; // foveated and reference
    bool denoise = false;
};

constexpr std::array<std::pair<MethodKind, const char*>, 3> kMethodWords{
    {{MethodKind::Foveated, "foveated"},
     {MethodKind::Layers, "layers"},
     {MethodKind::Reference, "reference"}}};
constexpr std::array<std::pair<passes::Interpolation, const char*>, 3> kInterpWords{
    {{passes::Interpolation::Nearest, "nn"},
     {passes::Interpolation::Shepard, "msm"},
     {passes::Interpolation::Rbf, "rbf"}}};
constexpr std::array<std::pair<passes::Interpolation, const char*>, 4> kViewWords{
    {{passes::Interpolation::ViewPoints, "points"},
     {passes::Interpolation::ViewCells, "cells"},
     {passes::Interpolation::ViewSpacing, "eccentricity"},
     {passes::Interpolation::ViewMotion, "motion"}}};

template <typename T, std::size_t N>
const char* wordOf(const std::array<std::pair<T, const char*>, N>& words, T value) {
    for (const auto& [v, w] : words)
        if (v == value) return w;
    return "";
}

// The next value in the order the words are listed, wrapping round (the M, I and V keys).
template <typename T, std::size_t N>
T nextOf(const std::array<std::pair<T, const char*>, N>& words, T value) {
    for (std::size_t i = 0; i < N; ++i)
        if (words[i].first == value) return words[(i + 1) % N].first;
    return words[0].first;
}

LiveSettings liveSettingsOf(const DemoSettings& words) {
    LiveSettings s;
    s.method = methodKindOf(words.method).value_or(MethodKind::Foveated);
    s.interp = parseInterpolation(words.interp);
    if (!words.view.empty()) s.view = parseView(words.view);
    s.k = words.k;
    s.raysPerPoint = words.raysPerPoint;
    s.scale = words.scale;
    s.taa = words.taa;
    s.integrator = parseIntegrator({words.integrator, words.bounces, words.sequence});
    s.denoise = words.denoise;
    return s;
}

DemoSettings wordsOf(const LiveSettings& s) {
    return {wordOf(kMethodWords, s.method),
            wordOf(kInterpWords, s.interp),
            s.k,
            s.raysPerPoint,
            s.scale,
            s.taa,
            s.view ? wordOf(kViewWords, *s.view) : "",
            s.integrator.integrator == render::Integrator::Path ? "path" : "direct",
            s.integrator.bounces,
            s.integrator.sequence == trace::SampleSequence::Sobol ? "sobol" : "independent",
            s.denoise};
}

// The foveation method for the current window size: a point set per size, built on first use
// and cached on disk like the command line's (desktop screen, same pixels per degree); with an
// HMD, the point set of its eyes' display, shared by both eyes. With `background` (an open-ended
// run), a set is generated off the frame thread and the full-resolution reference is shown until
// it is ready, so a resize never stalls the window; a run of --frames N waits for it, so its
// frames do not depend on how fast the set was made.
class DemoMethods {
public:
    DemoMethods(render::Renderer& r, const std::string& cacheDir, bool displaySpace,
                render::EccentricityLayerSettings layers, const std::string& hmd, bool background,
                uint32_t foveaRays)
        : mChoice(r, cacheDir), mDisplaySpace(displaySpace), mLayerSettings(std::move(layers)),
          mDesktop(foveation::displayProfile(foveation::DisplayModel::Desktop)),
          mBackground(background), mFoveaRays(foveaRays) {
        if (!hmd.empty()) {
            mHmdDisplay = hmdProfile(hmd).pointSetProfile;
        }
    }
    render::FoveationMethod& forHmd(const LiveSettings& s) {
        // Layers: each eye's frustum is its field of view.
        if (s.method == MethodKind::Layers) return layers(std::nullopt);
        return forDisplay(s, *mHmdDisplay);
    }
    render::FoveationMethod& forSize(const LiveSettings& s, uint32_t w, uint32_t h) {
        // Layers: the window on the desktop screen (the method sizes them per window).
        if (s.method == MethodKind::Layers) return layers(mDesktop);
        return forDisplay(s, foveation::windowProfile(mDesktop, w, h));
    }
    [[nodiscard]] double lastBuildMs() const noexcept { return mBuildMs; }
    // The point-set method last handed out (for the overlay's counts), or null.
    [[nodiscard]] const render::PointSetMethod* current() const noexcept { return mCurrent; }

private:
    render::FoveationMethod& layers(std::optional<foveation::DisplayProfile> display) {
        render::EccentricityLayerSettings s = mLayerSettings;
        s.display = std::move(display);
        mCurrent = nullptr;
        return mChoice.layers(s);
    }
    render::FoveationMethod& forDisplay(const LiveSettings& s,
                                        const foveation::DisplayProfile& display) {
        if (s.method == MethodKind::Reference) {
            mCurrent = nullptr;
            return mChoice.reference({s.raysPerPoint, 0, s.integrator});
        }
        foveation::PointSetParams params;
        params.display = display;
        params.scale = s.scale;
        const auto built = [this, &params](render::PointSetMethod&, double ms) {
            mBuildMs = ms;
            log::info("point set for " + std::to_string(params.display.width) + "x" +
                      std::to_string(params.display.height) + " at scale " +
                      std::to_string(params.scale) + " ready in " +
                      std::to_string(static_cast<int>(mBuildMs)) + " ms");
        };
        render::PointSetMethod* const ready =
            mBackground ? mChoice.pointSetIfReady(params, built) : &mChoice.pointSet(params, built);
        if (!ready) {
            mCurrent = nullptr;
            return mChoice.reference({s.raysPerPoint, 0, s.integrator});
        }
        render::PointSetMethod& pointSet = *ready;
        // The interpolation and rays follow the settings every frame (nothing to rebuild
        // except the k-NN table, which the method builds when k changes).
        passes::InterpolateSettings interp;
        interp.method = s.view.value_or(s.interp);
        interp.k = s.k;
        pointSet.settings = {s.raysPerPoint, interp, mDisplaySpace};
        pointSet.settings.integrator = s.integrator;
        pointSet.settings.foveaRaysPerPoint = mFoveaRays;
        mCurrent = &pointSet;
        return pointSet;
    }

    MethodChoice mChoice;
    bool mDisplaySpace;
    render::EccentricityLayerSettings mLayerSettings;
    foveation::DisplayProfile mDesktop;
    std::optional<foveation::DisplayProfile> mHmdDisplay;
    bool mBackground;
    uint32_t mFoveaRays; // --fovea-rays
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
    if (parseIntegrator(o.integrator).integrator != render::Integrator::Direct &&
        o.method == "layers") {
        throw ArgumentError("--integrator " + o.integrator.integrator +
                            ": foveated and reference only (layers trace the direct integrator)");
    }
    (void)parseDenoise(o.integrator);
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

// --resize FRAME:WxH: resize the window after that many frames (tests).
struct ResizeAt {
    bool pending = false;
    uint32_t frame = 0;
    VkExtent2D size{};
};

ResizeAt parseResize(const std::string& text) {
    ResizeAt r;
    if (text.empty()) return r;
    const auto colon = text.find(':');
    const auto frame = parseWholeNumber(text.substr(0, colon));
    const auto size =
        colon == std::string::npos ? std::nullopt : parseSizeText(text.substr(colon + 1));
    if (!frame || !size || size->first < 16 || size->second < 16 || size->first > 8192 ||
        size->second > 8192) {
        throw ArgumentError("--resize: expected FRAME:WxH (16..8192), got '" + text + "'");
    }
    return {true, *frame, {size->first, size->second}};
}

// The window, its swapchain and overlay, the camera and the gaze of one demo run, and the frame
// loop's stages over them: begin (input, camera, swapchain image), gaze, views, targets and
// done (present, timings, log).
class DemoRun {
public:
    explicit DemoRun(const DemoOptions& o);
    nlohmann::json run();

private:
    FrameStart begin(const FrameTick& t);
    void handleKey(int key);
    std::optional<GazeReading> readGaze(const FrameTick& t);
    std::vector<render::View> views(const std::optional<GazeReading>& reading);
    std::vector<render::View> hmdViews(const std::optional<GazeReading>& reading, VkExtent2D ext);
    std::vector<render::OutputTarget*> targets(std::span<const render::View> views,
                                               const FrameTick& t);
    bool done(const FrameTick& t, const std::optional<GazeReading>& reading,
              std::span<const render::View> views, const render::FrameResult& result);
    void recordCompleted(const FrameTick& t, std::span<const render::View> views,
                         const render::FrameResult& result);
    nlohmann::json summary(uint32_t frames);
    void recreate(VkExtent2D size) {
        mSwapchain->recreate(size);
        if (mOverlay) mOverlay->swapchainRecreated(mSwapchain->imageCount());
    }
    [[nodiscard]] bool lastFrame(const FrameTick& t) const {
        return mOptions.frames != 0 && t.index + 1 == mOptions.frames;
    }

    struct FrameGaze {
        SteadyClock::time_point sampled;
        uint64_t sequence;
        double sourceMs;
        glm::vec2 pixel;
    };

    const DemoOptions& mOptions;
    ResizeAt mResize;
    std::optional<CameraArg> mCameraArg;
    std::optional<scene::CameraPath> mPath;
    std::optional<io::AtomicFile> mLogFile;
    std::ostream* mLog = nullptr;
    std::optional<Window> mWindow;
    std::optional<CalibrationSession> mCalibration;
    std::unique_ptr<GazeInput> mGaze;
    std::optional<render::Renderer> mRenderer;
    std::optional<vk::Swapchain> mSwapchain;
    std::optional<render::SwapchainTarget> mTarget;
    LiveSettings mSettings;
    std::optional<DemoMethods> mMethods;
    std::optional<DemoOverlay> mOverlay;
    DemoStats mStats;
    DemoDefaults mDefaults;
    std::optional<OffScreenGazeWarning> mOffScreen;
    std::optional<render::StereoRig> mRig;
    std::optional<FlyCamera> mFly;
    std::optional<std::vector<scene::CameraKey>> mRecording;
    SteadyClock::time_point mLast;
    // Animation: scene time advances with the frames' times while not paused (Space).
    bool mAnimationPaused = false;
    double mSceneSeconds = 0.0, mLastTickMs = 0.0;
    SteadyClock::time_point mFrameStart;
    std::vector<double> mFrameTimes, mLatencies;
    std::map<uint64_t, FrameGaze> mInFlight; // the gaze each frame in flight used
    std::optional<glm::vec2> mGazePx;
    std::optional<GazeReading> mLastReading;
    std::optional<glm::vec2> mCalibrationTarget;
    std::optional<vk::Swapchain::Image> mImage;
    VkExtent2D mExtent{};
    int mScreenshotsTaken = 0;
};

DemoRun::DemoRun(const DemoOptions& o)
    : mOptions(o), mResize(parseResize(o.resize)), mCameraArg(parseCamera(o.camera)) {
    if (!o.cameraPath.empty()) mPath = scene::CameraPath::load(o.cameraPath);
    if (!o.log.empty()) {
        mLogFile.emplace(o.log); // a missing folder fails now, not after the run
        mLog = &mLogFile->stream();
        *mLog << "frame,t_ms,frame_ms,gpu_ms,gaze_x,gaze_y,gaze_sequence,gaze_t_ms,latency_ms\n";
    }
    // The gaze source first: a bad one fails before a window opens. The mouse reads the window
    // once it exists.
    GazeInputContext gazeContext;
    gazeContext.calibration = o.calibration;
    gazeContext.cursor = [this] { return mWindow ? mWindow->cursor() : glm::vec2(0.0f); };
    if (o.calibrate) {
        mCalibration.emplace(o.gaze, o.calibration);
        mGaze = openGazeInput("fixed:0,0", gazeContext); // the fovea follows the target instead
    } else {
        mGaze = openGazeInput(o.gaze, gazeContext);
    }
    mWindow.emplace("gazetrace", o.width, o.height);

    render::RendererOptions ro;
    ro.scene = o.scene;
    ro.validate = o.validate;
    ro.framesInFlight = o.framesInFlight;
    ro.deviceOverride = deviceRequest();
    ro.sceneLoad = gltfLoadOptions();
    ro.animation = o.animation;
    ro.display.instanceExtensions = mWindow->requiredInstanceExtensions();
    ro.display.deviceExtensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
    ro.display.createSurface = [this](VkInstance i) { return mWindow->createSurface(i); };
    mRenderer.emplace(ro);
    vk::Context& ctx = mRenderer->context();
    mSwapchain.emplace(ctx, mWindow->framebufferSize(), parsePresentMode(o.present));
    mTarget.emplace(ctx);
    DemoSettings words{o.method,
                       o.interp,
                       o.k,
                       o.method == "foveated" ? o.raysPerPoint : o.spp,
                       o.scale,
                       o.taa,
                       o.view,
                       o.integrator.integrator,
                       o.integrator.bounces,
                       o.integrator.sequence,
                       o.integrator.denoise == "on"};
    mDefaults = demoDefaults(ctx.properties().deviceType);
    applyDemoDefaults(words, mDefaults, o.given);
    log::info("demo defaults: " + mDefaults.label + " (options given on the command line win)");
    mSettings = liveSettingsOf(words);
    mMethods.emplace(*mRenderer, o.cacheDir, o.displaySpace && !o.hmd.empty() && o.distortion,
                     layerSettings(o.slope, o.layers, o.spp), o.hmd, o.frames == 0,
                     o.integrator.foveaRays);
    if (o.overlay || mCalibration) {
        mOverlay.emplace(*mWindow, ctx, mSwapchain->format(), mSwapchain->imageCount());
        if (mCalibration) mOverlay->toggle(); // the targets only: the panel would hide some
    }
    mStats.gazeSource = mGaze->describe();
    mStats.device = ctx.deviceName();
    mStats.defaults = mDefaults.label;
    mOffScreen.emplace(mGaze->describe());
    if (!o.hmd.empty()) mRig.emplace(hmdProfile(o.hmd), o.distortion);

    const scene::Scene& sc = mRenderer->scene();
    const float sceneSize = glm::length(sc.boundsMax() - sc.boundsMin());
    scene::Camera start = sc.camera;
    if (mCameraArg) {
        start = mCameraArg->camera(sc.camera.yfov);
    } else if (sc.cameraFramed) {
        // No camera in the file: inside an enclosed scene, start inside rather than outside.
        if (const auto inside = scene::insideStartView(sc, mRenderer->bvh())) start = *inside;
    }
    mFly.emplace(start, std::max(0.25f * sceneSize, 0.1f));
}

void DemoRun::handleKey(int key) {
    if (key == GLFW_KEY_ESCAPE) mWindow->requestClose();
    if (key == GLFW_KEY_T) mSettings.taa = !mSettings.taa;
    if (key == GLFW_KEY_TAB && mOverlay) mOverlay->toggle();
    if (key == GLFW_KEY_M) mSettings.method = nextOf(kMethodWords, mSettings.method);
    if (key == GLFW_KEY_I) mSettings.interp = nextOf(kInterpWords, mSettings.interp);
    if (key == GLFW_KEY_V) {
        // No view, then each debug view, then none again.
        mSettings.view = !mSettings.view ? std::optional(kViewWords[0].first)
                         : *mSettings.view == kViewWords.back().first
                             ? std::nullopt
                             : std::optional(nextOf(kViewWords, *mSettings.view));
    }
    if (key == GLFW_KEY_LEFT_BRACKET && mSettings.raysPerPoint > 1) --mSettings.raysPerPoint;
    if (key == GLFW_KEY_RIGHT_BRACKET && mSettings.raysPerPoint < 64) ++mSettings.raysPerPoint;
    if (key == GLFW_KEY_P) mTarget->requestScreenshot();
    if (key == GLFW_KEY_SPACE) mAnimationPaused = !mAnimationPaused;
    if (key == GLFW_KEY_R) {
        if (mRecording) {
            const std::string file = "camera_path.csv";
            scene::CameraPath::fromKeys(std::move(*mRecording)).save(file);
            log::info("recorded camera path written to " + file);
            mRecording.reset();
        } else {
            mRecording.emplace();
            log::info("recording the camera path (R again to stop)");
        }
    }
}

FrameStart DemoRun::begin(const FrameTick& t) {
    // SIGINT or SIGTERM close the demo as its window's close button does: after the frame
    // shown, with the log and the summary written.
    if (mWindow->shouldClose() || stopRequested()) return FrameStart::Stop;
    if (mResize.pending && t.index == mResize.frame) {
        mWindow->setSize(mResize.size.width, mResize.size.height);
        mResize.pending = false;
    }
    mWindow->poll();
    const VkExtent2D fb = mWindow->framebufferSize();
    if (fb.width == 0 || fb.height == 0) {
        mWindow->waitEvents(); // minimised: nothing to draw
        return FrameStart::Skip;
    }
    if (mWindow->takeResized() || fb.width != mSwapchain->extent().width ||
        fb.height != mSwapchain->extent().height) {
        recreate(fb);
    }
    for (const int key : mWindow->takePressedKeys())
        handleKey(key);
    mFrameStart = SteadyClock::now();
    const double dtS = std::min(msBetween(mLast, mFrameStart) * 1e-3, 0.25);
    mLast = mFrameStart;
    // Calibration: the target of this moment, from the desktop screen into the window (which
    // stands for the whole screen during a calibration: run it full screen).
    mCalibrationTarget.reset();
    if (mCalibration) {
        const auto target = mCalibration->target(t.timeMs);
        if (!target) return FrameStart::Stop; // every target shown
        const eyetrack::DisplayGeometry& d = mCalibration->display();
        const VkExtent2D fbNow = mWindow->framebufferSize();
        mCalibrationTarget =
            *target * glm::vec2(static_cast<float>(fbNow.width) / static_cast<float>(d.widthPx),
                                static_cast<float>(fbNow.height) / static_cast<float>(d.heightPx));
    }
    mFly->update(*mWindow, dtS);
    if (mPath) mFly->set(mPath->at(mPath->startMs() + t.timeMs, mFly->camera().yfov));
    if (mRecording) {
        const scene::Camera& c = mFly->camera();
        mRecording->push_back({t.timeMs, c.position, c.position + glm::normalize(c.forward)});
    }
    mImage = mSwapchain->acquire();
    if (!mImage) {
        recreate(mWindow->framebufferSize());
        return FrameStart::Skip;
    }
    return FrameStart::Render;
}

std::optional<GazeReading> DemoRun::readGaze(const FrameTick& t) {
    std::optional<GazeReading> reading = mGaze->read(t.timeMs);
    if (reading) {
        mLastReading = reading;
        mGazePx = windowPixelOf(*reading, glm::vec2(mWindow->position()));
    }
    return reading;
}

std::vector<render::View> DemoRun::hmdViews(const std::optional<GazeReading>& reading,
                                            VkExtent2D ext) {
    // Each eye in its half of the window; the gaze is a pixel of the left eye's image (the
    // mouse over either half counts as that point of the left eye).
    const display::HmdProfile& p = mRig->profile();
    glm::vec2 g = mGazePx.value_or(
        display::lensCentre(display::eyeTangents(p, 0)) *
        glm::vec2(static_cast<float>(p.eyeWidth), static_cast<float>(p.eyeHeight)));
    if (mOptions.gaze == "mouse") {
        const float half = 0.5f * static_cast<float>(ext.width);
        const float x = std::fmod(g.x, half);
        g = glm::vec2(x / half * static_cast<float>(p.eyeWidth),
                      g.y / static_cast<float>(ext.height) * static_cast<float>(p.eyeHeight));
    }
    render::StereoGaze sg;
    sg.direction = mRig->directionOfLeftPixel(g);
    if (mLastReading && mLastReading->anglesDeg) {
        sg.direction = render::directionOfAngles(*mLastReading->anglesDeg);
    }
    for (int e = 0; e < 2 && mLastReading; ++e) {
        if (mLastReading->eyeAnglesDeg[e]) {
            sg.eyeDirection[e] = render::directionOfAngles(*mLastReading->eyeAnglesDeg[e]);
        }
    }
    if (mOptions.vergenceM > 0.0) sg.vergenceM = static_cast<float>(mOptions.vergenceM);
    sg.saccade = reading && reading->saccade;
    render::PostSettings post;
    post.taa = mSettings.taa && !mSettings.view;
    if (mSettings.denoise) post.denoise = passes::DenoiseSettings{};
    const auto eyes = mRig->views(mFly->camera(), sg, mMethods->forHmd(mSettings), post,
                                  mRenderer->scene().exposure);
    const uint32_t half = ext.width / 2;
    mTarget->place("left", {{0, 0}, {half, ext.height}});
    mTarget->place("right", {{static_cast<int32_t>(half), 0}, {ext.width - half, ext.height}});
    return {eyes.begin(), eyes.end()};
}

std::vector<render::View> DemoRun::views(const std::optional<GazeReading>& reading) {
    const VkExtent2D ext = mSwapchain->extent();
    mExtent = ext; // the frame's size, though presenting it may recreate the swapchain
    if (mRig) return hmdViews(reading, ext);
    render::View view;
    view.camera = mFly->camera();
    view.width = ext.width;
    view.height = ext.height;
    view.exposure = mRenderer->scene().exposure;
    view.method = &mMethods->forSize(mSettings, ext.width, ext.height);
    view.post.taa = mSettings.taa && !mSettings.view;
    if (mSettings.denoise && mSettings.method != MethodKind::Layers) {
        view.post.denoise = passes::DenoiseSettings{};
    }
    if (reading) view.saccade = reading->saccade;
    if (mGazePx && !mCalibrationTarget) mOffScreen->check(*mGazePx, ext.width, ext.height);
    view.gaze =
        clampToImage(mCalibrationTarget ? *mCalibrationTarget
                                        : mGazePx.value_or(0.5f * glm::vec2(ext.width, ext.height)),
                     ext.width, ext.height);
    return {view};
}

std::vector<render::OutputTarget*> DemoRun::targets(std::span<const render::View> views,
                                                    const FrameTick& t) {
    mTarget->setImage(*mImage, mSwapchain->format(), mExtent);
    if (mOverlay) {
        const std::size_t recent = std::min<std::size_t>(30, mFrameTimes.size());
        mStats.frameMs =
            mFrameTimes.empty()
                ? 0.0
                : median(std::vector<double>(
                      mFrameTimes.end() - static_cast<std::ptrdiff_t>(recent), mFrameTimes.end()));
        mStats.latencyMs = mLatencies.empty() ? 0.0 : mLatencies.back();
        mStats.gaze = views[0].gaze;
        mStats.pointsSampled =
            mMethods->current() ? mMethods->current()->pointsSampled(views[0].gaze) : 0;
        // The overlay shows and edits the settings as words; they are read back only when it
        // changed one.
        DemoSettings words = wordsOf(mSettings);
        if (mOverlay->build(words, mStats, mCalibrationTarget)) mSettings = liveSettingsOf(words);
        mTarget->setOverlay(
            [this](rg::RenderGraph& g, rg::TextureId img) { return mOverlay->add(g, img); });
    }
    if (lastFrame(t) && !mOptions.screenshot.empty()) mTarget->requestScreenshot();
    return std::vector<render::OutputTarget*>(views.size(), &*mTarget);
}

// Frames the GPU finished: their GPU time and the latency from their gaze sample to the moment
// the frame was known finished (the driver offers no present timing here).
void DemoRun::recordCompleted(const FrameTick& t, std::span<const render::View> views,
                              const render::FrameResult& result) {
    std::vector<rg::CompletedFrame> done = mRenderer->takeCompleted();
    if (result.timings) done.push_back({result.number, *result.timings});
    const auto finishedAt = SteadyClock::now();
    for (const rg::CompletedFrame& c : done) {
        if (mOverlay) mOverlay->addTimings(c.timings);
        double latency = -1.0;
        FrameGaze used{{}, 0, 0.0, views[0].gaze};
        if (const auto it = mInFlight.find(c.number); it != mInFlight.end()) {
            used = it->second;
            latency = msBetween(used.sampled, finishedAt);
            mLatencies.push_back(latency);
            mInFlight.erase(it);
        }
        if (mLog) {
            *mLog << c.number << "," << t.timeMs << ","
                  << (mFrameTimes.empty() ? 0.0 : mFrameTimes.back()) << "," << c.timings.gpuMs
                  << "," << used.pixel.x << "," << used.pixel.y << "," << used.sequence << ","
                  << used.sourceMs << "," << latency << "\n";
        }
    }
}

bool DemoRun::done(const FrameTick& t, const std::optional<GazeReading>& reading,
                   std::span<const render::View> views, const render::FrameResult& result) {
    mStats.rays = 0;
    for (const auto& v : result.views)
        mStats.rays += v.rays;
    if (reading) {
        mInFlight[result.number] = {reading->sampled, reading->sequence, reading->sourceMs,
                                    views[0].gaze};
    }
    if (!mSwapchain->present(*mImage)) recreate(mWindow->framebufferSize());
    recordCompleted(t, views, result);
    mFrameTimes.push_back(msBetween(mFrameStart, SteadyClock::now()));
    const uint32_t frame = t.index + 1;
    if (frame % 10 == 0) {
        const double fps = 1000.0 / std::max(median(mFrameTimes), 1e-3);
        char title[160];
        std::snprintf(title, sizeof(title), "gazetrace - %.1f fps - %s - gaze %s", fps,
                      views[0].method->name().data(), mGaze->describe().c_str());
        glfwSetWindowTitle(mWindow->handle(), title);
    }
    if (mTarget->screenshot() && !lastFrame(t) && mOptions.screenshot.empty()) {
        const std::string file =
            "gazetrace_screenshot_" + std::to_string(++mScreenshotsTaken) + ".png";
        image::writePngAtomic(file, mExtent.width, mExtent.height, *mTarget->screenshot());
        log::info("screenshot written to " + file);
    }
    return true;
}

nlohmann::json DemoRun::run() {
    FrameStages<std::optional<GazeReading>> stages;
    stages.begin = [this](const FrameTick& t) { return begin(t); };
    stages.gaze = [this](const FrameTick& t) { return readGaze(t); };
    stages.views = [this](const FrameTick&, const std::optional<GazeReading>& r) {
        return views(r);
    };
    stages.targets = [this](const FrameTick& t, std::span<const render::View> v) {
        return targets(v, t);
    };
    stages.done = [this](const FrameTick& t, const std::optional<GazeReading>& r,
                         std::span<const render::View> v,
                         const render::FrameResult& result) { return done(t, r, v, result); };
    stages.onStop = OnStopRequest::BeginStageEnds;
    mSceneSeconds = mOptions.time;
    stages.sceneTime = [this](const FrameTick& t) {
        if (!mAnimationPaused) mSceneSeconds += (t.timeMs - mLastTickMs) * 1e-3;
        mLastTickMs = t.timeMs;
        return mSceneSeconds;
    };
    const FrameClock clock(mOptions.frameMs);
    mLast = clock.start();
    const uint32_t frames = runFrameLoop(*mRenderer, clock, mOptions.frames, stages);
    return summary(frames);
}

nlohmann::json DemoRun::summary(uint32_t frames) {
    mRenderer->waitIdle();
    if (!mOptions.screenshot.empty()) {
        if (!mTarget->screenshot()) {
            throw Error("--screenshot: the window closed before the last frame was shown");
        }
        image::writePngAtomic(mOptions.screenshot, mTarget->extent().width,
                              mTarget->extent().height, *mTarget->screenshot());
    }
    vk::Context& ctx = mRenderer->context();
    if (ctx.validationErrors() > 0) {
        throw Error(std::to_string(ctx.validationErrors()) + " Vulkan validation error(s)");
    }
    if (mLogFile) mLogFile->commit();
    nlohmann::json calibrationSummary;
    if (mCalibration) calibrationSummary = mCalibration->finish();
    // Steady state: leave out the first frames (pipelines warming, point set building).
    const std::vector<double> steady =
        mFrameTimes.size() > 4 ? std::vector<double>(mFrameTimes.begin() + 2, mFrameTimes.end())
                               : mFrameTimes;
    const double frameMedian = median(steady);
    return {{"device", ctx.deviceName()},
            {"present_mode", vk::toString(mSwapchain->presentMode())},
            {"window", {mSwapchain->extent().width, mSwapchain->extent().height}},
            {"method", mOptions.method},
            {"defaults", mDefaults.label},
            {"hmd", mOptions.hmd},
            {"gaze_source", mCalibration ? mOptions.gaze : mGaze->describe()},
            {"frames", frames},
            {"frames_in_flight", mRenderer->framesInFlight()},
            {"frame_ms_median", frameMedian},
            {"fps", frameMedian > 0.0 ? 1000.0 / frameMedian : 0.0},
            {"latency_ms_median", median(mLatencies)},
            {"point_set_build_ms", mMethods->lastBuildMs()},
            {"screenshot", mOptions.screenshot},
            {"calibration", calibrationSummary}};
}

} // namespace

nlohmann::json runDemo(const DemoOptions& o) {
    checkOptions(o);
    DemoRun session(o);
    return session.run();
}

} // namespace gt::app
