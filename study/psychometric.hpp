#pragma once
// Psychometric functions and their fit (Kingdom & Prins, Psychophysics, ch. 4; Wichmann & Hill
// 2001): the probability of a positive response ("correct" in a forced choice, "I saw it" in a
// yes/no task) at a stimulus level x,
//   psi(x) = gamma + (1 - gamma - lambda) * F(x; alpha, beta),
// with the guess rate gamma (0.5 in two-interval forced choice; the false-alarm rate in yes/no),
// the lapse rate lambda, and a core F that is 0.5 at the threshold alpha with spread 1/beta.
// Levels are in the parameter's own units; `increasing` false makes F fall with x (more rays per
// point are harder to tell from the reference).
#include <cstdint>
#include <random>
#include <span>
#include <vector>

namespace gt::study {

enum class PsychometricShape { Logistic, CumulativeNormal, Weibull };

struct PsychometricFunction {
    PsychometricShape shape = PsychometricShape::Logistic;
    double threshold = 1.0; // alpha: F = 0.5
    double slope = 5.0;     // beta > 0, per unit of level (Weibull: its shape, levels > 0)
    double guess = 0.5;     // gamma
    double lapse = 0.0;     // lambda
    bool increasing = true;
    [[nodiscard]] double core(double level) const;        // F
    [[nodiscard]] double probability(double level) const; // psi
    // The level where psi = p (for a p between guess and 1 - lapse).
    [[nodiscard]] double levelAt(double p) const;
};

// Responses at one level: how many trials, how many positive.
struct LevelCount {
    double level = 0.0;
    uint32_t trials = 0;
    uint32_t positive = 0;
};

// Groups single trials (level, positive) by level.
[[nodiscard]] std::vector<LevelCount> countByLevel(std::span<const double> levels,
                                                   std::span<const bool> positive);
// The same for answers kept as a std::vector<bool> (SimulatedRun, journals), which no span views.
[[nodiscard]] std::vector<LevelCount> countByLevel(std::span<const double> levels,
                                                   const std::vector<bool>& positive);

struct FitSettings {
    PsychometricShape shape = PsychometricShape::Logistic;
    bool increasing = true;
    double guess = 0.5; // fixed (2IFC), or fitted when fitGuess (yes/no with catch trials)
    bool fitGuess = false;
    // Yes/no catch trials (the reference alone): their "yes" answers inform the guess rate only.
    uint32_t catchTrials = 0;
    uint32_t catchPositive = 0;
    double maxLapse = 0.06; // lambda in [0, maxLapse] (Wichmann & Hill 2001)
    double levelMin = 0.0;  // alpha is searched over the design's range
    double levelMax = 1.0;
    uint32_t bootstrap = 400; // parametric bootstrap resamples for the intervals
    double confidence = 0.95;
    uint64_t seed = 1;
};

struct PsychometricFit {
    PsychometricFunction function;
    double logLikelihood = 0.0;
    double thresholdLow = 0.0; // the bootstrap's percentile interval for alpha
    double thresholdHigh = 0.0;
    double slopeLow = 0.0;
    double slopeHigh = 0.0;
    uint32_t trials = 0;
    bool converged = true;
};

// Maximum likelihood fit with a lapse rate, then a parametric bootstrap for the intervals.
// Throws std::invalid_argument when `counts` holds no trial.
[[nodiscard]] PsychometricFit fitPsychometric(std::span<const LevelCount> counts,
                                              const FitSettings& settings);

// A group's threshold from its participants' fits: the mean of their thresholds with a bootstrap
// interval over participants (resampling participants), and the pooled fit of all trials.
struct GroupThreshold {
    double mean = 0.0;
    double sd = 0.0;
    double low = 0.0;
    double high = 0.0;
    uint32_t participants = 0;
    PsychometricFit pooled;
};

[[nodiscard]] GroupThreshold poolParticipants(std::span<const PsychometricFit> fits,
                                              std::span<const std::vector<LevelCount>> counts,
                                              const FitSettings& settings);

} // namespace gt::study
