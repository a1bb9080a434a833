#include "study_xr.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>
#include <thread>
#include <tuple>

#include "action_sets.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "external_image_target.hpp"
#include "eye_gaze.hpp"
#include "gaze_input.hpp"
#include "option_parsing.hpp"
#include "renderer.hpp"
#include "response_actions.hpp"
#include "stop_request.hpp"
#include "study_stimuli.hpp"
#include "study_xr_buttons.hpp"
#include "xr_error.hpp"
#include "xr_eye_fill.hpp"
#include "xr_gaze.hpp"
#include "xr_runtime.hpp"
#include "xr_session.hpp"
#include "xr_views.hpp"

namespace gt::app {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

// How long the session may take to start, and to end once asked to.
constexpr double kStartTimeoutMs = 30000.0;
constexpr double kExitTimeoutMs = 5000.0;
// The fixation cross: arms of 0.4 degrees, 0.08 degrees thick, at least a few pixels.
constexpr double kCrossArmDeg = 0.4;
constexpr double kCrossThickDeg = 0.08;

// The scenes a run shows, each once: the first the renderer's own, the others added to it.
std::vector<std::string> scenesOf(const study::StudyDesign& design) {
    std::vector<std::string> scenes;
    for (const study::SceneChoice& c : design.scenes) {
        if (std::find(scenes.begin(), scenes.end(), c.scene) == scenes.end()) {
            scenes.push_back(c.scene);
        }
    }
    return scenes;
}

// What the frames of a run showed, and the answers given.
struct XrStudyCounts {
    uint32_t frames = 0, notShown = 0;
    uint32_t stimulusFrames = 0, fixationFrames = 0, blankFrames = 0;
    uint32_t runtimeGazeFrames = 0, gazeLostFrames = 0;
    uint32_t buttonAnswers = 0, observerAnswers = 0;
    uint32_t buttonsBound = 0; // the most buttons bound to a controller at once
};

} // namespace

class StudyXrDisplay::Run {
public:
    explicit Run(const StudySetup& setup);
    double refreshHz();
    nlohmann::json run(study::StudySession& session);

private:
    bool step();
    bool waitForRunning();
    void prepare(const xr::FrameInfo& frame);
    void runFrame(const xr::FrameInfo& frame, const std::vector<uint32_t>& pressed);
    std::optional<HeadGaze> gaze(const xr::FrameInfo& frame, double ms);
    std::optional<study::Response> answer(const std::vector<uint32_t>& pressed);
    void draw(const xr::FrameInfo& frame, const study::FrameShow& show, const HeadGaze& gaze,
              double ms);
    void drawStimulus(const xr::FrameInfo& frame, const study::Stimulus& stimulus,
                      const HeadGaze& gaze, double msIntoInterval);
    void drawFill(const xr::FrameInfo& frame, bool cross);
    void askExit();
    [[nodiscard]] bool trialsLeft() const;
    nlohmann::json summary();

    const StudySetup& mSetup;
    study::StudySession* mSession = nullptr;
    uint32_t mAtStart = 0;
    const std::vector<std::string> mScenes;
    std::unique_ptr<GazeInput> mOwnGaze;
    std::optional<xr::Runtime> mRuntime;
    std::optional<render::Renderer> mRenderer;
    std::optional<xr::Session> mXr;
    std::optional<xr::ActionSets> mActions; // before the inputs whose actions it holds
    std::optional<xr::EyeGaze> mEyeGaze;
    std::optional<xr::ResponseActions> mButtons;
    std::string mEyeGazeStatus = "not offered by the runtime";
    std::optional<StudyStimuli> mStimuli;
    std::optional<EyeFill> mFill;
    std::array<std::optional<render::ExternalImageTarget>, 2> mTargets;
    std::optional<StudyObserver> mObserver;
    // The design's fixation point as the session measures it, and in the head frame.
    study::GazeAngles mFixationDeg{};
    glm::vec3 mFixationDir{0.0f, 0.0f, -1.0f};
    StimulusDisplay mDisplay;
    bool mPrepared = false;
    std::optional<XrTime> mT0; // the first trial frame's predicted display time
    XrDuration mDisplayPeriod = 0;
    std::optional<study::Response> mPending; // the observer's answer, given on the next frame
    double mLatencyMs = 0.0;                 // the last frame's gaze-to-submitted time
    std::optional<std::tuple<study::Phase, uint32_t, study::Stimulus>> mSegment;
    double mSegmentMs = 0.0;
    std::string mPrompt;
    XrStudyCounts mCounts;
    Clock::time_point mStarted;
    std::optional<Clock::time_point> mExitAsked;
    bool mExited = false;
};

StudyXrDisplay::Run::Run(const StudySetup& setup)
    : mSetup(setup), mScenes(scenesOf(setup.design)), mStarted(Clock::now()) {
    if (setup.observer && setup.observer->basis == ObserverBasis::Flip) {
        throw ArgumentError("--observer flip: headless only (it reads every frame back)");
    }
    // The desktop's default (the mouse) has no window here: without the runtime's eye gaze the
    // gaze rests on the fixation point, as in a headless run.
    if (!setup.gaze.empty() && setup.gaze != "mouse") {
        GazeInputContext context;
        context.calibration = setup.calibration;
        mOwnGaze = openGazeInput(setup.gaze, context);
    }
    mFixationDeg = anglesOfViewPixel(setup.view, setup.view.fixationPx);
    mFixationDir = xrDirectionOfAngles({mFixationDeg.xDeg, mFixationDeg.yDeg});

    xr::RuntimeOptions rto;
    if (const char* manifest = std::getenv("XR_RUNTIME_JSON")) {
        rto.runtimeManifest = manifest;
    }
    mRuntime.emplace(rto);
    log::info("study: xr runtime " + mRuntime->runtimeName() + ", system " +
              mRuntime->systemName());
    render::RendererOptions ro;
    ro.scene = mScenes.front();
    ro.validate = setup.validate;
    ro.framesInFlight = 1; // each frame's images are released right after its submit
    ro.deviceOverride = deviceRequest();
    ro.sceneLoad = gltfLoadOptions();
    ro.display = mRuntime->vulkanHooks();
    mRenderer.emplace(ro);
    // Every further scene on the runtime's device: a trial's stimulus names the one it shows.
    for (std::size_t i = 1; i < mScenes.size(); ++i) {
        (void)mRenderer->addScene(mScenes[i], ro.sceneLoad);
    }
    xr::SessionOptions so;
    so.maxWidth = setup.view.width;
    so.maxHeight = setup.view.height;
    mXr.emplace(*mRuntime, mRenderer->context(), so);

    // Eye gaze and the answer buttons: their action sets attached together, once.
    mActions.emplace(*mXr);
    if (mRuntime->eyeGazeSupported()) {
        mEyeGaze.emplace(*mActions);
        mEyeGazeStatus = "offered";
    } else if (mRuntime->eyeGazeOffered()) {
        mEyeGazeStatus = "offered, but the system reports no eye tracker";
    }
    mButtons.emplace(*mActions);
    mActions->attach();

    mStimuli.emplace(*mRenderer, mScenes, setup.cacheDir);
    mFill.emplace(mRenderer->context());
    for (auto& t : mTargets) {
        t.emplace(mRenderer->context());
    }
    if (setup.observer) {
        mObserver.emplace(*setup.observer, setup.design, setup.view,
                          [](const study::Stimulus&) -> quality::RgbaImage {
                              throw Error("study: the xr display reads no frame back");
                          });
    }
}

bool StudyXrDisplay::Run::trialsLeft() const {
    return !mSession->finished() &&
           (mSetup.maxTrials == 0 || mSession->trialsDone() - mAtStart < mSetup.maxTrials);
}

void StudyXrDisplay::Run::askExit() {
    if (mExitAsked) {
        return;
    }
    mXr->requestExit();
    mExitAsked = Clock::now();
}

// Before the session runs (and after it was asked to end): false when the loop is to end.
bool StudyXrDisplay::Run::waitForRunning() {
    const auto now = Clock::now();
    if (mExitAsked && msSince(*mExitAsked, now) > kExitTimeoutMs) {
        log::warn("study: the runtime did not end the session within 5 s of the request");
        return false;
    }
    if (!mXr->running()) {
        if (!mExitAsked && msSince(mStarted, now) > kStartTimeoutMs) {
            throw Error("the OpenXR session did not start within 30 s (last state " +
                        xr::stateName(mXr->lifecycle().state()) +
                        "): is the headset on and the runtime's compositor running?");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return true;
}

// One frame of the runtime's; false once the loop is to end.
bool StudyXrDisplay::Run::step() {
    if (!mXr->pollEvents()) {
        mExited = true;
        return false;
    }
    if (stopRequested() || !trialsLeft()) {
        // SIGINT, SIGTERM or the last trial: the runtime is asked to end the session, and the
        // trials answered so far are journaled already.
        if (!mXr->running() && !mExitAsked) {
            return false;
        }
        askExit();
    }
    if (!waitForRunning()) {
        return false;
    }
    if (!mXr->running()) {
        return true;
    }
    const xr::FrameInfo frame = mXr->beginFrame();
    mActions->sync(); // the frame's one xrSyncActions: eye gaze and the buttons
    const std::vector<uint32_t> pressed = mButtons->pressed();
    mCounts.buttonsBound = std::max(mCounts.buttonsBound, mButtons->activeButtons());
    if (mExitAsked || !frame.shouldRender || !frame.posesValid) {
        mXr->endFrame(frame, false);
        ++mCounts.notShown;
        return true;
    }
    if (!mPrepared) {
        mXr->endFrame(frame, false); // nothing shown while the stimuli are built
        ++mCounts.notShown;
        prepare(frame);
        return true;
    }
    runFrame(frame, pressed);
    return true;
}

// Every stimulus built for the runtime's eye images (its size and field of view) before the
// first trial, so no trial waits for a point set.
void StudyXrDisplay::Run::prepare(const xr::FrameInfo& frame) {
    const VkExtent2D size = mXr->eyeExtent(0);
    mDisplay = {xr::eyeDisplay(frame.views[0].fov, size.width, size.height), std::nullopt, false};
    mStimuli->prepare(mSession->allStimuli(), mDisplay, size.width, size.height);
    mPrepared = true;
    log::info("study: xr eye images " + std::to_string(size.width) + "x" +
              std::to_string(size.height) + "; the first trial begins");
}

std::optional<HeadGaze> StudyXrDisplay::Run::gaze(const xr::FrameInfo& frame, double ms) {
    const std::optional<xr::EyeGazeSample> sample =
        mEyeGaze ? mEyeGaze->locate(frame.displayTime) : std::nullopt;
    if (sample) {
        ++mCounts.runtimeGazeFrames;
        return runtimeHeadGaze(*sample, 0.0, *mRuntime);
    }
    if (!mOwnGaze) {
        return fixation(glm::vec3(0.0f), mFixationDir, 0.0);
    }
    return ownHeadGaze(mOwnGaze.get(), ms, frame, mXr->eyeExtent(0), 0.0);
}

// A button press this frame, as the answer the current phase takes; else the observer's.
std::optional<study::Response> StudyXrDisplay::Run::answer(const std::vector<uint32_t>& pressed) {
    const std::vector<study::Response> accepted = mSession->accepted();
    for (const uint32_t b : pressed) {
        if (const auto r = responseOfButton(b, accepted)) {
            ++mCounts.buttonAnswers;
            mPending.reset();
            return r;
        }
    }
    if (mPending) {
        ++mCounts.observerAnswers;
    }
    return std::exchange(mPending, std::nullopt);
}

void StudyXrDisplay::Run::runFrame(const xr::FrameInfo& frame,
                                   const std::vector<uint32_t>& pressed) {
    const Clock::time_point begun = Clock::now();
    if (!mT0) {
        mT0 = frame.displayTime;
        mDisplayPeriod = frame.displayPeriod;
        const double hz = frame.displayPeriod > 0 ? 1e9 / double(frame.displayPeriod) : 0.0;
        const double design = mSetup.design.timing.refreshHz;
        if (hz > 0.0 && design > 0.0 && std::abs(hz - design) > 0.01 * design) {
            log::warn("study: the headset refreshes at " + std::to_string(hz) +
                      " Hz, the design counts frames at " + std::to_string(design) + " Hz");
        }
    }
    // The frame clock is the runtime's: when this frame is predicted to reach the eyes.
    const double ms = static_cast<double>(frame.displayTime - *mT0) / 1e6;
    const std::optional<HeadGaze> g = gaze(frame, ms);
    study::FrameInput in;
    in.timeMs = ms;
    if (g) {
        const glm::vec2 a = anglesOfHeadGaze(*g);
        in.gaze = study::GazeAngles{a.x, a.y};
    } else {
        ++mCounts.gazeLostFrames;
    }
    in.latencyMs = mLatencyMs;
    in.response = answer(pressed);
    const study::FrameShow show = mSession->frame(in);
    if (const std::string prompt = buttonPrompt(mSession->accepted());
        prompt != mPrompt && !prompt.empty()) {
        log::info("study: trial " + std::to_string(show.trial) + ": " + prompt);
    }
    mPrompt = buttonPrompt(mSession->accepted());
    draw(frame, show, g.value_or(fixation(glm::vec3(0.0f), mFixationDir, 0.0)), ms);
    mXr->endFrame(frame, true);
    mLatencyMs = msSince(g && g->sampled ? std::min(*g->sampled, begun) : begun, Clock::now());
    if (mObserver) {
        mObserver->frame(show, nullptr);
        mPending = mObserver->answer(*mSession, show);
    }
    ++mCounts.frames;
}

void StudyXrDisplay::Run::draw(const xr::FrameInfo& frame, const study::FrameShow& show,
                               const HeadGaze& gaze, double ms) {
    if (!show.stimulus) {
        mSegment.reset();
        drawFill(frame, show.showFixationMark);
        ++(show.showFixationMark ? mCounts.fixationFrames : mCounts.blankFrames);
        return;
    }
    auto segment = std::make_tuple(show.phase, show.trial, *show.stimulus);
    if (mSegment != segment) {
        // A new interval: its own history, its camera path from the start.
        mSegment = std::move(segment);
        mSegmentMs = ms;
        mRenderer->resetHistory();
    }
    drawStimulus(frame, *show.stimulus, gaze, ms - mSegmentMs);
    ++mCounts.stimulusFrames;
}

// Both eyes see the same stimulus, each through its own pose and field of view, the scene
// placed so the viewer stands at the stimulus's camera.
void StudyXrDisplay::Run::drawStimulus(const xr::FrameInfo& frame, const study::Stimulus& stimulus,
                                       const HeadGaze& gaze, double msIntoInterval) {
    const xr::ScenePlacement placement =
        xr::ScenePlacement::facing(mStimuli->camera(stimulus.scene, msIntoInterval), 1.0f);
    std::vector<render::View> views;
    std::vector<render::OutputTarget*> targets;
    for (uint32_t e = 0; e < 2; ++e) {
        const VkExtent2D size = mXr->eyeExtent(e);
        render::View v = eyeView(frame, e, gaze, placement, size);
        v.method = &mStimuli->method(stimulus, mDisplay, size.width, size.height);
        v.post = StudyStimuli::post(stimulus);
        v.exposure = mStimuli->exposure(stimulus);
        views.push_back(v);
        const xr::EyeImage img = mXr->acquire(e);
        mTargets[e]->setImage({img.image, img.format, img.extent, 0});
        targets.push_back(&*mTargets[e]);
    }
    (void)mRenderer->renderFrame(views, targets);
    mXr->release(0);
    mXr->release(1);
}

void StudyXrDisplay::Run::drawFill(const xr::FrameInfo& frame, bool cross) {
    for (uint32_t e = 0; e < 2; ++e) {
        const xr::EyeImage img = mXr->acquire(e);
        std::optional<FixationCross> mark;
        if (cross) {
            const XrView& head = frame.headViews[e];
            const double ppd =
                img.extent.width / glm::degrees(head.fov.angleRight - head.fov.angleLeft);
            mark = FixationCross{xr::gazePixel(mFixationDir, true, head.pose, head.fov,
                                               img.extent.width, img.extent.height),
                                 static_cast<uint32_t>(std::max(3.0, kCrossArmDeg * ppd)),
                                 static_cast<uint32_t>(std::max(2.0, kCrossThickDeg * ppd))};
        }
        mFill->fill({img.image, img.format, img.extent, 0}, mark);
        mXr->release(e);
    }
}

// Frames run (nothing shown) until the runtime paces one: its display period.
double StudyXrDisplay::Run::refreshHz() {
    while (mDisplayPeriod <= 0) {
        throwIfStopRequested();
        if (!mXr->pollEvents()) {
            throw Error("the OpenXR runtime ended the session before the study began");
        }
        if (!waitForRunning()) {
            throw Error("the OpenXR session did not start");
        }
        if (!mXr->running()) {
            continue;
        }
        const xr::FrameInfo frame = mXr->beginFrame();
        mActions->sync();
        (void)mButtons->pressed();
        mCounts.buttonsBound = std::max(mCounts.buttonsBound, mButtons->activeButtons());
        mXr->endFrame(frame, false);
        ++mCounts.notShown;
        mDisplayPeriod = frame.displayPeriod;
    }
    return 1e9 / static_cast<double>(mDisplayPeriod);
}

nlohmann::json StudyXrDisplay::Run::run(study::StudySession& session) {
    mSession = &session;
    mAtStart = session.trialsDone();
    while (step()) {
    }
    return summary();
}

nlohmann::json StudyXrDisplay::Run::summary() {
    mRenderer->waitIdle();
    vk::Context& ctx = mRenderer->context();
    nlohmann::json j = sessionSummary(mSetup, *mSession, mAtStart);
    const VkExtent2D eye = mXr->eyeExtent(0), recommended = mXr->recommendedExtent(0);
    const std::string ownGaze = mOwnGaze ? mOwnGaze->describe() : "the fixation point";
    nlohmann::json responses = {{"action_sets", mActions->setCount()},
                                {"profiles", mActions->suggestedProfiles()},
                                {"profiles_skipped", mActions->skippedProfiles()},
                                {"syncs", mActions->syncs()},
                                {"focused_syncs", mActions->focusedSyncs()},
                                {"buttons_bound", mCounts.buttonsBound},
                                {"button_presses", mButtons->presses()},
                                {"button_answers", mCounts.buttonAnswers},
                                {"observer_answers", mCounts.observerAnswers}};
    j.update(
        {{"display", "xr"},
         {"runtime", mRuntime->runtimeName()},
         {"system", mRuntime->systemName()},
         {"device", ctx.deviceName()},
         {"eye", {eye.width, eye.height}},
         {"eye_recommended", {recommended.width, recommended.height}},
         {"display_period_ms", static_cast<double>(mDisplayPeriod) / 1e6},
         {"frames", mCounts.frames},
         {"frames_not_shown", mCounts.notShown},
         {"frames_stimulus", mCounts.stimulusFrames},
         {"frames_fixation", mCounts.fixationFrames},
         {"frames_blank", mCounts.blankFrames},
         {"eye_gaze_extension", mEyeGazeStatus},
         {"gaze_source",
          mCounts.runtimeGazeFrames > 0 ? "XR_EXT_eye_gaze_interaction, else " + ownGaze : ownGaze},
         {"frames_with_runtime_gaze", mCounts.runtimeGazeFrames},
         {"frames_gaze_lost", mCounts.gazeLostFrames},
         {"responses", responses},
         {"stimuli", mStimuli->summaryByScene()},
         // A stop request or the runtime ended it before the plan or --max-trials did.
         {"ended_early", trialsLeft()}});
    // The action sets before the session they belong to.
    mEyeGaze.reset();
    mButtons.reset();
    mActions.reset();
    j["session_states"] = mXr->lifecycle().history();
    mXr.reset();
    j["session_ended_by_runtime"] = mExited;
    j["validation_errors"] = ctx.validationErrors();
    j["validation_errors_in_runtime_calls"] = ctx.runtimeValidationErrors();
    if (ctx.validationErrors() > 0) {
        throw Error(std::to_string(ctx.validationErrors()) +
                    " Vulkan validation error(s) in gazetrace's own calls");
    }
    if (!mSession->finished() && trialsLeft() && !stopRequested()) {
        log::warn("study: the OpenXR runtime ended the session before the run did; --resume "
                  "continues the journal");
    }
    return j;
}

StudyXrDisplay::StudyXrDisplay(const StudySetup& setup) : mRun(std::make_unique<Run>(setup)) {}
StudyXrDisplay::~StudyXrDisplay() = default;

double StudyXrDisplay::refreshHz() {
    return mRun->refreshHz();
}

nlohmann::json StudyXrDisplay::run(study::StudySession& session) {
    return mRun->run(session);
}

} // namespace gt::app
