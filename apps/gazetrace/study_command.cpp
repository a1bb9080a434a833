#include "study_command.hpp"

#include <algorithm>
#include <map>
#include <memory>
#include <regex>
#include <system_error>
#include <utility>

#include "commands/shared_options.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "design.hpp"
#include "frame_loop.hpp"
#include "gaze_input.hpp"
#include "gaze_mapping.hpp"
#include "gaze_view.hpp"
#include "journal.hpp"
#include "option_parsing.hpp"
#include "output_target.hpp"
#include "renderer.hpp"
#include "scene/camera_path.hpp"
#include "session.hpp"
#include "study_run.hpp"
#include "study_xr.hpp"
#include "view_args.hpp"
#include "vk/context.hpp"

namespace gt::app {

namespace {

// The experimenter's code for a participant: nothing personal fits in it.
void checkParticipant(const std::string& code) {
    if (code.empty()) {
        throw ArgumentError("--participant: give the participant's code");
    }
    static const std::regex kCode("[A-Za-z0-9_-]{1,32}");
    if (!std::regex_match(code, kCode)) {
        throw ArgumentError("--participant: '" + code +
                            "' is not a code (1 to 32 letters, digits, - and _)");
    }
}

// An existing journal is continued only when asked to, and --resume needs one.
void checkJournal(const std::filesystem::path& journal, bool resume) {
    std::error_code ec;
    const bool exists = std::filesystem::symlink_status(journal, ec).type() !=
                        std::filesystem::file_type::not_found;
    if (exists && !resume) {
        throw ArgumentError("journal " + journal.string() +
                            " exists: give --resume to continue it, or another --journal");
    }
    if (!exists && resume) {
        throw ArgumentError("--resume: no journal " + journal.string() + " to continue");
    }
}

// The view from --hmd (or the design's headset), else --width/--height (or the design's size).
StudyView studyView(const StudyOptions& o, const study::StudyDesign& d) {
    StudyView v;
    const std::string hmd = o.hmd.empty() ? d.hmd : o.hmd;
    if (!hmd.empty()) {
        if (o.width != 0 || o.height != 0) {
            throw ArgumentError("--width/--height: the headset " + hmd + " sets the view's size");
        }
        v.hmd = hmdProfile(hmd);
        v.width = v.hmd->eyeWidth;
        v.height = v.hmd->eyeHeight;
        v.stimuli = {v.hmd->pointSetProfile, std::nullopt, false};
        v.refreshHz = v.hmd->refreshHz;
    } else {
        for (const uint32_t size : {o.width, o.height}) {
            if (size != 0 && (size < 16 || size > 16384)) {
                throw ArgumentError("--width/--height: 16 to 16384 pixels (0: the design's)");
            }
        }
        v.width = o.width != 0 ? o.width : d.width;
        v.height = o.height != 0 ? o.height : d.height;
        v.stimuli = desktopStimulusDisplay(v.width, v.height);
    }
    if (d.timing.refreshHz > 0.0) {
        v.refreshHz = d.timing.refreshHz;
    }
    v.fixationPx = {static_cast<float>(d.fixationX * (v.width - 1)),
                    static_cast<float>(d.fixationY * (v.height - 1))};
    return v;
}

// Each scene's camera and camera path, read before anything is written.
void checkScenes(const study::StudyDesign& d) {
    for (std::size_t i = 0; i < d.scenes.size(); ++i) {
        const study::SceneChoice& sc = d.scenes[i];
        const std::string field = d.name + ": scenes[" + std::to_string(i) + "]";
        try {
            (void)parseCamera(sc.camera);
        } catch (const ArgumentError& e) {
            throw ArgumentError(field + ".camera: " + e.what());
        }
        if (!sc.cameraPath.empty()) {
            (void)scene::CameraPath::load(sc.cameraPath);
        }
    }
}

// Every option checked, every input read, before anything is written.
StudySetup studySetup(const StudyOptions& o) {
    checkParticipant(o.participant);
    StudySetup s;
    s.participant = o.participant;
    s.observer = parseObserver(o.observer);
    if (o.display == "headless" && !s.observer) {
        throw ArgumentError("--display headless: give --observer (level:T or flip:T) to answer");
    }
    if (o.display == "window" && s.observer && s.observer->basis == ObserverBasis::Flip) {
        throw ArgumentError("--observer flip: headless only (it reads every frame back)");
    }
    s.design = study::loadDesign(o.design);
    if (s.observer) {
        StudyObserver::check(*s.observer, s.design);
    }
    checkScenes(s.design);
    s.journal = o.journal.empty()
                    ? std::filesystem::path(s.design.name + "_" + o.participant + ".jsonl")
                    : std::filesystem::path(o.journal);
    checkJournal(s.journal, o.resume);
    checkRunFiles({{"--journal", s.journal}},
                  {{"--design", o.design}, {"--calibration", o.calibration}, {"--gaze", o.gaze}});
    s.view = studyView(o, s.design);
    s.frameMs = o.frameMs > 0.0 ? o.frameMs : 1000.0 / s.view.refreshHz;
    s.maxTrials = o.maxTrials;
    // Headless, the default gaze (the mouse) has no window: the gaze rests on the fixation point.
    s.gaze = o.display == "headless" && o.gaze == "mouse" ? "" : o.gaze;
    s.calibration = o.calibration;
    s.cacheDir = o.cacheDir;
    s.validate = o.validate;
    return s;
}

// A journal this run created or extended is put back as it was (removed, or cut back to its
// earlier length) when the run fails before it journaled a trial: a failed start writes nothing.
class JournalGuard {
public:
    explicit JournalGuard(std::filesystem::path path) : mPath(std::move(path)) {
        std::error_code ec;
        mExisted = std::filesystem::is_regular_file(mPath, ec);
        if (mExisted) {
            mSize = std::filesystem::file_size(mPath, ec);
        }
    }
    ~JournalGuard() {
        if (mKept) {
            return;
        }
        std::error_code ec;
        if (mExisted) {
            std::filesystem::resize_file(mPath, mSize, ec);
        } else {
            std::filesystem::remove(mPath, ec);
        }
    }
    JournalGuard(const JournalGuard&) = delete;
    JournalGuard& operator=(const JournalGuard&) = delete;
    void keep() noexcept { mKept = true; }

private:
    std::filesystem::path mPath;
    bool mExisted = false;
    std::uintmax_t mSize = 0;
    bool mKept = false;
};

// One scene of a headless run: its renderer, its stimuli's methods, its targets.
struct HeadlessScene {
    HeadlessScene(const StudySetup& s, const std::string& scene)
        : renderer(render::RendererOptions{.scene = scene,
                                           .validate = s.validate,
                                           .framesInFlight = 1,
                                           .deviceOverride = deviceRequest(),
                                           .sceneLoad = gltfLoadOptions()}),
          stimuli(renderer, {scene}, s.cacheDir), readback(renderer.context()) {}
    render::Renderer renderer;
    StudyStimuli stimuli;
    render::ReadbackTarget readback;
    render::DiscardTarget discard;
};

// A headless run: each Interval frame rendered offscreen at the fixed frame step, the answers
// from the simulated observer.
class HeadlessRun {
public:
    HeadlessRun(const StudySetup& s, study::StudySession& session);
    nlohmann::json run();

private:
    HeadlessScene& scene(const std::string& spec) { return *mScenes.at(spec); }
    std::optional<glm::vec2> gazePx(double ms);
    const quality::RgbaImage* render(const study::FrameShow& show, glm::vec2 gaze, double ms);
    quality::RgbaImage shot(const study::Stimulus& stimulus);
    [[nodiscard]] bool flip() const { return mSetup.observer->basis == ObserverBasis::Flip; }

    const StudySetup& mSetup;
    study::StudySession& mSession;
    std::map<std::string, std::unique_ptr<HeadlessScene>> mScenes;
    std::unique_ptr<GazeInput> mGaze;
    std::optional<StudyObserver> mObserver;
    uint64_t mRendered = 0;
    // The segment of frames showing one stimulus (an interval): it began at mSegmentMs.
    std::optional<std::tuple<study::Phase, uint32_t, study::Stimulus>> mSegment;
    double mSegmentMs = 0.0;
    quality::RgbaImage mPicture;
    std::map<std::string, quality::RgbaImage> mShots;
};

HeadlessRun::HeadlessRun(const StudySetup& s, study::StudySession& session)
    : mSetup(s), mSession(session) {
    if (!s.gaze.empty()) {
        GazeInputContext context;
        context.calibration = s.calibration;
        mGaze = openGazeInput(s.gaze, context);
    }
    const std::vector<study::Stimulus> all = session.allStimuli();
    for (const std::string& spec : scenesOf(all)) {
        auto& sc = mScenes[spec];
        sc = std::make_unique<HeadlessScene>(s, spec);
        sc->stimuli.prepare(all, s.view.stimuli, s.view.width, s.view.height);
    }
    mObserver.emplace(*s.observer, s.design, s.view,
                      [this](const study::Stimulus& st) { return shot(st); });
}

std::optional<glm::vec2> HeadlessRun::gazePx(double ms) {
    if (!mGaze) {
        return mSetup.view.fixationPx;
    }
    const std::optional<GazeReading> r = mGaze->read(ms);
    if (!r) {
        return std::nullopt;
    }
    if (r->anglesDeg && mSetup.view.hmd) {
        const glm::vec2 px = render::pixelOfDirection(render::directionOfAngles(*r->anglesDeg),
                                                      display::eyeTangents(*mSetup.view.hmd, 0),
                                                      mSetup.view.width, mSetup.view.height);
        return clampToImage(px, mSetup.view.width, mSetup.view.height);
    }
    const glm::vec2 origin = render::centredWindowOrigin(render::ScreenGeometry{},
                                                         {mSetup.view.width, mSetup.view.height});
    return clampToImage(windowPixelOf(*r, origin), mSetup.view.width, mSetup.view.height);
}

quality::RgbaImage HeadlessRun::shot(const study::Stimulus& stimulus) {
    const std::string key = describe(stimulus.render) + " | " + stimulus.scene.scene;
    if (const auto it = mShots.find(key); it != mShots.end()) {
        return it->second;
    }
    HeadlessScene& sc = scene(stimulus.scene.scene);
    sc.renderer.resetHistory();
    const render::View v =
        stimulusView(sc.stimuli, mSetup.view, stimulus, mSetup.view.fixationPx, 0.0);
    (void)renderOneFrame(sc.renderer, v, sc.readback);
    ++mRendered;
    sc.renderer.resetHistory();
    mSegment.reset(); // the next frame starts its interval afresh
    return mShots[key] = {v.width, v.height, sc.readback.takePixels()};
}

const quality::RgbaImage* HeadlessRun::render(const study::FrameShow& show, glm::vec2 gaze,
                                              double ms) {
    if (!show.stimulus) {
        mSegment.reset();
        return nullptr;
    }
    HeadlessScene& sc = scene(show.stimulus->scene.scene);
    auto segment = std::make_tuple(show.phase, show.trial, *show.stimulus);
    if (mSegment != segment) {
        // A new interval: its own history, its camera path from the start.
        mSegment = std::move(segment);
        mSegmentMs = ms;
        sc.renderer.resetHistory();
    }
    const render::View v =
        stimulusView(sc.stimuli, mSetup.view, *show.stimulus, gaze, ms - mSegmentMs);
    render::OutputTarget& target =
        flip() ? static_cast<render::OutputTarget&>(sc.readback) : sc.discard;
    (void)renderOneFrame(sc.renderer, v, target);
    ++mRendered;
    if (!flip()) {
        return nullptr;
    }
    mPicture = {v.width, v.height, sc.readback.takePixels()};
    return &mPicture;
}

nlohmann::json HeadlessRun::run() {
    const uint32_t atStart = mSession.trialsDone();
    // A session that neither ends a trial nor asks anything for this long is stuck.
    const uint64_t maxIdleFrames = 100000;
    uint64_t frame = 0, idle = 0;
    uint32_t lastDone = atStart;
    std::optional<study::Response> answer;
    while (!mSession.finished() &&
           (mSetup.maxTrials == 0 || mSession.trialsDone() - atStart < mSetup.maxTrials)) {
        throwIfStopRequested();
        const double ms = static_cast<double>(frame) * mSetup.frameMs;
        const std::optional<glm::vec2> gaze = gazePx(ms);
        study::FrameInput input;
        input.timeMs = ms;
        if (gaze) {
            input.gaze = anglesOfViewPixel(mSetup.view, *gaze);
        }
        input.response = std::exchange(answer, std::nullopt);
        const study::FrameShow show = mSession.frame(input);
        const quality::RgbaImage* picture = render(show, gaze.value_or(mSetup.view.fixationPx), ms);
        mObserver->frame(show, picture);
        answer = mObserver->answer(mSession, show);
        ++frame;
        idle = mSession.trialsDone() != lastDone ? 0 : idle + 1;
        lastDone = mSession.trialsDone();
        if (idle > maxIdleFrames) {
            throw Error("study: no trial ended in " + std::to_string(maxIdleFrames) +
                        " frames (a gaze source that never holds the fixation region?)");
        }
    }
    nlohmann::json j = sessionSummary(mSetup, mSession, atStart);
    j["display"] = "headless";
    j["frames"] = frame;
    j["frames_rendered"] = mRendered;
    j["frame_ms"] = mSetup.frameMs;
    nlohmann::json stimuli = nlohmann::json::object();
    for (const auto& [spec, sc] : mScenes) {
        stimuli[spec] = sc->stimuli.summary();
        if (sc->renderer.context().validationErrors() > 0) {
            throw Error(std::to_string(sc->renderer.context().validationErrors()) +
                        " Vulkan validation error(s)");
        }
    }
    j["stimuli"] = stimuli;
    if (const auto metric = mObserver->lastMetric()) {
        j["flip_last"] = *metric;
    }
    return j;
}

} // namespace

nlohmann::json sessionSummary(const StudySetup& setup, const study::StudySession& session,
                              uint32_t trialsAtStart) {
    uint32_t trials = 0, flagged = 0;
    for (const nlohmann::json& line : study::readJournal(setup.journal)) {
        if (!line.is_object() || line.value("type", "") != "trial") {
            continue;
        }
        ++trials;
        if (!line["flags"].empty()) {
            ++flagged;
        }
    }
    return {{"design", setup.design.name},
            {"participant", setup.participant},
            {"journal", setup.journal.string()},
            {"seed", session.seed()},
            {"trials_done", session.trialsDone() - trialsAtStart},
            {"trials_journaled", trials},
            {"trials_planned", session.trialsPlanned()},
            {"flagged", flagged},
            {"finished", session.finished()},
            {"view", {setup.view.width, setup.view.height}},
            {"hmd", setup.view.hmd ? setup.view.hmd->name : ""}};
}

nlohmann::json runStudy(const StudyOptions& options) {
    const StudySetup setup = studySetup(options);
    JournalGuard guard(setup.journal);
    study::Journal journal(setup.journal);
    study::SessionSettings settings;
    settings.participant = setup.participant;
    settings.refreshHz = setup.view.refreshHz;
    settings.fixationDeg = anglesOfViewPixel(setup.view, setup.view.fixationPx);
    // OpenXR: the headset is opened first, so the session counts frames at its refresh.
    std::optional<StudyXrDisplay> xr;
    if (options.display == "xr") {
        xr.emplace(setup);
        settings.refreshHz = xr->refreshHz();
    }
    study::StudySession session(setup.design, settings, journal);
    const uint32_t atStart = session.trialsDone();
    try {
        nlohmann::json summary;
        if (options.display == "window") {
            summary = runStudyWindow(setup, session);
        } else if (xr) {
            summary = xr->run(session);
        } else {
            HeadlessRun run(setup, session);
            summary = run.run();
        }
        guard.keep();
        return summary;
    } catch (...) {
        // Trials answered stay journaled; a run that failed before its first one leaves none.
        if (session.trialsDone() != atStart) {
            guard.keep();
        }
        throw;
    }
}

} // namespace gt::app
