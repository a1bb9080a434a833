#include "psychometric.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
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
        if (x <= 0.0 || alpha <= 0.0) {
            return 0.0;
        }
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

namespace {

// Levels a grid snapped are equal to the last bit; a relative tolerance also merges levels that
// took different arithmetic paths to the same grid point.
bool sameLevel(double a, double b) {
    return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(a));
}

// Counts sorted by level, those at the same level added up.
std::vector<LevelCount> mergeSorted(std::vector<LevelCount> counts) {
    std::ranges::stable_sort(counts, {}, &LevelCount::level);
    std::vector<LevelCount> merged;
    for (const LevelCount& c : counts) {
        if (merged.empty() || !sameLevel(c.level, merged.back().level)) {
            merged.push_back({c.level, 0, 0});
        }
        merged.back().trials += c.trials;
        merged.back().positive += c.positive;
    }
    return merged;
}

template <typename Answers>
std::vector<LevelCount> countTrials(std::span<const double> levels, const Answers& positive) {
    if (levels.size() != positive.size()) {
        throw std::invalid_argument("countByLevel: levels and answers differ in length");
    }
    std::vector<LevelCount> single;
    single.reserve(levels.size());
    for (std::size_t i = 0; i < levels.size(); ++i) {
        single.push_back({levels[i], 1, positive[i] ? 1u : 0u});
    }
    return mergeSorted(std::move(single));
}

} // namespace

std::vector<LevelCount> countByLevel(std::span<const double> levels,
                                     std::span<const bool> positive) {
    return countTrials(levels, positive);
}

std::vector<LevelCount> countByLevel(std::span<const double> levels,
                                     const std::vector<bool>& positive) {
    return countTrials(levels, positive);
}

namespace {

// Probabilities are kept this far from 0 and 1 in the likelihood, so a lapse rate of 0 and a
// steep fit never take the log of 0 (Wichmann & Hill 2001 bound the lapse for the same reason).
constexpr double kProbabilityFloor = 1e-9;

double clampedLog(double p) {
    return std::log(std::clamp(p, kProbabilityFloor, 1.0 - kProbabilityFloor));
}

// The binomial log likelihood of the counts (its constant binomial coefficients left out), plus
// the catch trials' answers, which depend on the guess rate alone.
double logLikelihood(const PsychometricFunction& f, std::span<const LevelCount> counts,
                     const FitSettings& settings) {
    double sum = 0.0;
    for (const LevelCount& c : counts) {
        const double p = f.probability(c.level);
        sum += c.positive * clampedLog(p) + (c.trials - c.positive) * clampedLog(1.0 - p);
    }
    sum += settings.catchPositive * clampedLog(f.guess) +
           (settings.catchTrials - settings.catchPositive) * clampedLog(1.0 - f.guess);
    return std::isfinite(sum) ? sum : -std::numeric_limits<double>::max();
}

// The box the fit searches: alpha over the design's range, log beta over slopes from nearly flat
// to nearly a step across that range, lambda in [0, maxLapse], gamma in [0, kMaxGuess].
struct SearchBox {
    std::array<double, 4> low{};
    std::array<double, 4> high{};
    std::size_t dimensions = 3; // alpha, log beta, lapse (+ guess when fitted)
};

constexpr double kMaxGuess = 0.5;

SearchBox searchBox(const FitSettings& s) {
    SearchBox box;
    const double range = s.levelMax - s.levelMin;
    // The Weibull's beta is a shape without units and its alpha must be positive.
    const bool weibull = s.shape == PsychometricShape::Weibull;
    const double alphaLow = weibull ? std::max(s.levelMin, 1e-9 * s.levelMax) : s.levelMin;
    const double betaLow = weibull ? 0.5 : 0.5 / range;
    const double betaHigh = weibull ? 50.0 : 500.0 / range;
    box.low = {alphaLow, std::log(betaLow), 0.0, 0.0};
    box.high = {s.levelMax, std::log(betaHigh), s.maxLapse, kMaxGuess};
    box.dimensions = s.fitGuess ? 4 : 3;
    return box;
}

using Point = std::array<double, 4>;

Point clampToBox(Point p, const SearchBox& box) {
    for (std::size_t i = 0; i < 4; ++i) {
        p[i] = std::clamp(p[i], box.low[i], box.high[i]);
    }
    return p;
}

PsychometricFunction functionAt(const Point& p, const FitSettings& s) {
    return {s.shape, p[0], std::exp(p[1]), s.fitGuess ? p[3] : s.guess, p[2], s.increasing};
}

// The objective every search minimises: the negative log likelihood at the point projected into
// the box, so the simplex may step outside and still compare points.
struct Objective {
    std::span<const LevelCount> counts;
    const FitSettings& settings;
    SearchBox box;
    double operator()(const Point& p) const {
        return -logLikelihood(functionAt(clampToBox(p, box), settings), counts, settings);
    }
};

} // namespace

namespace {

struct SearchResult {
    Point point{};
    double value = 0.0;
    bool converged = false;
};

// Nelder & Mead's downhill simplex with the standard coefficients (reflection 1, expansion 2,
// contraction 1/2, shrink 1/2) over the box's first `dimensions` coordinates.
SearchResult nelderMead(const Objective& f, Point start, const Point& scale) {
    const std::size_t n = f.box.dimensions;
    std::vector<Point> simplex(n + 1, start);
    std::vector<double> values(n + 1);
    for (std::size_t i = 0; i < n; ++i) {
        simplex[i + 1][i] += scale[i];
    }
    for (std::size_t i = 0; i <= n; ++i) {
        values[i] = f(simplex[i]);
    }
    const auto along = [&](const Point& from, const Point& to, double t) {
        Point p = from;
        for (std::size_t i = 0; i < n; ++i) {
            p[i] = from[i] + t * (to[i] - from[i]);
        }
        return p;
    };
    constexpr int kMaxIterations = 400;
    for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
        std::vector<std::size_t> order(n + 1);
        std::iota(order.begin(), order.end(), 0);
        std::ranges::sort(order, {}, [&](std::size_t i) { return values[i]; });
        const std::size_t best = order.front();
        const std::size_t worst = order.back();
        if (values[worst] - values[best] < 1e-10) {
            return {simplex[best], values[best], true};
        }
        Point centroid{};
        for (std::size_t k = 0; k < n; ++k) {
            for (std::size_t i = 0; i < n; ++i) {
                centroid[i] += simplex[order[k]][i] / n;
            }
        }
        const Point reflected = along(centroid, simplex[worst], -1.0);
        const double reflectedValue = f(reflected);
        if (reflectedValue < values[best]) {
            const Point expanded = along(centroid, simplex[worst], -2.0);
            const double expandedValue = f(expanded);
            const bool expand = expandedValue < reflectedValue;
            simplex[worst] = expand ? expanded : reflected;
            values[worst] = expand ? expandedValue : reflectedValue;
        } else if (reflectedValue < values[order[n - 1]]) {
            simplex[worst] = reflected;
            values[worst] = reflectedValue;
        } else {
            const Point contracted = along(centroid, simplex[worst], 0.5);
            const double contractedValue = f(contracted);
            if (contractedValue < values[worst]) {
                simplex[worst] = contracted;
                values[worst] = contractedValue;
            } else {
                for (std::size_t i = 0; i <= n; ++i) {
                    if (i == best) {
                        continue;
                    }
                    simplex[i] = along(simplex[best], simplex[i], 0.5);
                    values[i] = f(simplex[i]);
                }
            }
        }
    }
    const auto best = std::ranges::min_element(values) - values.begin();
    return {simplex[best], values[best], false};
}

// A coarse grid over the box (alpha x log beta x lapse x guess) to start the simplex near the
// global maximum: the likelihood of a few levels can have more than one local maximum.
// A bootstrap refit, which has its generating function to start from, takes a coarser grid.
SearchResult coarseStart(const Objective& f, bool coarser) {
    const SearchBox& box = f.box;
    const int kAlphas = coarser ? 9 : 21;
    const int kBetas = coarser ? 5 : 10;
    const int lapses = box.high[2] > 0.0 ? (coarser ? 2 : 3) : 1;
    const int guesses = box.dimensions == 4 ? 4 : 1;
    const auto at = [&](std::size_t axis, int i, int count) {
        return count == 1 ? box.low[axis]
                          : box.low[axis] + (box.high[axis] - box.low[axis]) * i / (count - 1);
    };
    SearchResult best{{}, std::numeric_limits<double>::infinity(), false};
    for (int g = 0; g < guesses; ++g) {
        for (int l = 0; l < lapses; ++l) {
            for (int b = 0; b < kBetas; ++b) {
                for (int a = 0; a < kAlphas; ++a) {
                    const Point p{at(0, a, kAlphas), at(1, b, kBetas), at(2, l, lapses),
                                  at(3, g, guesses)};
                    const double v = f(p);
                    if (v < best.value) {
                        best = {p, v, false};
                    }
                }
            }
        }
    }
    return best;
}

// The maximum likelihood parameters of `counts` (Wichmann & Hill 2001): the best of a coarse
// grid (and of `hint`, when given) refined by the simplex, whose steps start at a grid cell.
SearchResult maximumLikelihood(std::span<const LevelCount> counts, const FitSettings& settings,
                               const Point* hint = nullptr) {
    const Objective f{counts, settings, searchBox(settings)};
    SearchResult start = coarseStart(f, hint != nullptr);
    if (hint != nullptr) {
        const double v = f(*hint);
        if (v < start.value) {
            start = {clampToBox(*hint, f.box), v, false};
        }
    }
    Point scale{};
    for (std::size_t i = 0; i < 4; ++i) {
        scale[i] = (f.box.high[i] - f.box.low[i]) / 20.0;
    }
    SearchResult refined = nelderMead(f, start.point, scale);
    if (!(refined.value <= start.value)) {
        refined = {start.point, start.value, false};
    }
    refined.point = clampToBox(refined.point, f.box);
    return refined;
}

} // namespace

namespace {

void checkFitSettings(const FitSettings& s) {
    const auto fail = [](const std::string& what) {
        throw std::invalid_argument("fit setting " + what);
    };
    if (!(std::isfinite(s.levelMin) && std::isfinite(s.levelMax) && s.levelMin < s.levelMax)) {
        fail("'levelMax' must be above 'levelMin'");
    }
    if (!(s.maxLapse >= 0.0 && s.maxLapse < 0.5)) {
        fail("'maxLapse' must be in [0, 0.5)");
    }
    if (!(s.guess >= 0.0 && s.guess < 1.0)) {
        fail("'guess' must be in [0, 1)");
    }
    if (!(s.confidence > 0.0 && s.confidence < 1.0)) {
        fail("'confidence' must be in (0, 1)");
    }
    if (s.catchPositive > s.catchTrials) {
        fail("'catchPositive' exceeds 'catchTrials'");
    }
}

// The q-quantile of sorted values, interpolated linearly between order statistics (Hyndman &
// Fan's type 7), the percentile bootstrap's interval ends (Efron & Tibshirani 1993, 13.3).
double quantile(const std::vector<double>& sorted, double q) {
    const double position = q * static_cast<double>(sorted.size() - 1);
    const auto below = static_cast<std::size_t>(std::floor(position));
    const std::size_t above = std::min(below + 1, sorted.size() - 1);
    return sorted[below] +
           (position - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

uint32_t binomialDraw(uint32_t trials, double p, std::mt19937_64& random) {
    uint32_t positive = 0;
    for (uint32_t t = 0; t < trials; ++t) {
        positive += uniform01(random) < p ? 1 : 0;
    }
    return positive;
}

// One parametric bootstrap set (Wichmann & Hill 2001b): simulated observers that follow
// `generating` answer the same number of trials at the observed levels (and the catch trials at
// its guess rate); each data set is refitted. Returns the refitted alphas and betas, sorted.
struct BootstrapSet {
    std::vector<double> alphas;
    std::vector<double> betas;
};

BootstrapSet bootstrapSet(const PsychometricFunction& generating,
                          std::span<const LevelCount> counts, const FitSettings& settings,
                          std::mt19937_64& random) {
    std::vector<LevelCount> resample(counts.begin(), counts.end());
    FitSettings refit = settings;
    const Point hint{generating.threshold, std::log(generating.slope), generating.lapse,
                     generating.guess};
    BootstrapSet set;
    for (uint32_t b = 0; b < settings.bootstrap; ++b) {
        for (LevelCount& c : resample) {
            c.positive = binomialDraw(c.trials, generating.probability(c.level), random);
        }
        refit.catchPositive = binomialDraw(settings.catchTrials, generating.guess, random);
        const SearchResult r = maximumLikelihood(resample, refit, &hint);
        set.alphas.push_back(r.point[0]);
        set.betas.push_back(std::exp(r.point[1]));
    }
    std::ranges::sort(set.alphas);
    std::ranges::sort(set.betas);
    return set;
}

// The percentile intervals of the bootstrap from the fitted function, widened by Wichmann &
// Hill 2001b's sensitivity analysis of the "bootstrap bridging assumption": the spread of the
// refits depends on the generating function, and a fitted slope steeper than the observer's
// (common when an adaptive run puts its trials near threshold) gives intervals too narrow. So
// further sets are drawn from functions at the corners of the first set's 68 % region of alpha
// and beta, each set's spread around its generating values is laid around the fit, and the
// widest extent on each side is the interval.
void bootstrapIntervals(PsychometricFit& fit, std::span<const LevelCount> counts,
                        const FitSettings& settings) {
    const PsychometricFunction fitted = fit.function;
    fit.thresholdLow = fit.thresholdHigh = fitted.threshold;
    fit.slopeLow = fit.slopeHigh = fitted.slope;
    if (settings.bootstrap == 0) {
        return;
    }
    std::mt19937_64 random(mixSeed(settings.seed, 0xB007));
    const double tail = (1.0 - settings.confidence) / 2.0;
    const auto widen = [&](const BootstrapSet& set, const PsychometricFunction& generating) {
        fit.thresholdLow = std::min(fit.thresholdLow, fitted.threshold - generating.threshold +
                                                          quantile(set.alphas, tail));
        fit.thresholdHigh = std::max(fit.thresholdHigh, fitted.threshold - generating.threshold +
                                                            quantile(set.alphas, 1.0 - tail));
        // Slopes spread in proportion to their size: their deviations are ratios.
        const double ratio = fitted.slope / generating.slope;
        fit.slopeLow = std::min(fit.slopeLow, ratio * quantile(set.betas, tail));
        fit.slopeHigh = std::max(fit.slopeHigh, ratio * quantile(set.betas, 1.0 - tail));
    };
    const BootstrapSet first = bootstrapSet(fitted, counts, settings, random);
    widen(first, fitted);
    if (!settings.sensitivity) {
        return;
    }
    constexpr double kRegion = 0.68;
    const double lowQ = (1.0 - kRegion) / 2.0;
    for (const double qa : {lowQ, 1.0 - lowQ}) {
        for (const double qb : {lowQ, 1.0 - lowQ}) {
            PsychometricFunction generating = fitted;
            generating.threshold = quantile(first.alphas, qa);
            generating.slope = quantile(first.betas, qb);
            widen(bootstrapSet(generating, counts, settings, random), generating);
        }
    }
}

} // namespace

PsychometricFit fitPsychometric(std::span<const LevelCount> counts, const FitSettings& settings) {
    checkFitSettings(settings);
    uint32_t trials = 0;
    for (const LevelCount& c : counts) {
        if (c.positive > c.trials || !std::isfinite(c.level)) {
            throw std::invalid_argument("fitPsychometric: a level count is not a count");
        }
        trials += c.trials;
    }
    if (trials == 0) {
        throw std::invalid_argument("fitPsychometric: no trials to fit");
    }
    const SearchResult best = maximumLikelihood(counts, settings);
    PsychometricFit fit;
    fit.function = functionAt(best.point, settings);
    fit.logLikelihood = -best.value;
    fit.trials = trials;
    fit.converged = best.converged;
    bootstrapIntervals(fit, counts, settings);
    return fit;
}

namespace {

// All participants' counts merged level by level.
std::vector<LevelCount> mergeCounts(std::span<const std::vector<LevelCount>> counts) {
    std::vector<LevelCount> all;
    for (const std::vector<LevelCount>& participant : counts) {
        all.insert(all.end(), participant.begin(), participant.end());
    }
    return mergeSorted(std::move(all));
}

} // namespace

GroupThreshold poolParticipants(std::span<const PsychometricFit> fits,
                                std::span<const std::vector<LevelCount>> counts,
                                const FitSettings& settings) {
    if (fits.empty()) {
        throw std::invalid_argument("poolParticipants: no participant's fit");
    }
    checkFitSettings(settings);
    GroupThreshold group;
    group.participants = static_cast<uint32_t>(fits.size());
    const double n = static_cast<double>(fits.size());
    for (const PsychometricFit& f : fits) {
        group.mean += f.function.threshold / n;
    }
    double squares = 0.0;
    for (const PsychometricFit& f : fits) {
        squares += (f.function.threshold - group.mean) * (f.function.threshold - group.mean);
    }
    group.sd = fits.size() > 1 ? std::sqrt(squares / (n - 1.0)) : 0.0;
    // The interval of the group mean: participants resampled with replacement (Efron &
    // Tibshirani 1993), the percentiles of the resampled means.
    group.low = group.high = group.mean;
    if (settings.bootstrap > 0) {
        std::mt19937_64 random(mixSeed(settings.seed, 0x9A07));
        std::vector<double> means;
        for (uint32_t b = 0; b < settings.bootstrap; ++b) {
            double sum = 0.0;
            for (std::size_t i = 0; i < fits.size(); ++i) {
                sum += fits[uniformIndex(random, fits.size())].function.threshold;
            }
            means.push_back(sum / n);
        }
        std::ranges::sort(means);
        const double tail = (1.0 - settings.confidence) / 2.0;
        group.low = quantile(means, tail);
        group.high = quantile(means, 1.0 - tail);
    }
    const std::vector<LevelCount> all = mergeCounts(counts);
    if (!all.empty()) {
        group.pooled = fitPsychometric(all, settings);
    }
    return group;
}

} // namespace gt::study
