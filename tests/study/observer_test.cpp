#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "observer.hpp"

namespace gt::study {
namespace {

// A 2IFC observer on the point-set scale: the thesis's Table 3 nearest-neighbour mean (1.75) as
// its threshold, a slope that takes it from chance to near certainty over about half a scale
// unit (F from 0.1 to 0.9 over 2 ln 9 / 8 = 0.55), and a lapse rate of 0.02 (Wichmann & Hill
// 2001's typical observer).
PsychometricFunction plantedObserver(double threshold = 1.75) {
    return {PsychometricShape::Logistic, threshold, 8.0, 0.5, 0.02, true};
}
constexpr double kPlanted = 1.75;
constexpr int kObservers = 100;

FitSettings scaleFit() {
    FitSettings s;
    s.levelMin = 1.0; // the thesis 6.1's scale range, in steps of 0.1
    s.levelMax = 3.0;
    s.guess = 0.5;
    s.maxLapse = 0.06;
    s.bootstrap = 100;
    s.sensitivity = true;
    return s;
}

// Levitt 1971's 1-up-2-down (70.7 % correct) from the most foveated level, which a 2IFC observer
// tells easily. Its steps stay at 0.2, two grid steps, so the trials spread over the rising part
// of the function and the fit can tell its slope (a run in 0.1 steps puts nearly every trial on
// two or three levels: its fitted slopes come out steep and its intervals narrow, Wichmann &
// Hill 2001b); 14 reversals are averaged after the first two.
SimulationSettings staircase() {
    SimulationSettings s;
    s.placement.kind = PlacementKind::Staircase;
    s.placement.grid = {1.0, 3.0, 0.1, {}};
    s.placement.start = 3.0;
    s.placement.step = 0.2;
    s.placement.finalStep = 0.2;
    s.placement.down = 2;
    s.placement.up = 1;
    s.placement.skipReversals = 2;
    s.placement.reversals = 14;
    s.placement.maxTrials = 120;
    s.fit = scaleFit();
    s.tolerance = 0.2;
    return s;
}

// QUEST+ over the same grid, its levels chosen for the threshold (slope and lapse marginalised).
SimulationSettings questPlus() {
    SimulationSettings s = staircase();
    s.placement.kind = PlacementKind::QuestPlus;
    s.placement.questThresholdEntropy = true;
    s.placement.maxTrials = 80;
    s.fit.bootstrap = 0;
    return s;
}

std::vector<SimulatedRun> runObservers(const SimulationSettings& settings,
                                       double threshold = kPlanted) {
    std::vector<SimulatedRun> runs;
    for (int i = 0; i < kObservers; ++i) {
        SimulatedObserver observer(plantedObserver(threshold), 1000 + i);
        runs.push_back(simulateRun(observer, settings, 5000 + i));
    }
    return runs;
}

double median(std::vector<double> values) {
    std::ranges::sort(values);
    const std::size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// Trials to the tolerance; a run that never stayed within it counts as one trial past its end.
double medianTrialsToTolerance(const std::vector<SimulatedRun>& runs) {
    std::vector<double> trials;
    for (const SimulatedRun& run : runs) {
        trials.push_back(run.trialsToTolerance > 0 ? run.trialsToTolerance
                                                   : static_cast<double>(run.levels.size() + 1));
    }
    return median(trials);
}

TEST(SimulatedObserver, AnswersWithThePsychometricProbability) {
    SimulatedObserver observer(plantedObserver(), 3);
    int atThreshold = 0;
    int farBelow = 0;
    int catches = 0;
    constexpr int kDraws = 20000;
    for (int i = 0; i < kDraws; ++i) {
        atThreshold += observer.answer(kPlanted) ? 1 : 0;
        farBelow += observer.answer(0.0) ? 1 : 0;
        catches += observer.answerCatch() ? 1 : 0;
    }
    // psi(alpha) = 0.5 + (1 - 0.5 - 0.02) / 2 = 0.74; the binomial sd over 20000 is 0.003.
    EXPECT_NEAR(atThreshold / double(kDraws), 0.74, 0.012);
    EXPECT_NEAR(farBelow / double(kDraws), 0.5, 0.012);
    EXPECT_NEAR(catches / double(kDraws), 0.5, 0.012);
    // The seed alone decides the answers.
    SimulatedObserver once(plantedObserver(), 3);
    SimulatedObserver again(plantedObserver(), 3);
    SimulatedObserver other(plantedObserver(), 4);
    std::vector<bool> a;
    std::vector<bool> b;
    std::vector<bool> c;
    for (int i = 0; i < 64; ++i) {
        a.push_back(once.answer(kPlanted));
        b.push_back(again.answer(kPlanted));
        c.push_back(other.answer(kPlanted));
    }
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
}

TEST(SimulateRun, SameSeedsSameRunAndTheToleranceIsWhereTheEstimateStaysClose) {
    SimulationSettings s = questPlus();
    s.placement.maxTrials = 40;
    s.tolerance = 0.15;
    SimulatedObserver first(plantedObserver(), 11);
    SimulatedObserver second(plantedObserver(), 11);
    const SimulatedRun run = simulateRun(first, s, 12);
    const SimulatedRun same = simulateRun(second, s, 12);
    EXPECT_EQ(run.levels, same.levels);
    EXPECT_EQ(run.positive, same.positive);
    ASSERT_EQ(run.levels.size(), 40u);
    ASSERT_EQ(run.estimates.size(), 40u);
    ASSERT_GT(run.trialsToTolerance, 1u);
    for (std::size_t t = run.trialsToTolerance; t <= run.estimates.size(); ++t) {
        EXPECT_LE(std::abs(*run.estimates[t - 1] - kPlanted), s.tolerance) << t;
    }
    EXPECT_GT(std::abs(*run.estimates[run.trialsToTolerance - 2] - kPlanted), s.tolerance);
    EXPECT_EQ(run.placementEstimate, run.estimates.back());
}

TEST(SimulateRun, ConstantStimuliRecoverTheThreshold) {
    SimulationSettings s = staircase();
    s.placement.kind = PlacementKind::ConstantStimuli;
    s.placement.repeats = 40;
    s.placement.maxTrials = 10000;
    s.fit.bootstrap = 50;
    SimulatedObserver observer(plantedObserver(), 21);
    const SimulatedRun run = simulateRun(observer, s, 22);
    EXPECT_EQ(run.levels.size(), 21u * 40u);
    EXPECT_NEAR(run.fit.function.threshold, kPlanted, 0.06);
    EXPECT_LE(run.fit.thresholdLow, kPlanted);
    EXPECT_GE(run.fit.thresholdHigh, kPlanted);
    EXPECT_FALSE(run.placementEstimate.has_value());
}

// The study's acceptance: 100 simulated 2IFC observers on the point-set scale, each a 1-up-2-down
// staircase and a maximum likelihood fit with a lapse rate; the planted threshold lies within the
// fit's 95 % bootstrap interval for at least 90 of them.
TEST(SimulatedRunAcceptance, StaircaseIntervalsCoverThePlantedThreshold) {
    const std::vector<SimulatedRun> runs = runObservers(staircase());
    int covered = 0;
    std::vector<double> lengths;
    for (const SimulatedRun& run : runs) {
        covered += run.fit.thresholdLow <= kPlanted && kPlanted <= run.fit.thresholdHigh ? 1 : 0;
        lengths.push_back(static_cast<double>(run.levels.size()));
    }
    RecordProperty("covered", covered);
    RecordProperty("median_trials", std::to_string(median(lengths)));
    EXPECT_GE(covered, 90);
    // The placement ended on its reversals, not on maxTrials.
    EXPECT_LT(median(lengths), 120.0);
}

// QUEST+ (Watson 2017) gets the threshold within 0.2 scale units (two grid steps), and keeps it
// there, in fewer trials than the staircase's fitted threshold, for the same 100 observers and
// 80 trials each; and again for observers whose threshold (1.3) is far from the middle of the
// grid, where an estimate that stayed near its prior would not pass.
TEST(SimulatedRunAcceptance, QuestPlusReachesTheToleranceInFewerTrials) {
    SimulationSettings stairs = staircase();
    stairs.placement.reversals = 1000; // run to maxTrials, as QUEST+ does
    stairs.placement.maxTrials = 80;
    stairs.fit.bootstrap = 0;
    for (const double threshold : {kPlanted, 1.3}) {
        const std::string tag = std::to_string(threshold).substr(0, 4);
        const double staircaseTrials = medianTrialsToTolerance(runObservers(stairs, threshold));
        const std::vector<SimulatedRun> quest = runObservers(questPlus(), threshold);
        const double questTrials = medianTrialsToTolerance(quest);
        std::vector<double> errors;
        for (const SimulatedRun& run : quest) {
            errors.push_back(std::abs(*run.estimates.back() - threshold));
        }
        RecordProperty("staircase_median_trials_" + tag, std::to_string(staircaseTrials));
        RecordProperty("quest_median_trials_" + tag, std::to_string(questTrials));
        RecordProperty("quest_median_final_error_" + tag, std::to_string(median(errors)));
        EXPECT_LT(questTrials, staircaseTrials) << threshold;
        EXPECT_LT(staircaseTrials, 81.0) << threshold; // both get there
        EXPECT_LT(median(errors), 0.08) << threshold;
    }
}

} // namespace
} // namespace gt::study
