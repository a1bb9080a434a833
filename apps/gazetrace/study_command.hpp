#pragma once
// `gazetrace study --design FILE`: a participant's run of a perception study in the demo window,
// in an OpenXR session, or headless with a simulated observer. The study library (study/) plans
// the trials and keeps the journal; this front end renders each frame's stimulus, reads the
// gaze and the answers (keys, controller buttons, the observer) and builds every level's point
// set before the first trial.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace gt::app {

struct StudyOptions {
    std::string design;      // the design file
    std::string participant; // the experimenter's code for the participant
    std::string journal;     // default: DESIGN-NAME_PARTICIPANT.jsonl in the current folder
    bool resume = false;     // continue an existing journal (else an existing one is refused)
    std::string display = "window"; // window | xr | headless
    std::string gaze = "mouse";     // a gaze source as demo --gaze takes it
    std::string calibration;
    // A simulated observer answers instead of the keys: "level:T[,SLOPE[,LAPSE]]" answers from
    // the stimulus level alone (a logistic psychometric function, threshold T), "flip:T[,SLOPE
    // [,LAPSE]]" from eval's perceptual metric of the rendered frames against the reference.
    std::string observer;
    std::string hmd;    // overrides the design's display
    uint32_t width = 0; // 0: the design's
    uint32_t height = 0;
    double frameMs = 0.0;   // headless: time per frame (0: the design's refresh period)
    uint32_t maxTrials = 0; // end after this many trials (0: the whole plan)
    std::string cacheDir;
    bool validate = false;
};

// Runs the session; returns its JSON summary (trials done, flagged, the journal's path).
// Throws gt::Error (or a study::DesignError, JournalError) on failure.
nlohmann::json runStudy(const StudyOptions& options);

} // namespace gt::app
