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
#include <string>
#include <vector>

#include "design.hpp"
#include "journal.hpp"

namespace gt::study {

// What a participant can answer; which ones a trial takes depends on the procedure.
enum class Response { First, Second, Same, Yes, No, Up, Down, Reference, Accept, Continue };

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
};

enum class Phase { Instructions, Break, Fixation, Interval, Blank, Response, Done };

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
    // Any answer (a simulated observer, a test) replaces a key press; set by headless runs.
};

class StudySession {
public:
    // Starts a run, or resumes one from `journal`'s records (the plan from the journaled seed,
    // every answered trial replayed into the placements). Throws DesignError / JournalError.
    StudySession(StudyDesign design, SessionSettings settings, Journal& journal);
    ~StudySession();
    StudySession(const StudySession&) = delete;
    StudySession& operator=(const StudySession&) = delete;

    [[nodiscard]] FrameShow frame(const FrameInput& input);
    [[nodiscard]] bool finished() const;
    // Every stimulus the plan may show (each condition at every grid level, its comparison, each
    // scene), so the front end builds every level's point set before the first trial.
    [[nodiscard]] std::vector<Stimulus> allStimuli() const;
    // The responses the current phase accepts (for the prompt and the key map).
    [[nodiscard]] std::vector<Response> accepted() const;
    [[nodiscard]] uint64_t seed() const;
    [[nodiscard]] uint32_t trialsDone() const;
    [[nodiscard]] uint32_t trialsPlanned() const; // grows when trials are repeated

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
