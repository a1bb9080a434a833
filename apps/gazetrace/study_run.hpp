#pragma once
// What the displays of `gazetrace study` share (study_command.cpp runs it headless,
// study_window.cpp in the desktop window): the view the stimuli are seen in, gaze pixels as the
// session's angles, and the simulated observer that answers instead of a participant.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "display/hmd_profile.hpp"
#include "quality/image.hpp"
#include "session.hpp"
#include "stereo_rig.hpp"
#include "study_stimuli.hpp"

namespace gt::app {

// The view a run shows its stimuli in: a window on the desktop screen, or a headset's left eye
// (without its lens: the OpenXR display shows both eyes through the runtime).
struct StudyView {
    uint32_t width = 0, height = 0;
    StimulusDisplay stimuli;
    std::optional<display::HmdProfile> hmd;
    double refreshHz = 60.0;
    glm::vec2 fixationPx{}; // the design's fixation point in the view's pixels
};

// The session's gaze angles (degrees from the view's centre; +x right, +y up) of a pixel of the
// view: on the desktop screen as if the viewer faces the view's centre (ScreenGeometry), through
// the eye's frustum for a headset.
[[nodiscard]] study::GazeAngles anglesOfViewPixel(const StudyView& view, glm::vec2 px);

// The frame's view of `stimulus` with the gaze at `gazePx`, `ms` into its interval.
[[nodiscard]] render::View stimulusView(StudyStimuli& stimuli, const StudyView& view,
                                        const study::Stimulus& stimulus, glm::vec2 gazePx,
                                        double ms);

// --observer level:T[,SLOPE[,LAPSE]] | flip:T[,SLOPE[,LAPSE]]: a logistic psychometric function
// of the trial's level, or of the FLIP the condition's frames show against its comparison's.
enum class ObserverBasis { Level, Flip };
inline constexpr double kLevelObserverSlope = 5.0; // per unit of the level
inline constexpr double kFlipObserverSlope = 50.0; // per unit of FLIP (0..1)

struct ObserverSpec {
    ObserverBasis basis = ObserverBasis::Level;
    double threshold = 1.0;
    double slope = kLevelObserverSlope;
    double lapse = 0.0;
};

// Empty text: no observer. Throws ArgumentError naming --observer.
[[nodiscard]] std::optional<ObserverSpec> parseObserver(const std::string& text);

// The metric a flip observer answers from: the largest of eval's flip_ecc over the eccentricity
// bands around `gazePx` (FLIP per band as the eye resolves it there, the thesis's eq. 2) of
// `test` against `reference`, seen on `display`.
[[nodiscard]] double flipMetric(const quality::RgbaImage& reference, const quality::RgbaImage& test,
                                const foveation::DisplayProfile& display, glm::vec2 gazePx);

// A simulated observer's answers: fed every frame's FrameShow (and, for a flip observer, the
// frame's picture), it answers what the current phase accepts: Continue where that is all,
// the trial's question in the response phase (a fresh draw per trial from the run's seed and
// the trial's index, so a resumed run answers as an uninterrupted one would).
class StudyObserver {
public:
    // Renders a stimulus on its own (a flip observer's comparison for a one-interval trial).
    using Shot = std::function<quality::RgbaImage(const study::Stimulus&)>;
    StudyObserver(ObserverSpec spec, const study::StudyDesign& design, const StudyView& view,
                  Shot shot);
    // Throws ArgumentError when the observer cannot answer the design's procedure.
    static void check(const ObserverSpec& spec, const study::StudyDesign& design);

    void frame(const study::FrameShow& show, const quality::RgbaImage* picture);
    [[nodiscard]] std::optional<study::Response> answer(const study::StudySession& session,
                                                        const study::FrameShow& show);
    // The metric of the last trial a flip observer answered.
    [[nodiscard]] std::optional<double> lastMetric() const noexcept { return mLastMetric; }

private:
    struct Interval {
        study::Stimulus stimulus;
        quality::RgbaImage picture;
    };
    [[nodiscard]] bool positive(const study::StudySession::TrialInfo& trial, uint64_t seed);
    [[nodiscard]] double metricOf(const study::StudySession::TrialInfo& trial);
    [[nodiscard]] const study::Condition* condition(const std::string& name) const;

    ObserverSpec mSpec;
    const study::StudyDesign& mDesign;
    StudyView mView;
    Shot mShot;
    std::optional<uint32_t> mTrial;
    study::Phase mPhase = study::Phase::Instructions;
    std::vector<Interval> mIntervals;
    std::optional<uint32_t> mAnswered; // the trial last answered, and its answers so far
    uint64_t mAnswers = 0;
    std::optional<double> mLastMetric;
};

// A run's options, checked, as typed values (study_command.cpp: studySetup).
struct StudySetup {
    study::StudyDesign design;
    std::string participant;
    std::filesystem::path journal;
    StudyView view;
    std::optional<ObserverSpec> observer;
    double frameMs = 0.0;   // headless: the frame clock's step
    uint32_t maxTrials = 0; // trials this run ends after (0: the whole plan)
    std::string gaze;       // a gaze source as demo --gaze takes it; empty: the fixation point
    std::string calibration;
    std::string cacheDir;
    bool validate = false;
};

// What every display's summary says: the journal, the seed, the trials done, planned and
// flagged (read back from the journal).
[[nodiscard]] nlohmann::json
sessionSummary(const StudySetup& setup, const study::StudySession& session, uint32_t trialsAtStart);

// The run in the desktop window (study_window.cpp).
[[nodiscard]] nlohmann::json runStudyWindow(const StudySetup& setup, study::StudySession& session);

} // namespace gt::app
