#include "psychometric.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sampling.hpp"

namespace gt::study {

namespace {

// The rising core of each shape, 0.5 at alpha (Kingdom & Prins, Psychophysics, table 4.1). The
// Weibull is scaled by ln 2 so that it too is 0.5 at alpha rather than 1 - 1/e.
double risingCore(PsychometricShape shape, double x, double alpha, double beta) {
    switch (shape) {
    case PsychometricShape::Logistic:
        return 1.0 / (1.0 + std::exp(-beta * (x - alpha)));
    case PsychometricShape::CumulativeNormal:
        return 0.5 * std::erfc(-beta * (x - alpha) / std::sqrt(2.0));
    case PsychometricShape::Weibull:
        if (x <= 0.0 || alpha <= 0.0) return 0.0;
        return 1.0 - std::exp(-std::log(2.0) * std::pow(x / alpha, beta));
    }
    return 0.5;
}

// The x where the rising core equals f, 0 < f < 1.
double risingInverse(PsychometricShape shape, double f, double alpha, double beta) {
    switch (shape) {
    case PsychometricShape::Logistic:
        return alpha + std::log(f / (1.0 - f)) / beta;
    case PsychometricShape::CumulativeNormal: {
        // Bisection on the standard normal's z: erfc has no inverse in the standard library and
        // 200 halvings of [-40, 40] reach the double's resolution.
        double lo = -40.0;
        double hi = 40.0;
        for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
            const double mid = 0.5 * (lo + hi);
            (0.5 * std::erfc(-mid / std::sqrt(2.0)) < f ? lo : hi) = mid;
        }
        return alpha + 0.5 * (lo + hi) / beta;
    }
    case PsychometricShape::Weibull:
        return alpha * std::pow(-std::log(1.0 - f) / std::log(2.0), 1.0 / beta);
    }
    return alpha;
}

} // namespace

double PsychometricFunction::core(double level) const {
    const double rising = risingCore(shape, level, threshold, slope);
    // A falling function is the rising one mirrored about F = 0.5: still 0.5 at alpha.
    return increasing ? rising : 1.0 - rising;
}

double PsychometricFunction::probability(double level) const {
    return guess + (1.0 - guess - lapse) * core(level);
}

double PsychometricFunction::levelAt(double p) const {
    const double span = 1.0 - guess - lapse;
    const double f = span > 0.0 ? (p - guess) / span : -1.0;
    if (!(f > 0.0 && f < 1.0)) {
        throw std::invalid_argument("levelAt: p = " + std::to_string(p) +
                                    " is not between the guess rate and 1 - lapse");
    }
    return risingInverse(shape, increasing ? f : 1.0 - f, threshold, slope);
}

std::vector<LevelCount> countByLevel(std::span<const double> levels,
                                     std::span<const bool> positive) {
    if (levels.size() != positive.size()) {
        throw std::invalid_argument("countByLevel: levels and answers differ in length");
    }
    std::vector<std::pair<double, bool>> trials;
    trials.reserve(levels.size());
    for (std::size_t i = 0; i < levels.size(); ++i)
        trials.emplace_back(levels[i], positive[i]);
    std::ranges::sort(trials, {}, &std::pair<double, bool>::first);
    std::vector<LevelCount> counts;
    for (const auto& [level, yes] : trials) {
        // Levels a grid snapped are equal to the last bit; a relative tolerance also merges
        // levels that took different arithmetic paths to the same grid point.
        const bool same = !counts.empty() && std::abs(level - counts.back().level) <=
                                                 1e-9 * std::max(1.0, std::abs(level));
        if (!same) counts.push_back({level, 0, 0});
        ++counts.back().trials;
        counts.back().positive += yes ? 1 : 0;
    }
    return counts;
}

} // namespace gt::study
