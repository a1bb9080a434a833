#include "session.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <random>
#include <utility>

#include "placement.hpp"
#include "sampling.hpp"

namespace gt::study {

namespace {

using nlohmann::json;

// ---------------------------------------------------------------------------------------------
// The plan: which trial comes next, from (seed, trial index) and what was answered so far.

struct PlannedTrial {
    uint32_t index = 0;
    std::size_t condition = 0;
    std::size_t block = 0; // the condition's block when conditions run one after another
    bool practice = false;
    double level = 0.0;
    bool conditionFirst = true;
    bool catchTrial = false;
    bool rampUp = true;
    uint32_t attempt = 0; // repeats before this one
    uint32_t scene = 0;
    uint32_t repeatDelay = 1; // trials until it comes back, if it is repeated
};

// A trial that was cut short and comes back.
struct Deferred {
    std::size_t condition = 0;
    bool practice = false;
    uint32_t due = 0;
    uint32_t attempts = 0;
};

double mostFoveated(const Condition& c) {
    return c.placement.higherFoveatesMore ? c.placement.grid.all().back()
                                          : c.placement.grid.all().front();
}

class Planner {
public:
    Planner(const StudyDesign& design, uint64_t seed) : mDesign(design), mSeed(seed) {
        for (std::size_t c = 0; c < design.conditions.size(); ++c) {
            const Condition& condition = design.conditions[c];
            mPracticeLeft.push_back(design.practiceTrials);
            mEnded.push_back(0);
            mSliderDone.push_back(0);
            mPlacements.push_back(
                design.procedure == Procedure::Slider
                    ? nullptr
                    : makePlacement(condition.placement, mixSeed(seed, 0x5EED + c)));
        }
    }

    // The trial at index `slot`, or empty when the plan is done.
    [[nodiscard]] std::optional<PlannedTrial> next(uint32_t slot) const {
        std::mt19937_64 random(mixSeed(mSeed, slot));
        const uint64_t pick = random();
        bool first = (random() & 1U) != 0;
        const double catchDraw = uniform01(random);
        bool rampUp = (random() & 1U) != 0;
        const auto delay = static_cast<uint32_t>(1 + uniformIndex(random, 3));

        PlannedTrial t;
        t.index = slot;
        t.repeatDelay = delay;
        if (!choose(slot, pick, t)) {
            return std::nullopt;
        }
        const Condition& c = mDesign.conditions[t.condition];
        const Procedure p = mDesign.procedure;
        // Practice and the slider's start: the easiest level, the most foveated.
        t.level = t.practice || p == Procedure::Slider ? mostFoveated(c)
                                                       : mPlacements[t.condition]->next();
        if (const std::optional<bool> b = balanced(t)) {
            // Guenter et al. 2012: each pair "in both orders", each ramp "in both directions".
            first = *b;
            rampUp = *b;
        }
        t.conditionFirst = p == Procedure::ForcedChoice || p == Procedure::Pair ? first : true;
        t.catchTrial = p == Procedure::YesNo && !t.practice && catchDraw < mDesign.catchRate;
        t.rampUp = p == Procedure::Ramp ? rampUp : true;
        t.scene = static_cast<uint32_t>(mEnded[t.condition] % mDesign.scenes.size());
        return t;
    }

    void ended(const PlannedTrial& t, double level, bool positive) {
        eraseDeferred(t);
        if (t.practice) {
            --mPracticeLeft[t.condition];
        } else if (mPlacements[t.condition] == nullptr) {
            ++mSliderDone[t.condition];
        } else if (!t.catchTrial) {
            mPlacements[t.condition]->record(level, positive);
        }
        ++mEnded[t.condition];
        if (!t.practice) {
            ++mShownAt[{t.condition, t.level}];
        }
        mSlots = t.index + 1;
    }

    void repeated(const PlannedTrial& t) {
        eraseDeferred(t);
        mDeferred.push_back({t.condition, t.practice, t.index + t.repeatDelay, t.attempt + 1});
        mSlots = t.index + 1;
    }

    [[nodiscard]] uint32_t slots() const { return mSlots; }

    [[nodiscard]] uint32_t remaining() const {
        uint64_t n = mDeferred.size();
        for (std::size_t c = 0; c < mPlacements.size(); ++c) {
            n += mPracticeLeft[c];
            if (mPlacements[c] == nullptr) {
                n += mDesign.conditions[c].placement.repeats - mSliderDone[c];
            } else if (!mPlacements[c]->finished()) {
                const PlacementSettings& s = mDesign.conditions[c].placement;
                uint64_t most = s.maxTrials;
                if (s.kind == PlacementKind::ConstantStimuli) {
                    most = std::min<uint64_t>(most, s.grid.all().size() * s.repeats);
                }
                n += most > mPlacements[c]->trials() ? most - mPlacements[c]->trials() : 0;
            }
        }
        return static_cast<uint32_t>(n);
    }

    [[nodiscard]] const LevelPlacement* placement(std::size_t c) const {
        return mPlacements[c].get();
    }

private:
    // Constant stimuli: the order (or direction) alternates over a level's presentations,
    // starting from a coin drawn per condition and level, so two repeats show both.
    [[nodiscard]] std::optional<bool> balanced(const PlannedTrial& t) const {
        const PlacementSettings& s = mDesign.conditions[t.condition].placement;
        if (t.practice || s.kind != PlacementKind::ConstantStimuli) {
            return std::nullopt;
        }
        const auto it = mShownAt.find({t.condition, t.level});
        const uint64_t shown = it == mShownAt.end() ? 0 : it->second;
        const uint64_t coin =
            mixSeed(mSeed ^ std::bit_cast<uint64_t>(t.level), 0xBA1A + t.condition) & 1U;
        return (shown + coin) % 2 == 0;
    }

    [[nodiscard]] bool mainLeft(std::size_t c) const {
        return mPlacements[c] == nullptr ? mSliderDone[c] < mDesign.conditions[c].placement.repeats
                                         : !mPlacements[c]->finished();
    }
    [[nodiscard]] bool deferred(std::size_t c) const {
        return std::ranges::any_of(mDeferred, [c](const Deferred& d) { return d.condition == c; });
    }
    [[nodiscard]] bool blockLeft(std::size_t c) const {
        return mPracticeLeft[c] > 0 || deferred(c) || mainLeft(c);
    }

    // The condition of trial `slot`: a repeat that is due, else one drawn from those with
    // trials left (practice first), else a repeat that is not due yet.
    bool choose(uint32_t slot, uint64_t pick, PlannedTrial& t) const {
        const std::size_t n = mDesign.conditions.size();
        std::size_t block = 0;
        if (mDesign.breakBetweenConditions) {
            while (block < n && !blockLeft(block)) {
                ++block;
            }
            if (block == n) {
                return false;
            }
        }
        auto inScope = [&](std::size_t c) { return !mDesign.breakBetweenConditions || c == block; };
        t.block = block;
        for (const Deferred& d : mDeferred) {
            if (inScope(d.condition) && d.due <= slot) {
                return take(d, t);
            }
        }
        bool practice = false;
        for (std::size_t c = 0; c < n; ++c) {
            practice = practice || (inScope(c) && mPracticeLeft[c] > 0);
        }
        std::vector<std::size_t> candidates;
        for (std::size_t c = 0; c < n; ++c) {
            if (!inScope(c) || deferred(c)) {
                continue;
            }
            if (practice ? mPracticeLeft[c] > 0 : mainLeft(c)) {
                candidates.push_back(c);
            }
        }
        if (!candidates.empty()) {
            t.condition = candidates[pick % candidates.size()];
            t.practice = practice;
            return true;
        }
        for (const Deferred& d : mDeferred) {
            if (inScope(d.condition)) {
                return take(d, t);
            }
        }
        return false;
    }

    static bool take(const Deferred& d, PlannedTrial& t) {
        t.condition = d.condition;
        t.practice = d.practice;
        t.attempt = d.attempts;
        return true;
    }

    void eraseDeferred(const PlannedTrial& t) {
        std::erase_if(mDeferred, [&t](const Deferred& d) {
            return d.condition == t.condition && d.practice == t.practice;
        });
    }

    const StudyDesign& mDesign;
    uint64_t mSeed;
    std::vector<std::unique_ptr<LevelPlacement>> mPlacements;
    std::vector<uint32_t> mPracticeLeft;
    std::vector<uint32_t> mSliderDone;
    std::vector<uint64_t> mEnded;
    std::map<std::pair<std::size_t, double>, uint64_t> mShownAt; // non-practice trials per level
    std::vector<Deferred> mDeferred;
    uint32_t mSlots = 0;
};

// ---------------------------------------------------------------------------------------------
// Small helpers.

std::string nowUtc() {
    const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm tm{};
    gmtime_r(&now, &tm);
    std::array<char, 32> text{};
    std::strftime(text.data(), text.size(), "%Y-%m-%dT%H:%M:%SZ", &tm);
    return text.data();
}

uint64_t randomWord() {
    std::random_device device;
    return (static_cast<uint64_t>(device()) << 32U) ^ device();
}

std::string hex16(uint64_t v) {
    std::array<char, 17> text{};
    std::snprintf(text.data(), text.size(), "%016llx", static_cast<unsigned long long>(v));
    return text.data();
}

bool validParticipant(const std::string& code) {
    return !code.empty() && code.size() <= 32 && std::ranges::all_of(code, [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
               c == '_' || c == '-';
    });
}

double distanceDeg(const GazeAngles& a, const GazeAngles& b) {
    return std::hypot(a.xDeg - b.xDeg, a.yDeg - b.yDeg);
}

void addFlag(std::vector<std::string>& flags, const std::string& flag) {
    if (std::ranges::find(flags, flag) == flags.end()) {
        flags.push_back(flag);
    }
}

constexpr std::array<Response, 10> kResponses{
    Response::First, Response::Second, Response::Same,      Response::Yes,    Response::No,
    Response::Up,    Response::Down,   Response::Reference, Response::Accept, Response::Continue};

// What one interval of a trial shows.
struct IntervalPlan {
    std::string shown;
    Stimulus stimulus;
};

// The answer given since the previous frame, until a phase takes it (a plain pair: GCC warns of
// an uninitialised std::optional<enum> here).
struct Pending {
    Response value = Response::Continue;
    bool given = false;
};

// Latency sums per recorded interval, for the mean.
struct LatencySum {
    double sum = 0.0;
    uint32_t count = 0;
};

} // namespace

// ---------------------------------------------------------------------------------------------

std::string responseName(Response r) {
    switch (r) {
    case Response::First:
        return "first";
    case Response::Second:
        return "second";
    case Response::Same:
        return "same";
    case Response::Yes:
        return "yes";
    case Response::No:
        return "no";
    case Response::Up:
        return "up";
    case Response::Down:
        return "down";
    case Response::Reference:
        return "reference";
    case Response::Accept:
        return "accept";
    case Response::Continue:
        return "continue";
    }
    return "?";
}

std::optional<Response> responseNamed(std::string_view name) {
    for (const Response r : kResponses) {
        if (responseName(r) == name) {
            return r;
        }
    }
    return std::nullopt;
}

struct StudySession::State {
    StudyDesign design;
    SessionSettings settings;
    Journal& journal;
    uint64_t seed = 0;
    double periodMs = 1000.0 / 60.0;
    std::unique_ptr<Planner> planner;
    uint32_t trialsDone = 0;

    Phase phase = Phase::Instructions;
    double phaseStart = 0.0;
    std::optional<PlannedTrial> trial; // planned: in progress, or waiting behind a break
    std::size_t block = 0;
    std::vector<IntervalPlan> intervals;
    std::size_t interval = 0; // the one shown (or next)
    TrialRecord record;
    std::vector<LatencySum> latency;
    std::optional<double> fixationHeldSince;
    std::optional<double> gazeMissingSince;
    double responseStart = 0.0;
    bool repeatedLast = false; // the trial before this one was cut short (the prompt says why)
    // Slider: the level shown, the last change, the recorded level.
    double sliderLevel = 0.0;
    bool sliderLastUp = false;
    std::optional<double> sliderRecorded;

    // The previous frame, for dropped frames, latency and the saccade rule.
    std::optional<double> prevTime;
    std::optional<GazeAngles> prevGaze;
    std::optional<std::size_t> prevSegment; // the record's interval that frame was shown in

    State(StudyDesign d, SessionSettings s, Journal& j)
        : design(std::move(d)), settings(std::move(s)), journal(j) {}

    [[nodiscard]] const Condition& condition() const { return design.conditions[trial->condition]; }
    [[nodiscard]] double half() const { return periodMs / 2.0; }
    [[nodiscard]] bool expired(double t, double durationMs) const {
        return t - phaseStart >= durationMs - half();
    }

    [[nodiscard]] Stimulus conditionAt(double level) const {
        return {withLevel(condition().base, condition().vary, level), design.scenes[trial->scene]};
    }
    [[nodiscard]] Stimulus comparison() const {
        return {comparisonOf(condition()), design.scenes[trial->scene]};
    }

    // ----- the trial's intervals -----

    // The ramp's high-quality end: the comparison's value of the varied parameter, or the
    // least foveated level (Guenter et al. 2012 ramp from and to j0 = 22, a foveated frame).
    [[nodiscard]] double rampEnd(const Condition& c) const {
        if (c.comparison && c.comparison->method != Method::Reference) {
            const RenderChoice& r = *c.comparison;
            switch (c.vary) {
            case Parameter::Scale:
                return r.scale;
            case Parameter::RaysPerPoint:
                return r.raysPerPoint;
            case Parameter::K:
                return r.k;
            case Parameter::Slope:
                return r.slope;
            case Parameter::Layers:
                return r.layers;
            }
        }
        return c.placement.higherFoveatesMore ? c.placement.grid.all().front()
                                              : c.placement.grid.all().back();
    }

    [[nodiscard]] std::vector<double> rampLevels(const Condition& c, double level, bool up) const {
        const double end = rampEnd(c);
        const uint32_t n = design.rampSteps;
        std::vector<double> levels;
        for (uint32_t k = 0; k < n; ++k) {
            const double f = static_cast<double>(k) / (n - 1);
            const double v = level + (end - level) * f;
            levels.push_back(k == 0 ? level : k + 1 == n ? end : c.placement.grid.snap(v));
        }
        if (!up) {
            std::ranges::reverse(levels);
        }
        return levels;
    }

    [[nodiscard]] std::vector<IntervalPlan> planIntervals() const {
        const PlannedTrial& t = *trial;
        switch (design.procedure) {
        case Procedure::ForcedChoice:
        case Procedure::Pair: {
            IntervalPlan cond{"condition", conditionAt(t.level)};
            IntervalPlan comp{"comparison", comparison()};
            return t.conditionFirst ? std::vector{cond, comp} : std::vector{comp, cond};
        }
        case Procedure::YesNo:
            return t.catchTrial ? std::vector{IntervalPlan{"comparison", comparison()}}
                                : std::vector{IntervalPlan{"condition", conditionAt(t.level)}};
        case Procedure::Ramp: {
            std::vector<IntervalPlan> plans;
            for (double v : rampLevels(condition(), t.level, t.rampUp)) {
                char shown[64];
                std::snprintf(shown, sizeof shown, "condition@%g", v);
                plans.push_back({shown, conditionAt(v)});
            }
            return plans;
        }
        case Procedure::Slider:
            return {};
        }
        return {};
    }

    // ----- starting and ending trials -----

    void openSegment(const std::string& shown, uint32_t expected) {
        IntervalRecord r;
        r.shown = shown;
        r.expectedFrames = expected;
        record.intervals.push_back(std::move(r));
        latency.emplace_back();
        gazeMissingSince.reset();
    }

    [[nodiscard]] uint32_t expectedFrames() const {
        return static_cast<uint32_t>(std::lround(design.timing.intervalMs / periodMs));
    }

    void startTrial(double t) {
        const PlannedTrial& p = *trial;
        block = p.block;
        intervals = planIntervals();
        interval = 0;
        record = TrialRecord{};
        record.trial = p.index;
        record.practice = p.practice;
        record.condition = condition().name;
        record.parameter = std::string(infoOf(condition().vary).name);
        record.scene = p.scene;
        record.level = p.level;
        record.catchTrial = p.catchTrial;
        record.conditionFirst = p.conditionFirst;
        latency.clear();
        sliderLevel = p.level;
        sliderLastUp = false;
        sliderRecorded.reset();
        fixationHeldSince.reset();
        prevSegment.reset();
        phase = Phase::Fixation;
        phaseStart = t;
    }

    // After a trial ended or was cut short: the next one, a break before it, or the end.
    void planNext(double t, bool breakDue) {
        trial = planner->next(planner->slots());
        if (!trial) {
            phase = Phase::Done;
            phaseStart = t;
            journal.append({{"type", "end"},
                            {"time", nowUtc()},
                            {"trials", trialsDone},
                            {"slots", planner->slots()}});
            return;
        }
        if (breakDue || trial->block != block) {
            phase = Phase::Break;
            phaseStart = t;
            return;
        }
        startTrial(t);
    }

    void endTrial(double t, Response r, double answeredAt) {
        const PlannedTrial& p = *trial;
        record.response = responseName(r);
        record.reactionMs = std::max(0.0, answeredAt - responseStart);
        const bool first = r == Response::First;
        const bool second = r == Response::Second;
        switch (design.procedure) {
        case Procedure::ForcedChoice:
            record.positive = (first && p.conditionFirst) || (second && !p.conditionFirst);
            break;
        case Procedure::YesNo:
            record.positive = r == Response::Yes;
            break;
        case Procedure::Pair: // the reference judged better
            record.positive = (first && !p.conditionFirst) || (second && p.conditionFirst);
            break;
        case Procedure::Ramp:
            record.positive = (r == Response::Up && p.rampUp) || (r == Response::Down && !p.rampUp);
            break;
        case Procedure::Slider:
            record.level = sliderLevel;
            record.sliderLevel = sliderRecorded.value_or(sliderLevel);
            break;
        }
        finishRecord();
        journal.append(toJson(record));
        planner->ended(p, record.level, record.positive);
        ++trialsDone;
        repeatedLast = false;
        const bool breakDue = design.breakEvery > 0 && trialsDone % design.breakEvery == 0;
        planNext(t, breakDue);
    }

    void finishRecord() {
        for (std::size_t i = 0; i < record.intervals.size(); ++i) {
            IntervalRecord& r = record.intervals[i];
            if (latency[i].count > 0) {
                r.latencyMsMean = latency[i].sum / latency[i].count;
            }
            if (r.droppedFrames > 0) {
                addFlag(record.flags, "dropped_frame");
            }
        }
    }

    void repeatTrial(double t, const std::string& why) {
        const PlannedTrial& p = *trial;
        journal.append({{"type", "repeat"},
                        {"trial", p.index},
                        {"condition", condition().name},
                        {"practice", p.practice},
                        {"level", p.level},
                        {"why", why},
                        {"attempt", p.attempt + 1}});
        planner->repeated(p);
        repeatedLast = true;
        planNext(t, false);
    }

    // ----- gaze -----

    [[nodiscard]] bool insideFixation(const std::optional<GazeAngles>& g) const {
        return g && distanceDeg(*g, settings.fixationDeg) <= design.gaze.fixationRadiusDeg;
    }

    // Why this interval frame breaks the gaze rules, or "".
    [[nodiscard]] std::string gazeBreak(const FrameInput& in) const {
        if (!in.gaze) {
            return "";
        }
        if (design.gaze.fixationRadiusDeg > 0 && !insideFixation(in.gaze)) {
            return "fixation";
        }
        if (design.gaze.repeatOnSaccade && prevGaze && prevTime && in.timeMs > *prevTime) {
            const double speed =
                distanceDeg(*in.gaze, *prevGaze) / ((in.timeMs - *prevTime) / 1000.0);
            if (speed > design.gaze.saccadeDegPerS) {
                return "saccade";
            }
        }
        return "";
    }

    void closeGazeGap(double t) {
        if (gazeMissingSince && t - *gazeMissingSince > design.gaze.gazeLostMs + 1e-6) {
            addFlag(record.flags, "gaze_lost");
        }
        gazeMissingSince.reset();
    }

    // ----- phase changes, one per call -----

    void startInterval(double t) {
        phase = Phase::Interval;
        phaseStart = t;
        openSegment(intervals[interval].shown, expectedFrames());
    }

    void startResponse(double t) {
        // The slider's reaction time runs from its first picture, across visits to the reference.
        if (design.procedure != Procedure::Slider || phase == Phase::Fixation) {
            responseStart = t;
        }
        phase = Phase::Response;
        phaseStart = t;
        if (design.procedure == Procedure::Slider) {
            openSlider();
        }
    }

    void openSlider() {
        char shown[64];
        std::snprintf(shown, sizeof shown, "condition@%g", sliderLevel);
        openSegment(shown, 0);
    }

    bool advanceFixation(double t, const FrameInput& in) {
        if (design.gaze.fixationRadiusDeg > 0) {
            if (!insideFixation(in.gaze)) {
                fixationHeldSince.reset();
                return false;
            }
            if (!fixationHeldSince) {
                fixationHeldSince = t;
            }
            if (t - *fixationHeldSince < design.timing.fixationMs - half()) {
                return false;
            }
        } else if (!expired(t, design.timing.fixationMs)) {
            return false;
        }
        if (intervals.empty()) {
            startResponse(t);
        } else {
            startInterval(t);
        }
        return true;
    }

    bool advanceInterval(double t, const FrameInput& in) {
        if (expired(t, design.timing.intervalMs)) {
            closeGazeGap(t);
            // The slider's reference interval returns to its condition; other procedures go on
            // to their next interval, or to the answer after the last.
            const bool another =
                design.procedure != Procedure::Slider && ++interval < intervals.size();
            if (another) {
                phase = Phase::Blank;
                phaseStart = t;
            } else {
                startResponse(t);
            }
            return true;
        }
        const std::string why = design.procedure == Procedure::Slider ? "" : gazeBreak(in);
        if (why.empty()) {
            return false;
        }
        if (trial->attempt < design.gaze.maxRepeats) {
            repeatTrial(t, why);
            return true;
        }
        addFlag(record.flags, "max_repeats");
        return false;
    }

    bool advanceSlider(double t, Response r) {
        const std::vector<double> levels = condition().placement.grid.all();
        const auto at = std::ranges::min_element(
            levels, {}, [this](double v) { return std::abs(v - sliderLevel); });
        auto index = static_cast<std::ptrdiff_t>(at - levels.begin());
        // Up raises quality: towards less foveation.
        const bool towardsHigher = (r == Response::Up) != condition().placement.higherFoveatesMore;
        if (r == Response::Up || r == Response::Down) {
            index += towardsHigher ? 1 : -1;
            index = std::clamp<std::ptrdiff_t>(index, 0,
                                               static_cast<std::ptrdiff_t>(levels.size()) - 1);
            if (levels[static_cast<std::size_t>(index)] != sliderLevel) {
                closeGazeGap(t);
                sliderLevel = levels[static_cast<std::size_t>(index)];
                openSlider();
            }
            sliderLastUp = r == Response::Up;
            return false;
        }
        if (r == Response::Reference) {
            // Guenter et al. 2012: the first level at which the participant stopped raising
            // quality and compared it with the reference.
            if (sliderLastUp && !sliderRecorded) {
                sliderRecorded = sliderLevel;
            }
            sliderLastUp = false;
            closeGazeGap(t);
            phase = Phase::Interval;
            phaseStart = t;
            openSegment("comparison", expectedFrames());
            return true;
        }
        return false;
    }

    bool advanceResponse(double t, Pending& pending, const FrameInput& in) {
        const double timeout = design.timing.responseTimeoutMs;
        if (pending.given && isAccepted(pending.value)) {
            const Response r = pending.value;
            pending.given = false;
            if (design.procedure == Procedure::Slider && r != Response::Accept) {
                return advanceSlider(t, r);
            }
            closeGazeGap(t);
            endTrial(t, r, in.responseTimeMs.value_or(t));
            return true;
        }
        if (timeout > 0 && design.procedure != Procedure::Slider && expired(t, timeout)) {
            repeatTrial(t, "timeout");
            return true;
        }
        return false;
    }

    bool advance(const FrameInput& in, Pending& pending) {
        const double t = in.timeMs;
        switch (phase) {
        case Phase::Instructions:
        case Phase::Break:
            if (pending.given && pending.value == Response::Continue) {
                pending.given = false;
                startTrial(t);
                return true;
            }
            return false;
        case Phase::Fixation:
            return advanceFixation(t, in);
        case Phase::Interval:
            return advanceInterval(t, in);
        case Phase::Blank:
            if (!expired(t, design.timing.blankMs)) {
                return false;
            }
            startInterval(t);
            return true;
        case Phase::Response:
            return advanceResponse(t, pending, in);
        case Phase::Done:
            return false;
        }
        return false;
    }

    [[nodiscard]] bool isAccepted(Response r) const {
        const std::vector<Response> a = acceptedNow();
        return std::ranges::find(a, r) != a.end();
    }

    [[nodiscard]] std::vector<Response> acceptedNow() const {
        switch (phase) {
        case Phase::Instructions:
        case Phase::Break:
            return {Response::Continue};
        case Phase::Response:
            break;
        default:
            return {};
        }
        switch (design.procedure) {
        case Procedure::ForcedChoice:
            return {Response::First, Response::Second};
        case Procedure::YesNo:
            return {Response::Yes, Response::No};
        case Procedure::Pair:
            return {Response::First, Response::Second, Response::Same};
        case Procedure::Ramp:
            return {Response::Up, Response::Down, Response::Same};
        case Procedure::Slider:
            return {Response::Up, Response::Down, Response::Reference, Response::Accept};
        }
        return {};
    }

    // ----- the frame's measurements -----

    // The gap before this frame and the latency it reports belong to the previous frame.
    void attributePrevious(const FrameInput& in) {
        if (!prevSegment || !prevTime || *prevSegment >= record.intervals.size()) {
            return;
        }
        IntervalRecord& r = record.intervals[*prevSegment];
        if (in.timeMs - *prevTime > 1.5 * periodMs + 1e-6) {
            ++r.droppedFrames;
        }
        if (in.latencyMs > 0) {
            latency[*prevSegment].sum += in.latencyMs;
            ++latency[*prevSegment].count;
            r.latencyMsMax = std::max(r.latencyMsMax, in.latencyMs);
        }
    }

    void recordFrame(const FrameInput& in) {
        const bool shown = phase == Phase::Interval ||
                           (phase == Phase::Response && design.procedure == Procedure::Slider);
        prevSegment.reset();
        if (shown && !record.intervals.empty()) {
            const std::size_t k = record.intervals.size() - 1;
            IntervalRecord& r = record.intervals[k];
            ++r.frames;
            if (in.gaze) {
                closeGazeGap(in.timeMs);
                r.gaze.push_back({in.timeMs - phaseStart, in.gaze->xDeg, in.gaze->yDeg});
            } else {
                ++r.gazeLostFrames;
                if (!gazeMissingSince) {
                    gazeMissingSince = in.timeMs;
                }
            }
            prevSegment = k;
        }
        prevTime = in.timeMs;
        prevGaze = in.gaze;
    }

    [[nodiscard]] FrameShow show() const;
    [[nodiscard]] std::string prompt() const;
    void begin();
    void resume();
    void replay(const json& line, std::size_t number);
};

std::string StudySession::State::prompt() const {
    switch (phase) {
    case Phase::Instructions:
        return "Keep your eyes on the mark while a picture is shown. Continue to start.";
    case Phase::Break:
        return "Break. Continue when you are ready.";
    case Phase::Fixation:
        return repeatedLast ? "Again: keep your eyes on the mark." : "Look at the mark.";
    case Phase::Response:
        break;
    case Phase::Done:
        return "Done. Thank you.";
    default:
        return "";
    }
    switch (design.procedure) {
    case Procedure::ForcedChoice:
        return "Which one was foveated? first | second";
    case Procedure::YesNo:
        return "Was it foveated? yes | no";
    case Procedure::Pair:
        return "Which was better? first | second | same";
    case Procedure::Ramp:
        return "Did quality go up, down or stay the same? up | down | same";
    case Procedure::Slider:
        return "Find the quality of the reference: up | down | reference | accept";
    }
    return "";
}

FrameShow StudySession::State::show() const {
    FrameShow s;
    s.phase = phase;
    s.prompt = prompt();
    const bool inTrial =
        trial && phase != Phase::Break && phase != Phase::Done && phase != Phase::Instructions;
    if (inTrial) {
        s.trial = trial->index;
        s.practice = trial->practice;
    }
    s.showFixationMark = phase == Phase::Fixation || phase == Phase::Blank;
    if (phase == Phase::Interval) {
        s.stimulus =
            design.procedure == Procedure::Slider ? comparison() : intervals[interval].stimulus;
    } else if (phase == Phase::Response && design.procedure == Procedure::Slider) {
        s.stimulus = conditionAt(sliderLevel);
    }
    return s;
}

void StudySession::State::begin() {
    seed = design.seed != 0 ? design.seed : randomWord();
    if (seed == 0) {
        seed = 1;
    }
    planner = std::make_unique<Planner>(design, seed);
    journal.append({{"type", "start"},
                    {"design", designToJson(design)},
                    {"design_hash", designHash(design)},
                    {"seed", seed},
                    {"participant", settings.participant},
                    {"run", hex16(randomWord())},
                    {"refresh_hz", 1000.0 / periodMs},
                    {"time", nowUtc()}});
}

void StudySession::State::replay(const json& line, std::size_t number) {
    const std::string where = journal.path().string() + ": line " + std::to_string(number) + ": ";
    const std::string type = line["type"].get<std::string>();
    if (type == "resume" || type == "end") {
        return;
    }
    if (type != "trial" && type != "repeat") {
        throw JournalError(where + "unknown line type '" + type + "'");
    }
    const std::optional<PlannedTrial> planned = planner->next(planner->slots());
    const std::string name = line.value("condition", "");
    const auto index = line.value("trial", UINT32_MAX);
    if (!planned || planned->index != index || design.conditions[planned->condition].name != name ||
        planned->practice != line.value("practice", !planned->practice)) {
        throw JournalError(where + "trial " + std::to_string(index) + " (" + name +
                           ") is not the trial the plan holds there; the journal does not "
                           "belong to this design and seed");
    }
    if (type == "repeat") {
        planner->repeated(*planned);
        return;
    }
    TrialRecord r;
    try {
        r = trialFromJson(line);
    } catch (const JournalError& e) {
        throw JournalError(where + e.what());
    }
    planner->ended(*planned, r.level, r.positive);
    ++trialsDone;
}

void StudySession::State::resume() {
    const std::vector<json>& lines = journal.existing();
    const std::string name = journal.path().string();
    const json& start = lines.front();
    if (start.value("type", "") != "start" || !start.contains("seed") ||
        !start["seed"].is_number_unsigned()) {
        throw JournalError(name + ": line 1 is not the start of a run");
    }
    const std::string hash = designHash(design);
    if (start.value("design_hash", "") != hash) {
        throw JournalError(name + ": written for design '" +
                           start.value("/design/name"_json_pointer, std::string("?")) + "' (hash " +
                           start.value("design_hash", "?") + "), not for this one ('" +
                           design.name + "', hash " + hash + "); start a new journal");
    }
    if (start.value("participant", "") != settings.participant) {
        throw JournalError(name + ": the run of participant '" + start.value("participant", "") +
                           "', not '" + settings.participant + "'");
    }
    seed = start["seed"].get<uint64_t>();
    planner = std::make_unique<Planner>(design, seed);
    for (std::size_t i = 1; i < lines.size(); ++i) {
        replay(lines[i], i + 1);
    }
    // A run that is already complete stays as it is.
    if (planner->next(planner->slots())) {
        journal.append({{"type", "resume"}, {"time", nowUtc()}, {"trials_done", trialsDone}});
    }
}

StudySession::StudySession(StudyDesign design, SessionSettings settings, Journal& journal)
    : mState(std::make_unique<State>(std::move(design), std::move(settings), journal)) {
    State& s = *mState;
    if (!validParticipant(s.settings.participant)) {
        throw SessionError("participant '" + s.settings.participant +
                           "': a code of 1-32 letters, digits, '_' or '-' (nothing personal)");
    }
    const double hz =
        s.design.timing.refreshHz > 0 ? s.design.timing.refreshHz : s.settings.refreshHz;
    if (!(hz >= 1.0 && hz <= 1000.0)) {
        throw SessionError("refresh rate " + std::to_string(hz) + " Hz is outside [1, 1000]");
    }
    s.periodMs = 1000.0 / hz;
    if (journal.existing().empty()) {
        s.begin();
    } else {
        s.resume();
    }
    s.trial = s.planner->next(s.planner->slots());
    if (!s.trial) {
        s.phase = Phase::Done;
    }
}

StudySession::~StudySession() = default;

FrameShow StudySession::frame(const FrameInput& input) {
    State& s = *mState;
    s.attributePrevious(input);
    Pending pending;
    if (input.response) {
        pending = {*input.response, true};
    }
    // A frame may pass several phases (a zero blank, an answer that starts the next trial);
    // each phase has its own frames, so the chain is short.
    for (int i = 0; i < 16 && s.advance(input, pending); ++i) {
    }
    s.recordFrame(input);
    return s.show();
}

bool StudySession::finished() const {
    return mState->phase == Phase::Done;
}

std::vector<Stimulus> StudySession::allStimuli() const {
    const State& s = *mState;
    std::vector<Stimulus> all;
    auto add = [&all](Stimulus st) {
        if (std::ranges::find(all, st) == all.end()) {
            all.push_back(std::move(st));
        }
    };
    for (const Condition& c : s.design.conditions) {
        std::vector<double> levels = c.placement.grid.all();
        if (s.design.procedure == Procedure::Ramp) {
            levels.push_back(s.rampEnd(c));
        }
        for (const SceneChoice& scene : s.design.scenes) {
            for (double level : levels) {
                add({withLevel(c.base, c.vary, level), scene});
            }
            add({comparisonOf(c), scene});
        }
    }
    return all;
}

std::vector<Response> StudySession::accepted() const {
    return mState->acceptedNow();
}

uint64_t StudySession::seed() const {
    return mState->seed;
}

uint32_t StudySession::trialsDone() const {
    return mState->trialsDone;
}

uint32_t StudySession::trialsPlanned() const {
    return mState->planner->slots() + mState->planner->remaining();
}

const LevelPlacement* StudySession::placement(std::string_view condition) const {
    const State& s = *mState;
    for (std::size_t c = 0; c < s.design.conditions.size(); ++c) {
        if (s.design.conditions[c].name == condition) {
            return s.planner->placement(c);
        }
    }
    return nullptr;
}

std::optional<StudySession::TrialInfo> StudySession::currentTrial() const {
    const State& s = *mState;
    if (!s.trial || s.phase == Phase::Instructions || s.phase == Phase::Break ||
        s.phase == Phase::Done) {
        return std::nullopt;
    }
    const PlannedTrial& t = *s.trial;
    return TrialInfo{s.condition().name,
                     s.design.procedure == Procedure::Slider ? s.sliderLevel : t.level,
                     t.conditionFirst, t.catchTrial, t.rampUp};
}

} // namespace gt::study
