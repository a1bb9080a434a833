#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "placement.hpp"

namespace gt::study {
namespace {

PlacementSettings staircaseSettings() {
    PlacementSettings s;
    s.kind = PlacementKind::Staircase;
    s.grid = {1.0, 3.0, 0.1, {}};
    s.start = 2.0;
    s.step = 0.2;
    s.finalStep = 0.1;
    s.down = 2;
    s.up = 1;
    s.skipReversals = 2;
    s.reversals = 2;
    return s;
}

// Feeds `answers` to the placement and returns the level each trial showed.
std::vector<double> play(LevelPlacement& placement, const std::vector<bool>& answers) {
    std::vector<double> shown;
    for (bool answer : answers) {
        EXPECT_FALSE(placement.finished());
        shown.push_back(placement.next());
        placement.record(shown.back(), answer);
    }
    return shown;
}

void expectLevels(const std::vector<double>& got, const std::vector<double>& want) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i)
        EXPECT_NEAR(got[i], want[i], 1e-9) << "trial " << i;
}

TEST(LevelGrid, SnapsToTheNearestStepWithinItsRange) {
    const LevelGrid grid{1.0, 3.0, 0.1, {}};
    EXPECT_NEAR(grid.snap(1.74), 1.7, 1e-12);
    EXPECT_NEAR(grid.snap(1.76), 1.8, 1e-12);
    EXPECT_DOUBLE_EQ(grid.snap(0.2), 1.0);
    EXPECT_NEAR(grid.snap(9.0), 3.0, 1e-12);
    const std::vector<double> all = grid.all();
    ASSERT_EQ(all.size(), 21u);
    EXPECT_DOUBLE_EQ(all.front(), 1.0);
    EXPECT_NEAR(all.back(), 3.0, 1e-12);
    // The same grid point from two directions is the same double.
    EXPECT_EQ(grid.snap(1.6999), grid.snap(1.7001));
}

TEST(LevelGrid, ExplicitValuesAndContinuousRanges) {
    const LevelGrid list{1.0, 64.0, 0.0, {1.0, 2.0, 4.0, 8.0}};
    EXPECT_DOUBLE_EQ(list.snap(5.0), 4.0);
    EXPECT_DOUBLE_EQ(list.snap(100.0), 8.0);
    EXPECT_EQ(list.all().size(), 4u);
    const LevelGrid continuous{0.0, 1.0, 0.0, {}};
    EXPECT_DOUBLE_EQ(continuous.snap(0.123), 0.123);
    EXPECT_DOUBLE_EQ(continuous.snap(-1.0), 0.0);
    EXPECT_EQ(continuous.all().size(), 64u);
}

// Levitt 1971's 1-up-2-down, worked by hand: two positives step down (less foveation), one
// negative steps up; 0.2 until the two skipped reversals, then 0.1.
TEST(Staircase, OneUpTwoDownFollowsTheHandWorkedSequence) {
    const auto placement = makePlacement(staircaseSettings(), 1);
    const std::vector<double> shown =
        play(*placement, {true, true, true, true, false, true, true, false, false, true, true});
    expectLevels(shown, {2.0, 2.0, 1.8, 1.8, 1.6, 1.8, 1.8, 1.7, 1.8, 1.9, 1.9});
    expectLevels(placement->reversals(), {1.6, 1.8, 1.7, 1.9});
    EXPECT_TRUE(placement->finished());
    ASSERT_TRUE(placement->estimate().has_value());
    EXPECT_NEAR(*placement->estimate(), 1.8, 1e-9); // the mean of the counted 1.7 and 1.9
    EXPECT_EQ(placement->trials(), 11u);
}

// A parameter where a higher level foveates less (rays per point): the same answers mirror.
TEST(Staircase, PositivesMoveTowardsLessFoveation) {
    PlacementSettings s = staircaseSettings();
    s.higherFoveatesMore = false;
    const auto placement = makePlacement(s, 1);
    const std::vector<double> shown =
        play(*placement, {true, true, true, true, false, true, true, false, false, true, true});
    expectLevels(shown, {2.0, 2.0, 2.2, 2.2, 2.4, 2.2, 2.2, 2.3, 2.2, 2.1, 2.1});
    EXPECT_NEAR(*placement->estimate(), 2.2, 1e-9);
}

TEST(Staircase, NoEstimateBeforeACountedReversalAndStopsAtMaxTrials) {
    PlacementSettings s = staircaseSettings();
    s.maxTrials = 5;
    const auto placement = makePlacement(s, 1);
    play(*placement, {true, true, true, true, true});
    EXPECT_FALSE(placement->estimate().has_value());
    EXPECT_TRUE(placement->finished());
}

TEST(Staircase, StaysWithinTheGrid) {
    const auto placement = makePlacement(staircaseSettings(), 1);
    for (int i = 0; i < 20; ++i)
        placement->record(placement->next(), false);
    EXPECT_NEAR(placement->next(), 3.0, 1e-9);
}

// Kaernbach 1991: for p = 0.75 a negative steps up three times as far as a positive steps down.
TEST(WeightedStaircase, StepRatioIsTargetOverOneMinusTarget) {
    PlacementSettings s = staircaseSettings();
    s.kind = PlacementKind::WeightedStaircase;
    s.target = 0.75;
    s.step = 0.1;
    s.finalStep = 0.1;
    const auto placement = makePlacement(s, 1);
    const std::vector<double> shown = play(*placement, {true, false, true, true});
    expectLevels(shown, {2.0, 1.9, 2.2, 2.1});
    expectLevels(placement->reversals(), {1.9, 2.2});
}

// The thesis 6.2: ascending from 1.0 in steps of 0.2 until the first "yes" (a reversal that is
// not counted), then 1-up-1-down in steps of 0.1.
TEST(ThesisSeries, FirstReversalIsNotCounted) {
    PlacementSettings s = staircaseSettings();
    s.kind = PlacementKind::ThesisSeries;
    s.start = 1.0;
    s.reversals = 2;
    const auto placement = makePlacement(s, 1);
    const std::vector<double> shown = play(*placement, {false, false, true, true, false, true});
    expectLevels(shown, {1.0, 1.2, 1.4, 1.3, 1.2, 1.3});
    expectLevels(placement->reversals(), {1.4, 1.2, 1.3});
    EXPECT_TRUE(placement->finished());
    EXPECT_NEAR(*placement->estimate(), 1.25, 1e-9); // 1.2 and 1.3, not 1.4
}

TEST(ThesisSeries, AYesOnTheFirstTrialIsItsFirstReversal) {
    PlacementSettings s = staircaseSettings();
    s.kind = PlacementKind::ThesisSeries;
    s.start = 1.5;
    const auto placement = makePlacement(s, 1);
    const std::vector<double> shown = play(*placement, {true, false});
    expectLevels(shown, {1.5, 1.4});
    expectLevels(placement->reversals(), {1.5, 1.4});
    EXPECT_NEAR(*placement->estimate(), 1.4, 1e-9);
}

TEST(ConstantStimuli, EveryLevelRepeatsInASeededShuffle) {
    PlacementSettings s;
    s.kind = PlacementKind::ConstantStimuli;
    s.grid = {1.0, 1.5, 0.1, {}};
    s.repeats = 3;
    const auto a = makePlacement(s, 7);
    const auto b = makePlacement(s, 7);
    const auto c = makePlacement(s, 8);
    std::vector<double> orderA;
    std::vector<double> orderC;
    while (!a->finished()) {
        orderA.push_back(a->next());
        EXPECT_EQ(orderA.back(), b->next());
        orderC.push_back(c->next());
        a->record(orderA.back(), true);
        b->record(orderA.back(), true);
        c->record(orderC.back(), true);
    }
    ASSERT_EQ(orderA.size(), 18u);
    EXPECT_NE(orderA, orderC);
    for (double level : s.grid.all()) {
        EXPECT_EQ(std::count(orderA.begin(), orderA.end(), level), 3) << level;
    }
}

void expectThrowNaming(const PlacementSettings& s, const std::string& setting) {
    try {
        (void)makePlacement(s, 1);
        ADD_FAILURE() << "no error for " << setting;
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("'" + setting + "'"), std::string::npos) << e.what();
    }
}

TEST(MakePlacement, BadSettingsNameTheSetting) {
    PlacementSettings s = staircaseSettings();
    s.step = 0.0;
    expectThrowNaming(s, "step");
    s = staircaseSettings();
    s.start = 3.5;
    expectThrowNaming(s, "start");
    s = staircaseSettings();
    s.finalStep = -0.1;
    expectThrowNaming(s, "finalStep");
    s = staircaseSettings();
    s.down = 0;
    expectThrowNaming(s, "down");
    s = staircaseSettings();
    s.kind = PlacementKind::WeightedStaircase;
    s.target = 1.0;
    expectThrowNaming(s, "target");
    s = staircaseSettings();
    s.kind = PlacementKind::QuestPlus;
    s.questSlopes.clear();
    expectThrowNaming(s, "questSlopes");
    s = staircaseSettings();
    s.grid.max = 0.5;
    expectThrowNaming(s, "grid.max");
    s = staircaseSettings();
    s.maxTrials = 0;
    expectThrowNaming(s, "maxTrials");
}

} // namespace
} // namespace gt::study
