#include "placement.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sampling.hpp"

namespace gt::study {

namespace {

// Grid arithmetic is done in whole steps from `min`, so every visit to a grid point gives the
// same double and levels can be grouped by equality.
std::size_t stepCount(const LevelGrid& grid) {
    return static_cast<std::size_t>(std::floor((grid.max - grid.min) / grid.step + 1e-9));
}

} // namespace

double LevelGrid::snap(double level) const {
    if (!values.empty()) {
        const auto nearest =
            std::ranges::min_element(values, {}, [level](double v) { return std::abs(v - level); });
        return *nearest;
    }
    const double clamped = std::clamp(level, min, max);
    if (step <= 0.0) {
        return clamped;
    }
    const double index =
        std::clamp(std::round((clamped - min) / step), 0.0, static_cast<double>(stepCount(*this)));
    return min + index * step;
}

std::vector<double> LevelGrid::all() const {
    if (!values.empty()) {
        return values;
    }
    std::vector<double> levels;
    if (step > 0.0) {
        const std::size_t n = stepCount(*this);
        for (std::size_t i = 0; i <= n; ++i) {
            levels.push_back(min + static_cast<double>(i) * step);
        }
        return levels;
    }
    constexpr int kContinuousLevels = 64;
    for (int i = 0; i < kContinuousLevels; ++i) {
        levels.push_back(min + (max - min) * i / (kContinuousLevels - 1));
    }
    return levels;
}

namespace {

template <typename T> std::string text(T value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

void require(bool ok, const char* setting, const std::string& rule) {
    if (!ok) {
        throw std::invalid_argument(std::string("placement setting '") + setting + "' " + rule);
    }
}

void checkGrid(const LevelGrid& grid) {
    if (!grid.values.empty()) {
        require(std::ranges::is_sorted(grid.values), "grid.values", "must be sorted");
        require(std::ranges::all_of(grid.values, [](double v) { return std::isfinite(v); }),
                "grid.values", "must be finite");
        return;
    }
    require(std::isfinite(grid.min) && std::isfinite(grid.max) && grid.min < grid.max, "grid.max",
            "must be above grid.min (got " + text(grid.min) + " to " + text(grid.max) + ")");
    require(std::isfinite(grid.step) && grid.step >= 0.0, "grid.step",
            "must be >= 0 (got " + text(grid.step) + ")");
}

double gridLow(const LevelGrid& grid) {
    return grid.values.empty() ? grid.min : grid.values.front();
}
double gridHigh(const LevelGrid& grid) {
    return grid.values.empty() ? grid.max : grid.values.back();
}

void checkStaircase(const PlacementSettings& s) {
    require(s.start >= gridLow(s.grid) && s.start <= gridHigh(s.grid), "start",
            "must lie on the grid [" + text(gridLow(s.grid)) + ", " + text(gridHigh(s.grid)) +
                "] (got " + text(s.start) + ")");
    require(std::isfinite(s.step) && s.step > 0.0, "step",
            "must be > 0 (got " + text(s.step) + ")");
    require(std::isfinite(s.finalStep) && s.finalStep > 0.0, "finalStep",
            "must be > 0 (got " + text(s.finalStep) + ")");
    require(s.reversals >= 1, "reversals", "must be at least 1");
}

void checkSettings(const PlacementSettings& s) {
    checkGrid(s.grid);
    require(s.maxTrials >= 1, "maxTrials", "must be at least 1");
    switch (s.kind) {
    case PlacementKind::Staircase:
        checkStaircase(s);
        require(s.down >= 1, "down", "must be at least 1");
        require(s.up >= 1, "up", "must be at least 1");
        break;
    case PlacementKind::WeightedStaircase:
        checkStaircase(s);
        require(s.target > 0.0 && s.target < 1.0, "target",
                "must be between 0 and 1 (got " + text(s.target) + ")");
        break;
    case PlacementKind::ThesisSeries:
        checkStaircase(s);
        break;
    case PlacementKind::QuestPlus:
        require(!s.questSlopes.empty() &&
                    std::ranges::all_of(s.questSlopes, [](double b) { return b > 0.0; }),
                "questSlopes", "must list at least one slope, each > 0");
        require(
            !s.questLapses.empty() &&
                std::ranges::all_of(s.questLapses, [](double l) { return l >= 0.0 && l < 0.5; }),
            "questLapses", "must list at least one lapse rate, each in [0, 0.5)");
        require(s.guess >= 0.0 && s.guess < 1.0, "guess",
                "must be in [0, 1) (got " + text(s.guess) + ")");
        break;
    case PlacementKind::ConstantStimuli:
        require(s.repeats >= 1, "repeats", "must be at least 1");
        break;
    }
}

} // namespace

namespace {

// The rules that tell the up-down procedures apart.
struct StaircaseRules {
    uint32_t down = 2;        // positives in a row before a step towards less foveation (harder)
    uint32_t up = 1;          // negatives in a row before a step towards more foveation (easier)
    double easierRatio = 1.0; // easier step / harder step (Kaernbach 1991)
    uint32_t skip = 2;        // reversals taken with `step`, not averaged; then `finalStep`
    bool ascending = false;   // the thesis's series: it starts as an ascending (easier) run
};

// The up-down staircases: Levitt 1971's transformed n-down m-up rule, Kaernbach 1991's weighted
// steps and the thesis 6.2's ascending series share one track. The track moves in continuous
// parameter units within the grid's range; each trial shows its nearest grid level, and a
// reversal is the level shown on the trial whose answer turned the track around.
class Staircase final : public LevelPlacement {
public:
    Staircase(PlacementSettings settings, StaircaseRules rules)
        : mSettings(std::move(settings)), mRules(rules), mTrack(mSettings.start),
          mHarderSign(mSettings.higherFoveatesMore ? -1.0 : 1.0),
          mLastMove(rules.ascending ? kEasier : 0) {}

    [[nodiscard]] double next() const override { return mSettings.grid.snap(mTrack); }

    void record(double level, bool positive) override {
        ++mTrials;
        if (positive) {
            mNegativeRun = 0;
            if (++mPositiveRun >= mRules.down) {
                mPositiveRun = 0;
                move(kHarder, level);
            }
        } else {
            mPositiveRun = 0;
            if (++mNegativeRun >= mRules.up) {
                mNegativeRun = 0;
                move(kEasier, level);
            }
        }
    }

    [[nodiscard]] bool finished() const override {
        return counted() >= mSettings.reversals || mTrials >= mSettings.maxTrials;
    }

    [[nodiscard]] std::optional<double> estimate() const override {
        if (counted() == 0) {
            return std::nullopt;
        }
        double sum = 0.0;
        for (std::size_t i = mRules.skip; i < mReversals.size(); ++i) {
            sum += mReversals[i];
        }
        return sum / static_cast<double>(counted());
    }

    [[nodiscard]] std::vector<double> reversals() const override { return mReversals; }
    [[nodiscard]] uint32_t trials() const override { return mTrials; }

private:
    static constexpr int kHarder = 1;
    static constexpr int kEasier = -1;

    [[nodiscard]] uint32_t counted() const {
        const auto all = static_cast<uint32_t>(mReversals.size());
        return all > mRules.skip ? all - mRules.skip : 0;
    }

    void move(int direction, double level) {
        if (mLastMove != 0 && direction != mLastMove) {
            mReversals.push_back(level);
        }
        mLastMove = direction;
        // The step shrinks once the skipped reversals are behind (Levitt 1971; the thesis 6.2:
        // 0.2 until its first reversal, then 0.1).
        const double base = mReversals.size() < mRules.skip ? mSettings.step : mSettings.finalStep;
        const double size = direction == kHarder ? base : base * mRules.easierRatio;
        const LevelGrid& grid = mSettings.grid;
        const double low = grid.values.empty() ? grid.min : grid.values.front();
        const double high = grid.values.empty() ? grid.max : grid.values.back();
        mTrack = std::clamp(mTrack + direction * mHarderSign * size, low, high);
    }

    PlacementSettings mSettings;
    StaircaseRules mRules;
    double mTrack;
    double mHarderSign; // the sign of a step towards less foveation in parameter units
    int mLastMove;
    uint32_t mPositiveRun = 0;
    uint32_t mNegativeRun = 0;
    uint32_t mTrials = 0;
    std::vector<double> mReversals;
};

// The method of constant stimuli (the thesis 2.6; Guenter et al. 2012's pair and ramp tests):
// every grid level `repeats` times in an order shuffled with the seed.
class ConstantStimuli final : public LevelPlacement {
public:
    ConstantStimuli(const PlacementSettings& settings, uint64_t seed) : mLimit(settings.maxTrials) {
        const std::vector<double> levels = settings.grid.all();
        for (uint32_t r = 0; r < settings.repeats; ++r) {
            mOrder.insert(mOrder.end(), levels.begin(), levels.end());
        }
        std::mt19937_64 random(mixSeed(seed, 0xC5));
        shuffleInPlace(mOrder, random);
        mLimit = std::min<std::size_t>(mLimit, mOrder.size());
    }

    [[nodiscard]] double next() const override {
        return mOrder[std::min<std::size_t>(mTrials, mOrder.size() - 1)];
    }
    void record(double, bool) override { ++mTrials; }
    [[nodiscard]] bool finished() const override { return mTrials >= mLimit; }
    [[nodiscard]] std::optional<double> estimate() const override { return std::nullopt; }
    [[nodiscard]] std::vector<double> reversals() const override { return {}; }
    [[nodiscard]] uint32_t trials() const override { return mTrials; }

private:
    std::vector<double> mOrder;
    std::size_t mLimit;
    uint32_t mTrials = 0;
};

// Watson 2017's QUEST+ for one binary answer: a posterior over a grid of psychometric functions
// (thresholds at the grid's levels x questSlopes x questLapses, a uniform prior), each trial at
// the grid level whose two possible answers leave the least expected posterior entropy, or,
// with questThresholdEntropy, the least expected entropy of the threshold's
// marginal posterior, slope and lapse treated as nuisance parameters (the `marginalize` option
// of Brainard's mQUESTPlus implementation). The estimate is the posterior mean of the threshold
// (marginalised over slope and lapse), which moves smoothly where the marginal mode would jump
// between grid levels.
class QuestPlus final : public LevelPlacement {
public:
    explicit QuestPlus(const PlacementSettings& settings)
        : mStimuli(settings.grid.all()), mLimit(settings.maxTrials) {
        for (double threshold : mStimuli) {
            for (double slope : settings.questSlopes) {
                for (double lapse : settings.questLapses) {
                    mFunctions.push_back({settings.shape, threshold, slope, settings.guess, lapse,
                                          settings.higherFoveatesMore});
                }
            }
        }
        if (settings.questThresholdEntropy) {
            mBlock = settings.questSlopes.size() * settings.questLapses.size();
        }
        mPosterior.assign(mFunctions.size(), 1.0 / static_cast<double>(mFunctions.size()));
        mLikelihood.reserve(mStimuli.size() * mFunctions.size());
        for (double x : mStimuli) {
            for (const PsychometricFunction& f : mFunctions) {
                mLikelihood.push_back(f.probability(x));
            }
        }
        mNext = bestStimulus();
    }

    [[nodiscard]] double next() const override { return mNext; }

    void record(double level, bool positive) override {
        ++mTrials;
        double total = 0.0;
        for (std::size_t j = 0; j < mFunctions.size(); ++j) {
            const double p = mFunctions[j].probability(level);
            mPosterior[j] *= positive ? p : 1.0 - p;
            total += mPosterior[j];
        }
        // An answer every function calls impossible (lapse 0 at a level where psi is 0 or 1)
        // would empty the posterior: keep the prior belief rather than divide by zero.
        if (total > 0.0 && std::isfinite(total)) {
            for (double& w : mPosterior) {
                w /= total;
            }
        }
        mNext = bestStimulus();
    }

    [[nodiscard]] bool finished() const override { return mTrials >= mLimit; }

    [[nodiscard]] std::optional<double> estimate() const override {
        if (mTrials == 0) {
            return std::nullopt;
        }
        double mean = 0.0;
        for (std::size_t j = 0; j < mFunctions.size(); ++j) {
            mean += mPosterior[j] * mFunctions[j].threshold;
        }
        return mean;
    }

    [[nodiscard]] std::vector<double> reversals() const override { return {}; }
    [[nodiscard]] uint32_t trials() const override { return mTrials; }

private:
    // The entropy of the posterior the weights (summing to `total`) make; over the thresholds
    // alone when the settings marginalise slope and lapse (blocks of `mBlock` functions share a
    // threshold).
    [[nodiscard]] double entropy(std::span<const double> weights, double total) const {
        double h = 0.0;
        for (std::size_t start = 0; start < weights.size(); start += mBlock) {
            const std::size_t end = std::min(start + mBlock, weights.size());
            if (mBlock == 1) {
                const double p = weights[start] / total;
                if (p > 0.0) {
                    h -= p * std::log(p);
                }
                continue;
            }
            double p = 0.0;
            for (std::size_t j = start; j < end; ++j) {
                p += weights[j];
            }
            p /= total;
            if (p > 0.0) {
                h -= p * std::log(p);
            }
        }
        return h;
    }

    // The stimulus minimising the expected entropy of the next posterior; ties go to the first.
    [[nodiscard]] double bestStimulus() const {
        const std::size_t n = mFunctions.size();
        std::vector<double> yes(n);
        std::vector<double> no(n);
        double best = std::numeric_limits<double>::infinity();
        std::size_t bestIndex = 0;
        for (std::size_t s = 0; s < mStimuli.size(); ++s) {
            double pYes = 0.0;
            for (std::size_t j = 0; j < n; ++j) {
                yes[j] = mPosterior[j] * mLikelihood[s * n + j];
                no[j] = mPosterior[j] - yes[j];
                pYes += yes[j];
            }
            const double pNo = 1.0 - pYes;
            double expected = 0.0;
            if (pYes > 0.0) {
                expected += pYes * entropy(yes, pYes);
            }
            if (pNo > 0.0) {
                expected += pNo * entropy(no, pNo);
            }
            if (expected < best - 1e-12) {
                best = expected;
                bestIndex = s;
            }
        }
        return mStimuli[bestIndex];
    }

    std::vector<double> mStimuli;
    std::vector<PsychometricFunction> mFunctions;
    std::vector<double> mPosterior;
    std::vector<double> mLikelihood; // [stimulus][function]: psi
    std::size_t mBlock = 1;          // functions per entropy term: 1, or all that share a threshold
    uint32_t mLimit;
    uint32_t mTrials = 0;
    double mNext = 0.0;
};

} // namespace

std::unique_ptr<LevelPlacement> makePlacement(const PlacementSettings& settings, uint64_t seed) {
    checkSettings(settings);
    switch (settings.kind) {
    case PlacementKind::Staircase:
        return std::make_unique<Staircase>(
            settings, StaircaseRules{settings.down, settings.up, 1.0, settings.skipReversals});
    case PlacementKind::WeightedStaircase:
        // Kaernbach 1991: one step after every answer, step up / step down = p / (1 - p), so the
        // expected drift p * down - (1 - p) * up vanishes where psi = p.
        return std::make_unique<Staircase>(
            settings, StaircaseRules{1, 1, settings.target / (1.0 - settings.target),
                                     settings.skipReversals});
    case PlacementKind::ThesisSeries:
        // The thesis 6.2: an ascending series in steps of `step` whose first reversal is not
        // counted, then a plain 1-up-1-down staircase in steps of `finalStep`.
        return std::make_unique<Staircase>(settings, StaircaseRules{1, 1, 1.0, 1, true});
    case PlacementKind::QuestPlus:
        return std::make_unique<QuestPlus>(settings);
    case PlacementKind::ConstantStimuli:
        return std::make_unique<ConstantStimuli>(settings, seed);
    }
    throw std::invalid_argument("placement setting 'kind' is not a placement");
}

} // namespace gt::study
