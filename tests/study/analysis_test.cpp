#include <gtest/gtest.h>

#include <random>

#include "analysis.hpp"
#include "placement.hpp"

namespace gt::study {
namespace {

TrialRecord trial(double level, bool positive, bool catchTrial = false) {
    TrialRecord t;
    t.level = level;
    t.positive = positive;
    t.catchTrial = catchTrial;
    return t;
}

// The thesis's series, replayed by its placement: the rule recomputed from the answered trials
// must give the placement's own estimate (the mean of the counted reversals).
TEST(AnalysisRules, SeriesThresholdRecomputesThePlacementsEstimate) {
    PlacementSettings s;
    s.kind = PlacementKind::ThesisSeries;
    s.grid = {1.0, 3.0, 0.1, {}};
    s.start = 1.0;
    s.step = 0.2;
    s.finalStep = 0.1;
    s.reversals = 4;
    for (uint64_t seed = 1; seed <= 20; ++seed) {
        const auto placement = makePlacement(s, seed);
        std::mt19937_64 random(seed);
        std::vector<TrialRecord> trials;
        while (!placement->finished()) {
            const double level = placement->next();
            // Detection rises around 1.75 (the thesis's Table 3 NN mean), with noise.
            const double p = 1.0 / (1.0 + std::exp(-(level - 1.75) * 8.0));
            const bool yes = std::uniform_real_distribution<double>(0.0, 1.0)(random) < p;
            placement->record(level, yes);
            trials.push_back(trial(level, yes));
            if (seed % 3 == 0) trials.push_back(trial(0.0, seed % 2 == 0, true)); // catch trials
        }
        ASSERT_TRUE(placement->estimate().has_value());
        const std::optional<double> rule = seriesThreshold(trials, s.reversals);
        ASSERT_TRUE(rule.has_value()) << "seed " << seed;
        EXPECT_NEAR(*rule, *placement->estimate(), 1e-9) << "seed " << seed;
    }
}

TEST(AnalysisRules, SeriesThresholdSkipsTheFirstReversalAndStopsAtTheCountedOnes) {
    // Ascending 1.0, 1.2, 1.4 "no", 1.6 "yes" (first reversal, not counted), then 1.5 "yes",
    // 1.4 "no" (1.4), 1.5 "yes" (1.5), 1.4 "yes", 1.3 "no" (1.3), 1.4 "yes" (1.4), 1.3 "no" (1.3:
    // a fifth, past the four counted).
    const std::vector<TrialRecord> trials{trial(1.0, false), trial(1.2, false), trial(1.4, false),
                                          trial(1.6, true),  trial(1.5, true),  trial(1.4, false),
                                          trial(1.5, true),  trial(1.4, true),  trial(1.3, false),
                                          trial(1.4, true),  trial(1.3, false)};
    const std::optional<double> rule = seriesThreshold(trials, 4);
    ASSERT_TRUE(rule.has_value());
    EXPECT_NEAR(*rule, (1.4 + 1.5 + 1.3 + 1.4) / 4.0, 1e-12);
    EXPECT_FALSE(seriesThreshold({trial(1.0, false), trial(1.2, true)}, 4).has_value());
}

TEST(AnalysisRules, PairAndRampTakeTheMostFoveatedLevelJudgedEqual) {
    // Slope: a higher level foveates more. 0.030 told apart always, 0.0275 twice in four (judged
    // equal), 0.025 once in four, 0.020 never.
    const std::vector<LevelCount> counts{
        {0.020, 4, 0}, {0.025, 4, 1}, {0.0275, 4, 2}, {0.030, 4, 4}};
    const std::optional<double> pair = lowestQualityJudgedEqual(counts, true);
    ASSERT_TRUE(pair.has_value());
    EXPECT_DOUBLE_EQ(*pair, 0.0275);
    // Rays per point: a lower level foveates more.
    const std::vector<LevelCount> rays{{1, 2, 2}, {2, 2, 1}, {4, 2, 0}};
    EXPECT_DOUBLE_EQ(*lowestQualityJudgedEqual(rays, false), 2.0);
    EXPECT_FALSE(lowestQualityJudgedEqual(std::vector<LevelCount>{{1, 2, 2}}, false));
}

TEST(AnalysisRules, SliderIsTheMeanRecordedLevel) {
    std::vector<TrialRecord> trials(3);
    trials[0].sliderLevel = 0.02;
    trials[1].sliderLevel = 0.03;
    EXPECT_NEAR(*sliderThreshold(trials), 0.025, 1e-12);
    EXPECT_FALSE(sliderThreshold(std::vector<TrialRecord>(2)).has_value());
}

} // namespace
} // namespace gt::study
