#pragma once
// A study design: a JSON file (docs/study.md explains it; content/studies/ has examples) read
// into typed values. Every field is checked as it is read; a bad one is a DesignError whose one
// line names the file and the field's path ("thesis.json: conditions[1].vary: unknown parameter
// 'scal' (one of: scale, rays-per-point, k, slope, layers)").
//
// The schema. Keys are snake_case, except a condition's render settings, which carry the render
// command's option names so a design reads like a command line. A key not listed here is an
// error that lists the allowed ones; so is a wrong type or a value out of range.
// {
//   "name": "thesis-scale",          required; [A-Za-z0-9_-], 1-64 (journal file names use it)
//   "description": "...",            optional text
//   "procedure": "yes-no",           required: forced-choice | yes-no | pair | ramp | slider
//   "seed": 0,                       unsigned; 0: a random seed, written in the journal
//   "practice_trials": 0,            per condition, at the easiest (most foveated) level
//   "break_every": 0,                trials between breaks, 0: none
//   "break_between_conditions": false,  true: conditions one after another, a break between
//                                    (the thesis); false: interleaved at random
//   "catch_rate": 0.0,               yes-no only: share of catch trials, [0, 0.5]
//   "ramp_steps": 5,                 ramp: intervals per ramp, 2-20
//   "fixation_x": 0.5, "fixation_y": 0.5,  the fixation point, fraction of the view, [0, 1]
//   "hmd": "",                       a headset profile as --hmd takes it; "" the window
//   "width": 1280, "height": 720,    the window's size, 16-16384
//   "timing": {                      milliseconds; each optional
//     "fixation_ms": 500, "interval_ms": 1000, "blank_ms": 500,   [0, 600000], interval > 0
//     "response_timeout_ms": 0,      0: wait for the answer
//     "refresh_hz": 0 },             0: the display's, else [1, 1000]
//   "gaze": {                        the gaze-contingent rules; each optional
//     "fixation_radius_deg": 0,      0: off, else (0, 90]
//     "repeat_on_saccade": false, "saccade_deg_per_s": 100,   (0, 10000]
//     "max_repeats": 3,              0-100
//     "gaze_lost_ms": 100 },         (0, 600000]
//   "scenes": [                      optional, default [{"scene": "builtin:market"}]; trials
//     {"scene": "builtin:market",    cycle through them per condition; a string is a scene
//      "camera": "x,y,z,tx,ty,tz",   optional
//      "camera_path": "FILE.csv"}],  optional; paths as the command line takes them
//   "conditions": [                  required, at least one
//     {"name": "scale",              required, unique; [A-Za-z0-9_.-], 1-64
//      "vary": "scale",              required: scale | rays-per-point | k | slope | layers
//      "levels": {"min": 1.0, "max": 3.0, "step": 0.1},   required: within the parameter's
//                                    range (stimulus.hpp), min < max; step 0: continuous, 64
//                                    levels (quest-plus and constant only: a staircase needs a
//                                    step); default 1 for whole-number parameters, else 0; or a
//                                    list of levels [1.0, 1.5, 2.0]; whole numbers where the
//                                    parameter is one
//      "method": "foveated",         foveated | layers; default: layers when vary is slope or
//                                    layers, else foveated (the parameter must be the method's)
//      "scale": 1.0, "rays-per-point": 1, "interp": "nn", "k": 10,   the settings not varied
//      "slope": 0.0275, "layers": 3, "spp": 1, "taa": true,         ("slope" also "A" | "B";
//                                    "interp": nn | msm | rbf); the varied one may not be set
//      "comparison": {...},          optional: the render settings above (method may be
//                                    "reference") over the condition's; absent: the reference
//      "placement": {                optional
//        "kind": "staircase",        staircase | weighted-staircase | thesis-series |
//                                    quest-plus | constant (slider: constant only)
//        "start": ...,               within the levels; default: the thesis series' least
//                                    foveated level, else the most foveated (easiest) one
//        "step": ..., "final_step": ...,   default 2 and 1 grid steps; not below one grid step
//        "down": 2, "up": 1,         1-10
//        "target": 0.75,             weighted staircase, (0, 1); forced-choice: above 0.5
//        "reversals": 8, "skip_reversals": 2,   skip below reversals
//        "max_trials": 80,           1-10000
//        "repeats": 2,               constant: trials per level (max_trials caps the
//                                    total); slider: slider trials per condition
//        "quest_slopes": [2, 4, 8, 16], "quest_lapses": [0, 0.02, 0.04],
//        "guess": 0.5,               [0, 1); default 0.5 for forced-choice, else 0
//        "shape": "logistic"}}]      logistic | cumulative-normal | weibull
// }
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "placement.hpp"
#include "stimulus.hpp"

namespace gt::study {

class DesignError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// How a trial asks its question.
//  - ForcedChoice: two intervals, the condition and its comparison (the reference, or a second
//    condition) in random order; "which one was foveated?" (First / Second). Positive: correct.
//  - YesNo: one interval, the condition or, with `catchRate`, the comparison alone (a catch
//    trial); "was it foveated?" (Yes / No). Positive: yes. The thesis's series is YesNo with the
//    ThesisSeries placement and catch trials.
//  - Pair: Guenter et al. 2012's pair test: the reference and the condition in both orders;
//    "which was better?" (First / Second / Same). Positive: the reference judged better.
//  - Ramp: Guenter et al. 2012's ramp test: `rampSteps` intervals from the comparison level to
//    the trial's level or back; "did quality go up, down or stay?" (Up / Down / Same). Positive:
//    the direction named correctly.
//  - Slider: Guenter et al. 2012's slider test: the condition shown until the participant
//    answers, starting at the least-quality level: Up / Down move the level a grid step,
//    Reference shows the comparison for one interval, Accept ends the trial. The recorded
//    threshold is the first level at which the participant stopped raising quality and compared
//    it to the reference.
enum class Procedure { ForcedChoice, YesNo, Pair, Ramp, Slider };

// One thing a study measures: a renderer setting varied over levels on a base setting.
struct Condition {
    std::string name;
    RenderChoice base; // the settings not varied
    Parameter vary = Parameter::Scale;
    PlacementSettings placement; // its grid, kind and rules (higherFoveatesMore from vary)
    // What the condition is compared with: the reference (a full-resolution frame at base.spp),
    // or another condition's settings at a fixed level.
    std::optional<RenderChoice> comparison;
};

// Gaze-contingent rules: a trial is repeated (later in the run) when the gaze leaves the fixation
// region or a saccade starts during an interval. Radius 0 turns the region check off.
struct GazeRules {
    double fixationRadiusDeg = 0.0; // around the fixation point
    bool repeatOnSaccade = false;
    double saccadeDegPerS = 100.0; // an angular speed above it is a saccade
    uint32_t maxRepeats = 3;       // then the trial is kept, flagged
    double gazeLostMs = 100.0;     // gaze missing longer than this flags the trial
};

struct Timing {
    double fixationMs = 500.0; // the fixation mark before the first interval
    double intervalMs = 1000.0;
    double blankMs = 500.0;         // between intervals (Guenter et al. 2012: 0.5 s of black)
    double responseTimeoutMs = 0.0; // 0: wait for the answer
    double refreshHz = 0.0;         // 0: the display's; frames longer than 1.5 periods are dropped
};

struct StudyDesign {
    std::string name;
    std::string description;
    Procedure procedure = Procedure::ForcedChoice;
    std::vector<Condition> conditions; // at least one
    std::vector<SceneChoice> scenes;   // trials cycle through them; at least one
    Timing timing;
    GazeRules gaze;
    double fixationX = 0.5; // the fixation point, fraction of the view
    double fixationY = 0.5;
    uint32_t practiceTrials = 0;         // per condition, at the start, not analysed
    uint32_t breakEvery = 0;             // trials between breaks (0: none); a break waits for a key
    bool breakBetweenConditions = false; // run conditions one after another (the thesis), else
                                         // interleaved at random
    double catchRate = 0.0;              // YesNo: share of catch trials
    uint32_t rampSteps = 5;              // Ramp
    uint64_t seed = 0;                   // 0: a random seed, written in the journal
    // The display the study runs on (a headset profile name as --hmd takes it, or empty for the
    // window's own size).
    std::string hmd;
    uint32_t width = 1280;
    uint32_t height = 720;
};

// The names the schema uses ("forced-choice", "quest-plus", "foveated", "msm").
[[nodiscard]] std::string procedureName(Procedure procedure);
[[nodiscard]] std::string placementKindName(PlacementKind kind);
[[nodiscard]] std::string methodName(Method method);
[[nodiscard]] std::string interpolationName(Interpolation interp);

// Throws DesignError naming `source` and the field.
[[nodiscard]] StudyDesign parseDesign(const nlohmann::json& json, const std::string& source);
// Reads and parses a design file (io::readInputFile's checks: missing, too large, not a file).
[[nodiscard]] StudyDesign loadDesign(const std::filesystem::path& path);
// The design back as JSON (every field, defaults filled in): written into the journal's first
// line so a run's analysis never needs the file again.
[[nodiscard]] nlohmann::json designToJson(const StudyDesign& design);
// 16 hex digits (FNV-1a of designToJson's compact text): a journal is resumed, and journals are
// pooled, only under the design that wrote them.
[[nodiscard]] std::string designHash(const StudyDesign& design);
// The comparison a condition's trials show: its `comparison`, or the reference at the
// condition's spp.
[[nodiscard]] RenderChoice comparisonOf(const Condition& condition);

} // namespace gt::study
