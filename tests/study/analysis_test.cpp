#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include <unistd.h>

#include "analysis.hpp"
#include "design.hpp"
#include "observer.hpp"
#include "placement.hpp"
#include "simulation.hpp"

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

namespace fs = std::filesystem;
using nlohmann::json;

StudyDesign designOf(const std::string& procedure, double catchRate = 0.0) {
    json d{{"name", "analysis-test"},
           {"procedure", procedure},
           {"conditions",
            {{{"name", "nn"},
              {"vary", "scale"},
              {"levels", {{"min", 1.0}, {"max", 3.0}, {"step", 0.1}}},
              {"placement", {{"kind", "constant"}, {"repeats", 20}}}}}}};
    if (catchRate > 0.0) d["catch_rate"] = catchRate;
    return parseDesign(d, "analysis-test.json");
}

// A journal as the session writes it: the start line, then one line per trial answered by a
// simulated observer at every grid level `repeats` times (plus practice, flagged and catch
// trials where asked).
struct JournalPlan {
    std::string participant;
    PsychometricFunction observer;
    uint32_t repeats = 20;
    uint32_t practice = 0;
    uint32_t flaggedEvery = 0; // every n-th trial flagged (0: none)
    uint32_t catchTrials = 0;
};

void writeJournal(const fs::path& path, const StudyDesign& design, const JournalPlan& plan,
                  uint64_t seed) {
    Journal journal(path);
    journal.append({{"type", "start"},
                    {"design", designToJson(design)},
                    {"design_hash", designHash(design)},
                    {"seed", seed},
                    {"participant", plan.participant},
                    {"run", "0123456789abcdef"}});
    SimulatedObserver observer(plan.observer, seed);
    uint32_t index = 0;
    auto add = [&](double level, bool practice, bool catchTrial) {
        TrialRecord t;
        t.trial = index++;
        t.practice = practice;
        t.condition = "nn";
        t.parameter = "scale";
        t.level = level;
        t.catchTrial = catchTrial;
        t.positive = catchTrial ? observer.answerCatch() : observer.answer(level);
        t.response = t.positive ? "yes" : "no";
        if (plan.flaggedEvery > 0 && index % plan.flaggedEvery == 0) t.flags = {"dropped_frame"};
        journal.append(toJson(t));
    };
    for (uint32_t i = 0; i < plan.practice; ++i)
        add(3.0, true, false);
    for (uint32_t r = 0; r < plan.repeats; ++r) {
        for (const double level : design.conditions[0].placement.grid.all())
            add(level, false, false);
    }
    for (uint32_t i = 0; i < plan.catchTrials; ++i)
        add(0.0, false, true);
    journal.append({{"type", "end"}});
}

class AnalyseJournals : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = fs::temp_directory_path() /
               ("gt-analysis-" + std::to_string(::getpid()) + "-" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(mDir);
        fs::create_directories(mDir);
    }
    void TearDown() override { fs::remove_all(mDir); }
    fs::path mDir;
};

TEST_F(AnalyseJournals, RecoversEachParticipantsThresholdAndPoolsThem) {
    const StudyDesign design = designOf("forced-choice");
    const std::vector<double> planted{1.6, 2.2};
    std::vector<fs::path> journals;
    for (std::size_t i = 0; i < planted.size(); ++i) {
        JournalPlan plan;
        plan.participant = "P0" + std::to_string(i + 1);
        plan.observer = {PsychometricShape::Logistic, planted[i], 8.0, 0.5, 0.0, true};
        plan.practice = 5;
        plan.flaggedEvery = 10;
        journals.push_back(mDir / (plan.participant + ".jsonl"));
        writeJournal(journals.back(), design, plan, 7 + i);
    }
    const Analysis a = analyseJournals(journals, {false, 200, 3});
    EXPECT_EQ(a.design, "analysis-test");
    ASSERT_EQ(a.participants.size(), 2u);
    for (std::size_t i = 0; i < planted.size(); ++i) {
        const ParticipantCondition& pc = a.participants[i];
        EXPECT_EQ(pc.participant, "P0" + std::to_string(i + 1));
        EXPECT_EQ(pc.parameter, "scale");
        ASSERT_TRUE(pc.fitted);
        EXPECT_EQ(pc.fit.trials, 21u * 20u) << "practice trials are left out";
        EXPECT_EQ(pc.counts.size(), 21u);
        EXPECT_EQ(pc.flaggedTrials, 42u);
        EXPECT_DOUBLE_EQ(pc.fit.function.guess, 0.5);
        EXPECT_NEAR(pc.fit.function.threshold, planted[i], 0.15);
        EXPECT_LT(pc.fit.thresholdLow, pc.fit.function.threshold);
        EXPECT_GT(pc.fit.thresholdHigh, pc.fit.function.threshold);
        EXPECT_FALSE(pc.ruleThreshold.has_value()) << "2IFC with constant stimuli has no rule";
    }
    ASSERT_EQ(a.conditions.size(), 1u);
    EXPECT_EQ(a.conditions[0].group.participants, 2u);
    EXPECT_NEAR(
        a.conditions[0].group.mean,
        (a.participants[0].fit.function.threshold + a.participants[1].fit.function.threshold) / 2.0,
        1e-9);
    const json j = toJson(a);
    EXPECT_EQ(j.at("participants").size(), 2u);
    EXPECT_EQ(j.at("conditions")[0].at("participants"), 2);
    EXPECT_TRUE(j.at("conditions")[0].at("rule_mean").is_null());

    const Analysis excluded = analyseJournals(journals, {true, 200, 3});
    EXPECT_EQ(excluded.participants[0].fit.trials, 21u * 20u - 42u);
    EXPECT_EQ(excluded.participants[0].flaggedTrials, 42u);
}

TEST_F(AnalyseJournals, YesNoFitsTheGuessRateFromTheCatchTrials) {
    const StudyDesign design = designOf("yes-no", 0.2);
    JournalPlan plan;
    plan.participant = "P01";
    plan.observer = {PsychometricShape::Logistic, 1.8, 8.0, 0.3, 0.0, true};
    plan.catchTrials = 200;
    const fs::path journal = mDir / "p01.jsonl";
    writeJournal(journal, design, plan, 11);
    const Analysis a = analyseJournals(std::vector<fs::path>{journal}, {false, 100, 3});
    ASSERT_EQ(a.participants.size(), 1u);
    EXPECT_NEAR(a.participants[0].fit.function.guess, 0.3, 0.06);
    EXPECT_NEAR(a.participants[0].fit.function.threshold, 1.8, 0.2);
}

TEST_F(AnalyseJournals, RefusesJournalsOfAnotherDesignNamingTheFile) {
    JournalPlan plan;
    plan.participant = "P01";
    plan.repeats = 1;
    writeJournal(mDir / "a.jsonl", designOf("forced-choice"), plan, 1);
    writeJournal(mDir / "b.jsonl", designOf("yes-no"), plan, 2);
    try {
        (void)analyseJournals(std::vector<fs::path>{mDir / "a.jsonl", mDir / "b.jsonl"}, {});
        FAIL() << "journals of two designs were pooled";
    } catch (const JournalError& e) {
        EXPECT_NE(std::string(e.what()).find("b.jsonl"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("a.jsonl"), std::string::npos) << e.what();
    }
    Journal notAStudy(mDir / "c.jsonl");
    notAStudy.append({{"type", "trial"}, {"trial", 0}});
    EXPECT_THROW((void)analyseJournals(std::vector<fs::path>{mDir / "c.jsonl"}, {}), JournalError);
}

// Every design shipped in content/studies parses.
TEST(ContentStudies, EveryDesignParses) {
    const fs::path folder = fs::path(GT_SOURCE_DIR) / "content" / "studies";
    uint32_t designs = 0;
    for (const fs::directory_entry& e : fs::directory_iterator(folder)) {
        if (e.path().extension() != ".json") continue;
        SCOPED_TRACE(e.path().filename().string());
        const StudyDesign d = loadDesign(e.path());
        EXPECT_EQ(d.name, e.path().stem().string()) << "a design is named as its file";
        EXPECT_FALSE(d.description.empty());
        ++designs;
    }
    EXPECT_GE(designs, 5u);
}

// The thesis's experiment run by simulated observers through the real session: the fits and
// the thesis's own rule (the mean of the counted reversals) come back near the planted
// threshold in every condition, and the journals hold every answered trial.
TEST_F(AnalyseJournals, SimulatedThesisScaleRecoversThePlantedThreshold) {
    const StudyDesign design =
        loadDesign(fs::path(GT_SOURCE_DIR) / "content" / "studies" / "thesis-scale.json");
    DesignSimulationSettings settings;
    settings.observers = 10;
    settings.threshold = 1.75; // the thesis's Table 3, NN
    settings.slope = 10.0;     // 25 % to 75 % detection over 0.22 of scale
    settings.seed = 5;
    const DesignSimulation sim = simulateDesign(design, settings, mDir);
    ASSERT_EQ(sim.journals.size(), 10u);
    ASSERT_EQ(sim.conditions.size(), 3u);
    for (const ConditionRecovery& c : sim.conditions) {
        SCOPED_TRACE(c.condition);
        EXPECT_DOUBLE_EQ(c.planted.threshold, 1.75);
        EXPECT_EQ(c.fitted, 10u);
        ASSERT_TRUE(c.errorMedian && c.ruleErrorMedian && c.trialsMedian);
        EXPECT_LT(*c.errorMedian, 0.15);
        EXPECT_LT(*c.ruleErrorMedian, 0.15);
        EXPECT_GE(*c.trialsMedian, 6.0); // an ascent from 1.0 and four counted reversals
    }
    // The journals analyse again to the same fits (study analyse DIR/*.jsonl).
    const Analysis again = analyseJournals(sim.journals, {false, 200, 5});
    ASSERT_EQ(again.participants.size(), sim.analysis.participants.size());
    EXPECT_DOUBLE_EQ(again.participants[0].fit.function.threshold,
                     sim.analysis.participants[0].fit.function.threshold);
    EXPECT_THROW((void)simulateDesign(design, settings, mDir), JournalError)
        << "a simulation never appends to an earlier run's journals";
}

} // namespace
} // namespace gt::study
