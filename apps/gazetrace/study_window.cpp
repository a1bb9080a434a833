// `gazetrace study --display window`: the session in the desktop window, answered from the
// keyboard (or a simulated observer). The frame loop is demo's (frame_loop.hpp): the window's
// input, the gaze source, the views, the swapchain; the prompt, the fixation mark and the plain
// frames of the phases that show no stimulus are drawn by Dear ImGui over the image.
//
// Keys: 1 or Left = first, 2 or Right = second, S = same, Y = yes, N = no, Up = up, Down = down,
// R = reference, Enter = accept, Space = continue; Esc or closing the window ends the run (every
// trial answered is in the journal already).
#include <algorithm>
#include <array>
#include <chrono>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include "core/error.hpp"
#include "frame_loop.hpp"
#include "gaze_input.hpp"
#include "gaze_view.hpp"
#include "imgui_layer.hpp"
#include "option_parsing.hpp"
#include "renderer.hpp"
#include "stop_request.hpp"
#include "study_run.hpp"
#include "swapchain_target.hpp"
#include "vk/context.hpp"
#include "vk/swapchain.hpp"
#include "window.hpp"

namespace gt::app {

namespace {

using study::Response;

struct KeyResponse {
    int key;
    Response response;
    const char* label; // as the prompt shows it
};

constexpr std::array<KeyResponse, 12> kKeys{{{GLFW_KEY_1, Response::First, "1"},
                                             {GLFW_KEY_LEFT, Response::First, "Left"},
                                             {GLFW_KEY_2, Response::Second, "2"},
                                             {GLFW_KEY_RIGHT, Response::Second, "Right"},
                                             {GLFW_KEY_S, Response::Same, "S"},
                                             {GLFW_KEY_Y, Response::Yes, "Y"},
                                             {GLFW_KEY_N, Response::No, "N"},
                                             {GLFW_KEY_UP, Response::Up, "Up"},
                                             {GLFW_KEY_DOWN, Response::Down, "Down"},
                                             {GLFW_KEY_R, Response::Reference, "R"},
                                             {GLFW_KEY_ENTER, Response::Accept, "Enter"},
                                             {GLFW_KEY_SPACE, Response::Continue, "Space"}}};

// The answer a key gives, when the phase takes it.
std::optional<Response> responseOfKey(int key, const std::vector<Response>& accepted) {
    for (const KeyResponse& k : kKeys) {
        if (k.key == key &&
            std::find(accepted.begin(), accepted.end(), k.response) != accepted.end()) {
            return k.response;
        }
    }
    return std::nullopt;
}

// "1/Left: first   2/Right: second" for the answers the phase takes.
std::string keyLegend(const std::vector<Response>& accepted) {
    std::string legend;
    for (const Response r : accepted) {
        std::string keys;
        for (const KeyResponse& k : kKeys) {
            if (k.response == r) {
                keys += (keys.empty() ? "" : "/") + std::string(k.label);
            }
        }
        legend += (legend.empty() ? "" : "   ") + keys + ": " + study::responseName(r);
    }
    return legend;
}

double msBetween(SteadyClock::time_point a, SteadyClock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

class StudyWindowRun {
public:
    StudyWindowRun(const StudySetup& s, study::StudySession& session);
    nlohmann::json run();

private:
    FrameStart begin(const FrameTick& t);
    std::optional<GazeReading> readGaze(const FrameTick& t);
    std::vector<render::View> views(const FrameTick& t, const std::optional<GazeReading>& r);
    std::vector<render::OutputTarget*> targets(std::span<const render::View> views);
    bool done(const std::optional<GazeReading>& r, const render::FrameResult& result);
    void drawUi();
    [[nodiscard]] StudyView viewNow() const;
    [[nodiscard]] bool enough() const {
        return mSession.finished() ||
               (mSetup.maxTrials != 0 && mSession.trialsDone() - mAtStart >= mSetup.maxTrials);
    }
    void recreate(VkExtent2D size) {
        mSwapchain->recreate(size);
        mUi->swapchainRecreated(mSwapchain->imageCount());
    }

    const StudySetup& mSetup;
    study::StudySession& mSession;
    uint32_t mAtStart = 0;
    std::optional<Window> mWindow;
    std::unique_ptr<GazeInput> mGaze;
    std::optional<render::Renderer> mRenderer;
    std::optional<vk::Swapchain> mSwapchain;
    std::optional<render::SwapchainTarget> mTarget;
    std::optional<ImGuiLayer> mUi;
    std::optional<StudyStimuli> mStimuli;
    std::optional<StudyObserver> mObserver;
    std::optional<vk::Swapchain::Image> mImage;
    study::FrameShow mShow;
    std::optional<Response> mAnswer;
    std::optional<glm::vec2> mGazePx;
    std::optional<std::tuple<study::Phase, uint32_t, study::Stimulus>> mSegment;
    double mSegmentMs = 0.0;
    std::map<uint64_t, SteadyClock::time_point> mInFlight; // each frame's gaze sample time
    double mLatencyMs = 0.0;
    uint64_t mRendered = 0;
    bool mClosed = false; // Esc, the window's close button or a stop request
};

StudyWindowRun::StudyWindowRun(const StudySetup& s, study::StudySession& session)
    : mSetup(s), mSession(session), mAtStart(session.trialsDone()) {
    const std::vector<study::Stimulus> all = session.allStimuli();
    const std::vector<std::string> scenes = scenesOf(all);
    // The gaze source first: a bad one fails before a window opens.
    GazeInputContext gazeContext;
    gazeContext.calibration = s.calibration;
    gazeContext.cursor = [this] { return mWindow ? mWindow->cursor() : glm::vec2(0.0f); };
    mGaze = openGazeInput(s.gaze, gazeContext);
    mWindow.emplace("gazetrace study", s.view.width, s.view.height);
    render::RendererOptions ro;
    ro.scene = scenes.front();
    ro.validate = s.validate;
    ro.framesInFlight = 0;
    ro.deviceOverride = deviceRequest();
    ro.sceneLoad = gltfLoadOptions();
    ro.display.instanceExtensions = mWindow->requiredInstanceExtensions();
    ro.display.deviceExtensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
    ro.display.createSurface = [this](VkInstance i) { return mWindow->createSurface(i); };
    mRenderer.emplace(ro);
    // Every further scene on the same device: a trial's stimulus names the one it shows.
    for (std::size_t i = 1; i < scenes.size(); ++i) {
        (void)mRenderer->addScene(scenes[i], ro.sceneLoad);
    }
    vk::Context& ctx = mRenderer->context();
    mSwapchain.emplace(ctx, mWindow->framebufferSize(), parsePresentMode("fifo"));
    mTarget.emplace(ctx);
    mUi.emplace(*mWindow, ctx, mSwapchain->format(), mSwapchain->imageCount());
    mStimuli.emplace(*mRenderer, scenes, s.cacheDir);
    const StudyView v = viewNow();
    mStimuli->prepare(all, v.stimuli, v.width, v.height);
    if (s.observer) {
        mObserver.emplace(*s.observer, s.design, s.view, StudyObserver::Shot{});
    }
}

// The view at the window's present size (a headset's eye keeps its own: the window scales it).
StudyView StudyWindowRun::viewNow() const {
    StudyView v = mSetup.view;
    if (v.hmd) {
        return v;
    }
    const VkExtent2D e = mSwapchain->extent();
    v.width = e.width;
    v.height = e.height;
    v.stimuli = desktopStimulusDisplay(e.width, e.height);
    v.fixationPx = {static_cast<float>(mSetup.design.fixationX * (e.width - 1)),
                    static_cast<float>(mSetup.design.fixationY * (e.height - 1))};
    return v;
}

FrameStart StudyWindowRun::begin(const FrameTick&) {
    // SIGINT or SIGTERM end the run as Esc does: after the frame shown, the journal complete.
    if (mWindow->shouldClose() || stopRequested()) {
        mClosed = true;
        return FrameStart::Stop;
    }
    if (enough()) {
        return FrameStart::Stop;
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
    const std::vector<Response> accepted = mSession.accepted();
    for (const int key : mWindow->takePressedKeys()) {
        if (key == GLFW_KEY_ESCAPE) {
            mWindow->requestClose();
        }
        if (const auto r = responseOfKey(key, accepted); r && !mObserver) {
            mAnswer = r;
        }
    }
    mImage = mSwapchain->acquire();
    if (!mImage) {
        recreate(mWindow->framebufferSize());
        return FrameStart::Skip;
    }
    return FrameStart::Render;
}

std::optional<GazeReading> StudyWindowRun::readGaze(const FrameTick& t) {
    std::optional<GazeReading> reading = mGaze->read(t.timeMs);
    mGazePx.reset();
    if (reading) {
        const StudyView v = viewNow();
        mGazePx = clampToImage(windowPixelOf(*reading, glm::vec2(mWindow->position())), v.width,
                               v.height);
    }
    return reading;
}

std::vector<render::View> StudyWindowRun::views(const FrameTick& t,
                                                const std::optional<GazeReading>&) {
    const StudyView v = viewNow();
    study::FrameInput input;
    input.timeMs = t.timeMs;
    if (mGazePx) {
        input.gaze = anglesOfViewPixel(v, *mGazePx);
    }
    input.latencyMs = mLatencyMs;
    input.response = std::exchange(mAnswer, std::nullopt);
    mShow = mSession.frame(input);
    if (mObserver) {
        mObserver->frame(mShow, nullptr);
        mAnswer = mObserver->answer(mSession, mShow);
    }
    const glm::vec2 gaze = mGazePx.value_or(v.fixationPx);
    if (!mShow.stimulus) {
        // Nothing of the scene: a tiny frame the drawn background covers.
        mSegment.reset();
        study::Stimulus blank;
        blank.render.method = study::Method::Reference;
        blank.render.taa = false;
        blank.scene.scene = mStimuli->scene();
        render::View view = mStimuli->view(blank, v.stimuli, 8, 8, glm::vec2(4.0f), 0.0);
        view.name = "blank";
        mTarget->place("blank", {{0, 0}, {8, 8}});
        return {view};
    }
    auto segment = std::make_tuple(mShow.phase, mShow.trial, *mShow.stimulus);
    if (mSegment != segment) {
        mSegment = std::move(segment);
        mSegmentMs = t.timeMs;
        mRenderer->resetHistory();
    }
    ++mRendered;
    return {stimulusView(*mStimuli, v, *mShow.stimulus, gaze, t.timeMs - mSegmentMs)};
}

// The phase's background (black between intervals, mid-grey otherwise), the fixation mark and
// the prompt with its keys.
void StudyWindowRun::drawUi() {
    mUi->newFrame();
    const ImVec2 size = ImGui::GetIO().DisplaySize;
    // Text that reads alike from a small window to a full screen.
    ImGui::GetIO().FontGlobalScale = std::max(1.0f, size.y / 540.0f);
    ImGui::NewFrame();
    if (!mShow.stimulus) {
        const ImU32 colour = mShow.phase == study::Phase::Blank ? IM_COL32(0, 0, 0, 255)
                                                                : IM_COL32(128, 128, 128, 255);
        ImGui::GetBackgroundDrawList()->AddRectFilled(ImVec2(0, 0), size, colour);
    }
    ImDrawList* d = ImGui::GetForegroundDrawList();
    if (mShow.showFixationMark) {
        const ImVec2 c(static_cast<float>(mSetup.design.fixationX) * size.x,
                       static_cast<float>(mSetup.design.fixationY) * size.y);
        const float arm = 0.015f * std::min(size.x, size.y) + 4.0f;
        d->AddLine(ImVec2(c.x - arm, c.y), ImVec2(c.x + arm, c.y), IM_COL32(255, 255, 255, 255),
                   3.0f);
        d->AddLine(ImVec2(c.x, c.y - arm), ImVec2(c.x, c.y + arm), IM_COL32(255, 255, 255, 255),
                   3.0f);
    }
    const std::vector<Response> accepted = mSession.accepted();
    std::string text = mShow.prompt;
    if (!accepted.empty()) {
        text += (text.empty() ? "" : "\n") + keyLegend(accepted);
    }
    if (!text.empty()) {
        // Wrapped to the window, centred near its bottom, on a dark band.
        const float wrap = 0.9f * size.x;
        const ImVec2 t = ImGui::CalcTextSize(text.c_str(), nullptr, false, wrap);
        const ImVec2 at(0.5f * (size.x - t.x), size.y - t.y - 0.06f * size.y);
        d->AddRectFilled(ImVec2(at.x - 8, at.y - 6), ImVec2(at.x + t.x + 8, at.y + t.y + 6),
                         IM_COL32(0, 0, 0, 200));
        d->AddText(ImGui::GetFont(), ImGui::GetFontSize(), at, IM_COL32(255, 255, 255, 255),
                   text.c_str(), nullptr, wrap);
    }
    ImGui::Render();
}

std::vector<render::OutputTarget*> StudyWindowRun::targets(std::span<const render::View> views) {
    mTarget->setImage(*mImage, mSwapchain->format(), mSwapchain->extent());
    drawUi();
    mTarget->setOverlay([this](rg::RenderGraph& g, rg::TextureId img) { return mUi->add(g, img); });
    return std::vector<render::OutputTarget*>(views.size(), &*mTarget);
}

// Presents, and measures each finished frame's latency from its gaze sample (as demo does).
bool StudyWindowRun::done(const std::optional<GazeReading>& r, const render::FrameResult& result) {
    if (r) {
        mInFlight[result.number] = r->sampled;
    }
    if (!mSwapchain->present(*mImage)) {
        recreate(mWindow->framebufferSize());
    }
    std::vector<rg::CompletedFrame> finished = mRenderer->takeCompleted();
    if (result.timings) {
        finished.push_back({result.number, *result.timings});
    }
    const auto now = SteadyClock::now();
    for (const rg::CompletedFrame& c : finished) {
        if (const auto it = mInFlight.find(c.number); it != mInFlight.end()) {
            mLatencyMs = msBetween(it->second, now);
            mInFlight.erase(it);
        }
    }
    return true;
}

nlohmann::json StudyWindowRun::run() {
    FrameStages<std::optional<GazeReading>> stages;
    stages.begin = [this](const FrameTick& t) { return begin(t); };
    stages.gaze = [this](const FrameTick& t) { return readGaze(t); };
    stages.views = [this](const FrameTick& t, const std::optional<GazeReading>& r) {
        return views(t, r);
    };
    stages.targets = [this](const FrameTick&, std::span<const render::View> v) {
        return targets(v);
    };
    stages.done = [this](const FrameTick&, const std::optional<GazeReading>& r,
                         std::span<const render::View>,
                         const render::FrameResult& result) { return done(r, result); };
    stages.onStop = OnStopRequest::BeginStageEnds;
    const uint32_t frames = runFrameLoop(*mRenderer, FrameClock(), 0, stages);
    mRenderer->waitIdle();
    vk::Context& ctx = mRenderer->context();
    if (ctx.validationErrors() > 0) {
        throw Error(std::to_string(ctx.validationErrors()) + " Vulkan validation error(s)");
    }
    nlohmann::json j = sessionSummary(mSetup, mSession, mAtStart);
    j["display"] = "window";
    j["frames"] = frames;
    j["frames_rendered"] = mRendered;
    j["ended_early"] = mClosed && !mSession.finished();
    j["gaze_source"] = mGaze->describe();
    j["stimuli"] = mStimuli->summaryByScene();
    return j;
}

} // namespace

nlohmann::json runStudyWindow(const StudySetup& setup, study::StudySession& session) {
    StudyWindowRun run(setup, session);
    return run.run();
}

} // namespace gt::app
