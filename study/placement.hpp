#pragma once
// Where a condition's next trial is placed: the stimulus level. A placement sees every answer
// (positive: correct in a forced choice, "I saw it" in yes/no) and says when it has enough.
//  - TransformedStaircase: n-down 1-up (Levitt 1971): 1-up-2-down converges on 70.7 % positive.
//  - WeightedStaircase: fixed step ratio (Kaernbach 1991): step up / step down = p / (1 - p)
//    converges on p.
//  - ThesisSeries: the thesis's 6.2 series: ascending from a start level in coarse steps; at the
//    first reversal (not counted) the step shrinks; then a plain staircase until it has the asked
//    number of reversals; the threshold is their mean.
//  - QuestPlus: Watson 2017's QUEST+: a posterior over a grid of psychometric functions, each
//    trial at the level that minimises the expected entropy of the next posterior.
//  - ConstantStimuli: every level a fixed number of times, in the order the plan shuffles them
//    (Guenter et al. 2012's pair and ramp tests).
// "Foveates more" is always up: the placement works in the parameter's direction, so a level step
// "harder" is towards less foveation.
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "psychometric.hpp"

namespace gt::study {

// The grid of levels a condition may take: [min, max] in steps of `step` (0: continuous), or an
// explicit list (sorted).
struct LevelGrid {
    double min = 1.0;
    double max = 3.0;
    double step = 0.1;
    std::vector<double> values; // when not empty, the only levels allowed
    // The allowed level nearest to `level`, within [min, max].
    [[nodiscard]] double snap(double level) const;
    // Every allowed level (step > 0 or values); a continuous grid gives 64 evenly spaced ones.
    [[nodiscard]] std::vector<double> all() const;
};

enum class PlacementKind { Staircase, WeightedStaircase, ThesisSeries, QuestPlus, ConstantStimuli };

struct PlacementSettings {
    PlacementKind kind = PlacementKind::Staircase;
    LevelGrid grid;
    bool higherFoveatesMore = true; // from the parameter (ParameterInfo)
    double start = 1.0;             // first level
    double step = 0.2;              // staircase: first step
    double finalStep = 0.1;         // staircase, thesis series: step after the first reversal(s)
    uint32_t down = 2;              // transformed staircase: positives in a row before a step down
    uint32_t up = 1;                // ... negatives in a row before a step up
    double target = 0.75;           // weighted staircase: the p it converges on
    uint32_t reversals = 8;         // staircase, thesis series: reversals that end it (counted)
    uint32_t skipReversals = 2;     // staircase: reversals not averaged (thesis series: its first)
    uint32_t maxTrials = 80;        // every kind ends here at the latest
    uint32_t repeats = 2;           // constant stimuli: trials per level
    // QUEST+: the grid of psychometric functions (thresholds from `grid`).
    std::vector<double> questSlopes{2.0, 4.0, 8.0, 16.0};
    std::vector<double> questLapses{0.0, 0.02, 0.04};
    // QUEST+: choose levels for what they tell about the threshold alone (the expected entropy
    // of its marginal posterior) rather than about threshold, slope and lapse together.
    bool questThresholdEntropy = false;
    double guess = 0.5; // QUEST+ likelihoods (2IFC 0.5; yes/no the catch-trial rate)
    PsychometricShape shape = PsychometricShape::Logistic;
};

class LevelPlacement {
public:
    virtual ~LevelPlacement() = default;
    // The level of the next trial (snapped to the grid). Valid until record().
    [[nodiscard]] virtual double next() const = 0;
    virtual void record(double level, bool positive) = 0;
    [[nodiscard]] virtual bool finished() const = 0;
    // The current threshold estimate: the mean of the counted reversals (staircases, thesis
    // series), the posterior mean (QUEST+); empty until there is one.
    [[nodiscard]] virtual std::optional<double> estimate() const = 0;
    // Reversal levels so far (staircases, thesis series; empty for the others).
    [[nodiscard]] virtual std::vector<double> reversals() const = 0;
    [[nodiscard]] virtual uint32_t trials() const = 0;
};

// Throws std::invalid_argument naming the setting when the settings cannot work (start outside
// the grid, step 0, an empty QUEST+ grid).
[[nodiscard]] std::unique_ptr<LevelPlacement> makePlacement(const PlacementSettings& settings,
                                                            uint64_t seed);

} // namespace gt::study
