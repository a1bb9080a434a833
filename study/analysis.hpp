#pragma once
// `gazetrace study analyse`: the journals of one design's runs read back, a psychometric function
// fitted per participant and condition (maximum likelihood with a lapse rate, bootstrap
// intervals), the thesis series' and Guenter et al. 2012's own threshold rules beside it, and the
// participants pooled per condition.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "journal.hpp"
#include "psychometric.hpp"

namespace gt::study {

struct ParticipantCondition {
    std::string participant;
    std::string condition;
    std::string parameter;
    std::vector<LevelCount> counts; // practice trials left out
    PsychometricFit fit;
    bool fitted = false; // false for the slider (its rule is the threshold) or no counted trial
    // The procedure's own rule, where it has one: the thesis series' mean of counted reversals,
    // the pair test's lowest quality judged equal or better, the ramp test's lowest quality
    // mislabelled, the slider's mean recorded level.
    std::optional<double> ruleThreshold;
    uint32_t flaggedTrials = 0; // dropped frames or lost gaze (kept, counted)
};

struct ConditionSummary {
    std::string condition;
    std::string parameter;
    GroupThreshold group;           // the slider's: of the rule thresholds (no fit, `pooled` empty)
    bool fitted = false;            // `group` pools fits
    std::optional<double> ruleMean; // mean of the participants' rule thresholds
    std::optional<double> ruleSd;
};

struct Analysis {
    std::string design;
    std::vector<ParticipantCondition> participants;
    std::vector<ConditionSummary> conditions;
};

struct AnalysisSettings {
    bool excludeFlagged = false; // leave out trials with dropped frames or lost gaze
    uint32_t bootstrap = 400;
    uint64_t seed = 1;
    // Called before each fit (a fit with its bootstrap takes a while): the app's stop check.
    std::function<void()> beforeFit;
};

// The procedures' own rules, on one participant's trials of one condition (practice left out, in
// the order answered):
//  - the thesis's series (its 6.2): the mean of the reversals after the first (which is not
//    counted), at most `counted` of them; a reversal is a trial answered unlike the one before.
[[nodiscard]] std::optional<double> seriesThreshold(const std::vector<TrialRecord>& trials,
                                                    uint32_t counted);
//  - Guenter et al. 2012's pair and ramp tests: the level that foveates most among those judged
//    equal to the reference (pair) or mislabelled / "same" (ramp): at most half its trials
//    positive.
[[nodiscard]] std::optional<double> lowestQualityJudgedEqual(std::span<const LevelCount> counts,
                                                             bool higherFoveatesMore);
//  - Guenter et al. 2012's slider test: the mean of the recorded slider levels.
[[nodiscard]] std::optional<double> sliderThreshold(const std::vector<TrialRecord>& trials);

// Throws JournalError naming the file; the journals must share one design (its name and hash).
[[nodiscard]] Analysis analyseJournals(std::span<const std::filesystem::path> journals,
                                       const AnalysisSettings& settings);
[[nodiscard]] nlohmann::json toJson(const Analysis& analysis);

} // namespace gt::study
