#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "psychometric.hpp"

namespace gt::study {
namespace {

PsychometricFunction planted() {
    return {PsychometricShape::Logistic, 1.75, 8.0, 0.5, 0.02, true};
}

// psi(alpha) = gamma + (1 - gamma - lambda) / 2 for every shape: F(alpha) = 0.5.
TEST(PsychometricFunction, HalfwayBetweenGuessAndOneMinusLapseAtTheThreshold) {
    const PsychometricFunction f = planted();
    EXPECT_DOUBLE_EQ(f.core(1.75), 0.5);
    EXPECT_NEAR(f.probability(1.75), 0.5 + 0.48 / 2.0, 1e-12); // 0.74
    // Logistic: F(alpha + ln 3 / beta) = 3 / 4, so psi = 0.5 + 0.48 * 0.75 = 0.86.
    EXPECT_NEAR(f.probability(1.75 + std::log(3.0) / 8.0), 0.86, 1e-12);
    EXPECT_NEAR(f.probability(100.0), 0.98, 1e-12); // the lapse caps it
    EXPECT_NEAR(f.probability(-100.0), 0.5, 1e-12); // the guess floors it
}

TEST(PsychometricFunction, CumulativeNormalAndWeibullByHand) {
    const PsychometricFunction normal{
        PsychometricShape::CumulativeNormal, 2.0, 4.0, 0.0, 0.0, true};
    EXPECT_DOUBLE_EQ(normal.probability(2.0), 0.5);
    EXPECT_NEAR(normal.probability(2.25), 0.8413447460685429, 1e-12); // Phi(1)
    // Weibull scaled to 0.5 at alpha: F(2 alpha) = 1 - 2^-(2^beta) = 1 - 1/16 for beta = 2.
    const PsychometricFunction weibull{PsychometricShape::Weibull, 1.5, 2.0, 0.0, 0.0, true};
    EXPECT_NEAR(weibull.probability(1.5), 0.5, 1e-12);
    EXPECT_NEAR(weibull.probability(3.0), 0.9375, 1e-12);
    EXPECT_DOUBLE_EQ(weibull.probability(0.0), 0.0);
}

TEST(PsychometricFunction, FallingFunctionMirrorsTheRisingOne) {
    PsychometricFunction falling = planted();
    falling.increasing = false;
    const PsychometricFunction rising = planted();
    EXPECT_NEAR(falling.core(2.0), rising.core(1.5), 1e-12);
    EXPECT_NEAR(falling.probability(1.75), 0.74, 1e-12);
    EXPECT_GT(falling.probability(1.0), falling.probability(2.5));
}

TEST(PsychometricFunction, LevelAtInvertsProbability) {
    for (const PsychometricShape shape :
         {PsychometricShape::Logistic, PsychometricShape::CumulativeNormal,
          PsychometricShape::Weibull}) {
        for (const bool increasing : {true, false}) {
            const PsychometricFunction f{shape, 1.75, 3.0, 0.5, 0.02, increasing};
            for (double x = 1.0; x <= 3.0; x += 0.25) {
                EXPECT_NEAR(f.levelAt(f.probability(x)), x, 1e-7)
                    << static_cast<int>(shape) << " " << increasing << " " << x;
            }
        }
    }
    // 1-up-2-down's 70.7 % point on the planted 2IFC function, by hand:
    // F = (0.7071 - 0.5) / 0.48, x = alpha + ln(F / (1 - F)) / beta.
    const double f707 = (std::sqrt(0.5) - 0.5) / 0.48;
    EXPECT_NEAR(planted().levelAt(std::sqrt(0.5)), 1.75 + std::log(f707 / (1 - f707)) / 8.0, 1e-12);
    EXPECT_THROW((void)planted().levelAt(0.4), std::invalid_argument);  // below the guess rate
    EXPECT_THROW((void)planted().levelAt(0.99), std::invalid_argument); // above 1 - lapse
}

TEST(CountByLevel, GroupsTrialsAtEqualLevels) {
    const std::vector<double> levels{1.2, 1.0, 1.2, 1.0 + 0.2 - 1e-12, 3.0};
    const std::vector<bool> answers{true, false, false, true, true};
    const std::vector<LevelCount> counts = countByLevel(levels, answers);
    ASSERT_EQ(counts.size(), 3u);
    EXPECT_DOUBLE_EQ(counts[0].level, 1.0);
    EXPECT_EQ(counts[0].trials, 1u);
    EXPECT_EQ(counts[0].positive, 0u);
    EXPECT_EQ(counts[1].trials, 3u);
    EXPECT_EQ(counts[1].positive, 2u);
    EXPECT_EQ(counts[2].positive, 1u);
    EXPECT_THROW((void)countByLevel(levels, std::vector<bool>{true}), std::invalid_argument);
}

// Noiseless data: the expected number of positives out of many trials at each level.
std::vector<LevelCount> expectedCounts(const PsychometricFunction& f, uint32_t trials) {
    std::vector<LevelCount> counts;
    for (int i = 0; i <= 20; ++i) {
        const double level = 1.0 + 0.1 * i;
        counts.push_back(
            {level, trials, static_cast<uint32_t>(std::lround(trials * f.probability(level)))});
    }
    return counts;
}

FitSettings scaleFit() {
    FitSettings s;
    s.levelMin = 1.0;
    s.levelMax = 3.0;
    s.bootstrap = 0;
    return s;
}

TEST(FitPsychometric, RecoversNoiselessLargeCountData) {
    const PsychometricFit fit = fitPsychometric(expectedCounts(planted(), 100000), scaleFit());
    EXPECT_NEAR(fit.function.threshold, 1.75, 0.002);
    EXPECT_NEAR(fit.function.slope, 8.0, 0.08);
    EXPECT_NEAR(fit.function.lapse, 0.02, 0.002);
    EXPECT_DOUBLE_EQ(fit.function.guess, 0.5);
    EXPECT_EQ(fit.trials, 21u * 100000u);
    EXPECT_TRUE(fit.converged);
}

TEST(FitPsychometric, RecoversOtherShapesAndFallingFunctions) {
    FitSettings s = scaleFit();
    s.shape = PsychometricShape::CumulativeNormal;
    s.increasing = false;
    const PsychometricFunction normal{s.shape, 2.2, 5.0, 0.5, 0.03, false};
    PsychometricFit fit = fitPsychometric(expectedCounts(normal, 100000), s);
    EXPECT_NEAR(fit.function.threshold, 2.2, 0.002);
    EXPECT_NEAR(fit.function.slope, 5.0, 0.05);
    s.shape = PsychometricShape::Weibull;
    s.increasing = true;
    const PsychometricFunction weibull{s.shape, 1.6, 6.0, 0.5, 0.01, true};
    fit = fitPsychometric(expectedCounts(weibull, 100000), s);
    EXPECT_NEAR(fit.function.threshold, 1.6, 0.002);
    EXPECT_NEAR(fit.function.slope, 6.0, 0.06);
}

// Yes/no with catch trials: the false-alarm rate comes from the catch trials and the levels.
TEST(FitPsychometric, FitsTheGuessRateFromCatchTrials) {
    FitSettings s = scaleFit();
    s.fitGuess = true;
    s.catchTrials = 100000;
    s.catchPositive = 10000;
    const PsychometricFunction yesNo{PsychometricShape::Logistic, 1.9, 6.0, 0.1, 0.02, true};
    const PsychometricFit fit = fitPsychometric(expectedCounts(yesNo, 100000), s);
    EXPECT_NEAR(fit.function.guess, 0.1, 0.002);
    EXPECT_NEAR(fit.function.threshold, 1.9, 0.003);
}

TEST(FitPsychometric, DegenerateDataGiveFiniteFitsWithinTheRange) {
    const FitSettings s = scaleFit();
    for (const std::vector<LevelCount>& counts :
         {std::vector<LevelCount>{{2.0, 10, 10}}, std::vector<LevelCount>{{2.0, 10, 0}},
          std::vector<LevelCount>{{1.5, 1, 1}},
          std::vector<LevelCount>{{1.0, 5, 5}, {3.0, 5, 0}}}) {
        const PsychometricFit fit = fitPsychometric(counts, s);
        EXPECT_TRUE(std::isfinite(fit.logLikelihood));
        EXPECT_TRUE(std::isfinite(fit.function.slope));
        EXPECT_GE(fit.function.threshold, 1.0);
        EXPECT_LE(fit.function.threshold, 3.0);
        EXPECT_GE(fit.function.lapse, 0.0);
        EXPECT_LE(fit.function.lapse, s.maxLapse);
    }
}

TEST(FitPsychometric, BootstrapIntervalsContainTheFitAndNarrowWithMoreTrials) {
    FitSettings s = scaleFit();
    s.bootstrap = 200;
    const PsychometricFit few = fitPsychometric(expectedCounts(planted(), 20), s);
    const PsychometricFit many = fitPsychometric(expectedCounts(planted(), 400), s);
    for (const PsychometricFit& fit : {few, many}) {
        EXPECT_LT(fit.thresholdLow, fit.function.threshold);
        EXPECT_GT(fit.thresholdHigh, fit.function.threshold);
        EXPECT_LT(fit.slopeLow, fit.function.slope);
        EXPECT_GT(fit.slopeHigh, fit.function.slope);
    }
    EXPECT_LT(many.thresholdHigh - many.thresholdLow, 0.5 * (few.thresholdHigh - few.thresholdLow));
    // Binomial noise of the threshold over 21 x 400 trials: the 95 % interval spans about
    // 4 standard errors, a few hundredths of a scale unit.
    EXPECT_LT(many.thresholdHigh - many.thresholdLow, 0.15);
    s.confidence = 0.68;
    const PsychometricFit narrow = fitPsychometric(expectedCounts(planted(), 400), s);
    EXPECT_GT(narrow.thresholdLow, many.thresholdLow);
    EXPECT_LT(narrow.thresholdHigh, many.thresholdHigh);
    // The same seed gives the same interval.
    s.confidence = 0.95;
    EXPECT_EQ(fitPsychometric(expectedCounts(planted(), 400), s).thresholdLow, many.thresholdLow);
}

void expectThrowNaming(const std::vector<LevelCount>& counts, const FitSettings& s,
                       const std::string& name) {
    try {
        (void)fitPsychometric(counts, s);
        ADD_FAILURE() << "no error for " << name;
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
}

TEST(FitPsychometric, BadInputsThrow) {
    const std::vector<LevelCount> counts{{2.0, 10, 6}};
    expectThrowNaming({}, scaleFit(), "no trials");
    expectThrowNaming({{2.0, 0, 0}}, scaleFit(), "no trials");
    FitSettings s = scaleFit();
    s.levelMax = 1.0;
    expectThrowNaming(counts, s, "'levelMax'");
    s = scaleFit();
    s.maxLapse = 0.7;
    expectThrowNaming(counts, s, "'maxLapse'");
    s = scaleFit();
    s.confidence = 1.0;
    expectThrowNaming(counts, s, "'confidence'");
}

TEST(PoolParticipants, MeanSdBootstrapAndPooledFit) {
    FitSettings s = scaleFit();
    std::vector<PsychometricFit> fits;
    std::vector<std::vector<LevelCount>> counts;
    for (const double alpha : {1.5, 1.75, 2.0}) {
        PsychometricFunction f = planted();
        f.threshold = alpha;
        counts.push_back(expectedCounts(f, 1000));
        fits.push_back(fitPsychometric(counts.back(), s));
    }
    s.bootstrap = 500;
    const GroupThreshold group = poolParticipants(fits, counts, s);
    EXPECT_EQ(group.participants, 3u);
    EXPECT_NEAR(group.mean, 1.75, 0.002);
    EXPECT_NEAR(group.sd, 0.25, 0.002);
    // Resampled means of three participants lie between the smallest and the largest.
    EXPECT_GE(group.low, 1.5 - 0.002);
    EXPECT_LT(group.low, group.mean);
    EXPECT_GT(group.high, group.mean);
    EXPECT_LE(group.high, 2.0 + 0.002);
    EXPECT_EQ(group.pooled.trials, 3u * 21u * 1000u);
    EXPECT_NEAR(group.pooled.function.threshold, 1.75, 0.03);
    EXPECT_THROW((void)poolParticipants({}, counts, s), std::invalid_argument);
}

} // namespace
} // namespace gt::study
