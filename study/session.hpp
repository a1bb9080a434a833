#pragma once
// A participant's run of a design, advanced one displayed frame at a time. The front end (the
// demo window, an OpenXR session, a headless run with a simulated observer) calls frame() once per
// frame with what it measured and the answer given since the last frame, and shows what frame()
// returns. The session owns the trial plan (the order, from the seed), the placements, the
// gaze-contingent rules and the timing checks, and writes every ended trial to the journal before
// the next one starts. Nothing here renders, reads a key or knows a window.
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "design.hpp"
#include "journal.hpp"

namespace gt::study {

// A run that cannot start: a participant code that is not one.
class SessionError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// What a participant can answer; which ones a trial takes depends on the procedure.
enum class Response { First, Second, Same, Yes, No, Up, Down, Reference, Accept, Continue };
// "first", "second", "same", "yes", "no", "up", "down", "reference", "accept", "continue": the
// journal's words, and what a front end's key or controller map may name.
[[nodiscard]] std::string responseName(Response response);
[[nodiscard]] std::optional<Response> responseNamed(std::string_view name);

// One frame's gaze, as visual angles from the view's centre (degrees; +x right, +y up), or empty
// when the tracker has none this frame.
struct GazeAngles {
    double xDeg = 0.0;
    double yDeg = 0.0;
};

struct FrameInput {
    double timeMs = 0.0; // when this frame begins (the frame clock)
    std::optional<GazeAngles> gaze;
    double latencyMs = 0.0; // the previous frame's gaze-to-finished latency, 0 when unknown
    std::optional<Response> response; // given since the previous frame
    // When it was given on the frame clock (a key event's time stamp); empty: this frame's time.
    std::optional<double> responseTimeMs;
};

enum class Phase { Instructions, Break, Fixation, Interval, Blank, Response, Done };

// The phases of a trial and the frame clock:
//  - a phase that begins on the frame at time t0 and lasts D ms shows on the frames with
//    t - t0 < D - half a refresh period, so at a steady refresh it holds round(D / period)
//    frames; the frame after it begins the next phase;
//  - Fixation (fixationMs; with a fixation radius, the gaze inside it for that long) ->
//    Interval -> Blank -> Interval ... -> Response; ForcedChoice and Pair show two intervals,
//    YesNo one, Ramp rampSteps; Slider goes from Fixation to Response, where the condition is
//    shown from its most foveated level, Up / Down move it one level towards less / more
//    foveation, and Reference shows the comparison for one interval (intervalMs) and goes back;
//  - a trial's practice and its slider start are at the most foveated level (the easiest to
//    tell); practice and catch trials never reach the placement;
//  - an answer ends the trial on the frame it arrives, which begins the next trial's Fixation
//    (or a Break, or Done); answers a phase does not accept are ignored;
//  - during an Interval, the gaze outside the fixation radius or an angular speed above
//    saccadeDegPerS between two consecutive frames (repeatOnSaccade) ends the trial at once:
//    a "repeat" line, and the same condition is planned again one to three trials later (at
//    once when nothing else is left); after maxRepeats repeats it is kept, flagged
//    "max_repeats". A response timeout repeats the trial the same way, without a limit (there
//    is no answer to keep). The slider's display has no gaze rules: the participant looks
//    around it;
//  - a frame that begins more than 1.5 refresh periods after the one before counts as a
//    dropped frame of the interval that frame was shown in; the latency a frame reports is the
//    previous frame's, and is counted there too.
// Every random choice of a trial (its condition, the interval order, a catch trial, the ramp's
// direction, a repeat's delay) is drawn from an engine seeded from (seed, trial index) alone, so
// replaying a journal's lines rebuilds the same plan. With constant stimuli the interval order
// (ForcedChoice, Pair) and the ramp's direction alternate over a level's presentations instead,
// from a coin per level, so two repeats show both (Guenter et al. 2012: "in both orders", "in
// both directions").

// What to show this frame.
struct FrameShow {
    Phase phase = Phase::Instructions;
    std::optional<Stimulus> stimulus; // Interval (and Slider's Response phase): render this
    std::string prompt;               // a line of text for the overlay ("1: first  2: second")
    uint32_t trial = 0;               // the trial's index in the plan
    bool practice = false;
    bool showFixationMark = false; // Fixation: a mark at the design's fixation point
};

struct SessionSettings {
    std::string participant; // an experimenter's code: [A-Za-z0-9_-]{1,32}, nothing personal
    double refreshHz = 60.0; // the display's, unless the design sets one
    // Where the design's fixation point lies as angles from the view's centre (the front end
    // knows the projection); the fixation radius is measured from it.
    GazeAngles fixationDeg{};
};

class StudySession {
public:
    // Starts a run, or resumes one from `journal`'s records (the plan from the journaled seed,
    // every answered trial replayed into the placements). Throws DesignError / JournalError.
    StudySession(StudyDesign design, SessionSettings settings, Journal& journal);
    ~StudySession();
    StudySession(const StudySession&) = delete;
    StudySession& operator=(const StudySession&) = delete;

    // Throws JournalError when a line cannot be written (a full disk): the journal then holds
    // every trial before it, and the run stops there.
    [[nodiscard]] FrameShow frame(const FrameInput& input);
    [[nodiscard]] bool finished() const;
    // Every stimulus the plan may show (each condition at every grid level, its comparison, each
    // scene), so the front end builds every level's point set before the first trial.
    [[nodiscard]] std::vector<Stimulus> allStimuli() const;
    // The responses the current phase accepts (for the prompt and the key map).
    [[nodiscard]] std::vector<Response> accepted() const;
    [[nodiscard]] uint64_t seed() const;
    [[nodiscard]] uint32_t trialsDone() const;
    // Trials so far (answered and repeated) plus the most the plan may still hold: adaptive
    // placements may end sooner. Grows when trials are repeated.
    [[nodiscard]] uint32_t trialsPlanned() const;
    // A condition's placement (its next level, estimate, reversals); null for a slider
    // condition or an unknown name.
    [[nodiscard]] const LevelPlacement* placement(std::string_view condition) const;

    // The trial in progress, for a simulated observer: the condition's level, whether the first
    // interval holds the condition (ForcedChoice, Pair), whether it is a catch trial, the ramp's
    // direction. Empty between trials.
    struct TrialInfo {
        std::string condition;
        double level = 0.0;
        bool conditionFirst = true;
        bool catchTrial = false;
        bool rampUp = true;
    };
    [[nodiscard]] std::optional<TrialInfo> currentTrial() const;

private:
    struct State;
    std::unique_ptr<State> mState;
};

} // namespace gt::study
