#pragma once
// A simulated observer, for tests and for planning a study: it answers each trial by drawing
// from a psychometric function of the level (or of a perceptual metric the app computes on the
// rendered frames, when `fromMetric`), so a whole study runs headless and the analysis can be
// checked against the threshold it was given.
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "placement.hpp"
#include "psychometric.hpp"

namespace gt::study {

class SimulatedObserver {
public:
    SimulatedObserver(PsychometricFunction function, uint64_t seed);
    // A forced choice: true when it picks the interval that held the foveated stimulus; a yes/no
    // trial: true when it says "foveated". `x` is the level (or the metric value).
    [[nodiscard]] bool answer(double x);
    // A catch trial (the reference shown alone): "foveated" with the guess (false-alarm) rate.
    [[nodiscard]] bool answerCatch();
    [[nodiscard]] const PsychometricFunction& function() const noexcept { return mFunction; }

private:
    PsychometricFunction mFunction;
    std::mt19937_64 mRandom;
};

// A whole simulated run of one placement: `trials` answers from `observer`, then the fit.
struct SimulatedRun {
    std::vector<double> levels;
    std::vector<bool> positive;
    PsychometricFit fit;
    std::optional<double> placementEstimate;
    // The threshold estimate after each trial (QUEST+: its posterior's; the others: a fit of the
    // answers so far), the curve trialsToTolerance reads.
    std::vector<std::optional<double>> estimates;
    // Trials after which the fitted (or QUEST+ posterior) threshold stayed within `tolerance` of
    // the observer's for the rest of the run; 0 when it never did.
    uint32_t trialsToTolerance = 0;
};

struct SimulationSettings {
    PlacementSettings placement;
    FitSettings fit;
    double tolerance = 0.1; // threshold error for trialsToTolerance, in level units
};

[[nodiscard]] SimulatedRun simulateRun(SimulatedObserver& observer,
                                       const SimulationSettings& settings, uint64_t seed);

} // namespace gt::study
