#pragma once
// A study design: a JSON file (docs/study.md has the schema and content/studies/ examples) read
// into typed values. Every field is checked as it is read; a bad one is a DesignError whose one
// line names the file and the field's path ("thesis.json: conditions[1].vary: unknown parameter
// 'scal' (one of: scale, rays-per-point, k, slope, layers)").
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

// Throws DesignError naming `source` and the field.
[[nodiscard]] StudyDesign parseDesign(const nlohmann::json& json, const std::string& source);
// Reads and parses a design file (io::readInputFile's checks: missing, too large, not a file).
[[nodiscard]] StudyDesign loadDesign(const std::filesystem::path& path);
// The design back as JSON (every field, defaults filled in): written into the journal's first
// line so a run's analysis never needs the file again.
[[nodiscard]] nlohmann::json designToJson(const StudyDesign& design);

} // namespace gt::study
