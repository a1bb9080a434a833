#include "observer.hpp"

#include <algorithm>
#include <cmath>

#include "sampling.hpp"

namespace gt::study {

SimulatedObserver::SimulatedObserver(PsychometricFunction function, uint64_t seed)
    : mFunction(function), mRandom(mixSeed(seed, 0x0B5E)) {}

bool SimulatedObserver::answer(double x) {
    return uniform01(mRandom) < mFunction.probability(x);
}

bool SimulatedObserver::answerCatch() {
    return uniform01(mRandom) < mFunction.guess;
}

namespace {

// The threshold estimates after each trial of a run that placed its levels other than by QUEST+:
// a maximum likelihood fit of the answers so far with the lapse held at 0 and no bootstrap (only
// the point estimate is compared, and the run is refitted after every trial).
std::vector<std::optional<double>> fittedPerTrial(const SimulatedRun& run,
                                                  const FitSettings& settings) {
    FitSettings quick = settings;
    quick.maxLapse = 0.0;
    quick.bootstrap = 0;
    std::vector<std::optional<double>> estimates;
    std::vector<LevelCount> counts;
    for (std::size_t t = 0; t < run.levels.size(); ++t) {
        const double level = run.levels[t];
        auto at = std::ranges::find_if(
            counts, [level](const LevelCount& c) { return std::abs(c.level - level) <= 1e-12; });
        if (at == counts.end()) {
            at = counts.insert(counts.end(), {level, 0, 0});
        }
        ++at->trials;
        at->positive += run.positive[t] ? 1 : 0;
        estimates.emplace_back(fitPsychometric(counts, quick).function.threshold);
    }
    return estimates;
}

// The trials after which every later estimate lies within `tolerance` of `planted`; 0 when the
// last one does not.
uint32_t trialsToTolerance(const std::vector<std::optional<double>>& estimates, double planted,
                           double tolerance) {
    uint32_t first = 0;
    for (std::size_t t = estimates.size(); t > 0; --t) {
        const std::optional<double>& e = estimates[t - 1];
        if (!e || std::abs(*e - planted) > tolerance) {
            break;
        }
        first = static_cast<uint32_t>(t);
    }
    return first;
}

} // namespace

SimulatedRun simulateRun(SimulatedObserver& observer, const SimulationSettings& settings,
                         uint64_t seed) {
    const std::unique_ptr<LevelPlacement> placement = makePlacement(settings.placement, seed);
    SimulatedRun run;
    std::vector<std::optional<double>> placementEstimates;
    while (!placement->finished()) {
        const double level = placement->next();
        const bool positive = observer.answer(level);
        placement->record(level, positive);
        run.levels.push_back(level);
        run.positive.push_back(positive);
        placementEstimates.push_back(placement->estimate());
    }
    run.placementEstimate = placement->estimate();
    FitSettings fit = settings.fit;
    fit.seed = mixSeed(settings.fit.seed, seed);
    run.fit = fitPsychometric(countByLevel(run.levels, run.positive), fit);
    // QUEST+ is judged by its own posterior estimate (Watson 2017); the other placements by the
    // fit an analysis would make of their answers.
    run.estimates = settings.placement.kind == PlacementKind::QuestPlus
                        ? std::move(placementEstimates)
                        : fittedPerTrial(run, settings.fit);
    run.trialsToTolerance =
        trialsToTolerance(run.estimates, observer.function().threshold, settings.tolerance);
    return run;
}

} // namespace gt::study
