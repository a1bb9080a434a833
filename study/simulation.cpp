#include "simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace gt::study {

PsychometricFunction plantedFunction(const StudyDesign& design, const Condition& condition,
                                     double threshold, double slope, double lapse) {
    const LevelGrid& grid = condition.placement.grid;
    const double lo = grid.values.empty() ? grid.min : grid.values.front();
    const double hi = grid.values.empty() ? grid.max : grid.values.back();
    PsychometricFunction f;
    f.shape = PsychometricShape::Logistic;
    f.threshold = threshold > 0.0 ? threshold : 0.5 * (lo + hi);
    // Logistic: the core rises from 25 % to 75 % over 2 ln 3 / beta; a quarter of the span.
    f.slope = slope > 0.0 ? slope : 8.0 * std::log(3.0) / (hi - lo);
    f.lapse = lapse;
    f.increasing = infoOf(condition.vary).higherFoveatesMore;
    switch (design.procedure) {
    case Procedure::ForcedChoice:
        f.guess = 0.5;
        break;
    case Procedure::YesNo:
        f.guess = lapse;
        break;
    case Procedure::Pair:
    case Procedure::Ramp:
    case Procedure::Slider:
        f.guess = 0.0;
        break;
    }
    return f;
}

SimulatedParticipant::SimulatedParticipant(const StudyDesign& design,
                                           const std::vector<PsychometricFunction>& functions,
                                           uint64_t seed)
    : mProcedure(design.procedure) {
    if (functions.size() != design.conditions.size()) {
        throw std::invalid_argument("SimulatedParticipant: one function per condition");
    }
    for (std::size_t i = 0; i < functions.size(); ++i) {
        mObservers.emplace(design.conditions[i].name,
                           SimulatedObserver(functions[i], seed * 1000 + i));
    }
}

std::optional<Response> SimulatedParticipant::answer(const FrameShow& show,
                                                     const StudySession& session) {
    const std::vector<Response> accepted = session.accepted();
    const auto accepts = [&](Response r) {
        return std::find(accepted.begin(), accepted.end(), r) != accepted.end();
    };
    if (show.phase == Phase::Instructions || show.phase == Phase::Break) {
        return accepts(Response::Continue) ? std::optional(Response::Continue) : std::nullopt;
    }
    if (show.phase != Phase::Response) {
        return std::nullopt;
    }
    const std::optional<StudySession::TrialInfo> t = session.currentTrial();
    if (!t) {
        return std::nullopt;
    }
    SimulatedObserver& observer = mObservers.at(t->condition);
    if (t->catchTrial) {
        return observer.answerCatch() ? Response::Yes : Response::No;
    }
    switch (mProcedure) {
    case Procedure::ForcedChoice:
        return observer.answer(t->level) == t->conditionFirst ? Response::First : Response::Second;
    case Procedure::YesNo:
        return observer.answer(t->level) ? Response::Yes : Response::No;
    case Procedure::Pair:
        // Positive: the reference judged better; else the two look the same.
        if (!observer.answer(t->level)) {
            return Response::Same;
        }
        return t->conditionFirst ? Response::Second : Response::First;
    case Procedure::Ramp:
        if (!observer.answer(t->level)) {
            return Response::Same;
        }
        return t->rampUp ? Response::Up : Response::Down;
    case Procedure::Slider:
        return sliderAnswer(*t, observer, session.trialsDone());
    }
    return std::nullopt;
}

// Guenter et al. 2012's slider: raise quality while the foveation is seen, then compare with
// the reference (the session records that level) and accept.
Response SimulatedParticipant::sliderAnswer(const StudySession::TrialInfo& t,
                                            SimulatedObserver& observer, uint32_t trialsDone) {
    constexpr uint32_t kMaxSteps = 1000;
    if (trialsDone != mSliderTrial) {
        mSliderTrial = trialsDone;
        mSliderSteps = 0;
        mComparedReference = false;
    }
    if (mComparedReference) {
        return Response::Accept;
    }
    if (++mSliderSteps < kMaxSteps && observer.answer(t.level)) {
        return Response::Up;
    }
    mComparedReference = true;
    return Response::Reference;
}

void runSimulatedParticipant(const StudyDesign& design, const std::string& participant,
                             Journal& journal, SimulatedParticipant& simulated) {
    SessionSettings settings;
    settings.participant = participant;
    const double refreshHz = design.timing.refreshHz > 0.0 ? design.timing.refreshHz : 60.0;
    settings.refreshHz = refreshHz;
    StudySession session(design, settings, journal);
    const auto maxFramesPerTrial = static_cast<uint64_t>(3600.0 * refreshHz);
    uint64_t frame = 0, trialStart = 0;
    uint32_t done = session.trialsDone();
    std::optional<Response> pending;
    while (!session.finished()) {
        FrameInput input;
        input.timeMs = static_cast<double>(frame) * 1000.0 / refreshHz;
        input.gaze = GazeAngles{0.0, 0.0}; // on the fixation point (SessionSettings' default)
        input.response = pending;
        const FrameShow show = session.frame(input);
        pending = simulated.answer(show, session);
        ++frame;
        if (session.trialsDone() != done) {
            done = session.trialsDone();
            trialStart = frame;
        } else if (frame - trialStart > maxFramesPerTrial) {
            throw std::logic_error("study simulate: " + participant + "'s trial " +
                                   std::to_string(done) + " did not end in an hour of frames");
        }
    }
}

namespace {

std::optional<double> median(std::vector<double> v) {
    if (v.empty()) {
        return std::nullopt;
    }
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

ConditionRecovery recovery(const Analysis& a, const Condition& condition,
                           const PsychometricFunction& planted) {
    ConditionRecovery r;
    r.condition = condition.name;
    r.planted = planted;
    std::vector<double> trials, errors, ruleErrors, thresholds;
    for (const ParticipantCondition& pc : a.participants) {
        if (pc.condition != condition.name) {
            continue;
        }
        uint32_t n = 0;
        for (const LevelCount& c : pc.counts) {
            n += c.trials;
        }
        trials.push_back(n);
        if (pc.fitted) {
            ++r.fitted;
            const double t = planted.threshold;
            r.covered += pc.fit.thresholdLow <= t && t <= pc.fit.thresholdHigh ? 1 : 0;
            errors.push_back(std::abs(pc.fit.function.threshold - t));
            thresholds.push_back(pc.fit.function.threshold);
        }
        if (pc.ruleThreshold) {
            ruleErrors.push_back(std::abs(*pc.ruleThreshold - planted.threshold));
        }
    }
    r.trialsMedian = median(trials);
    r.thresholdMedian = median(thresholds);
    r.errorMedian = median(errors);
    r.ruleErrorMedian = median(ruleErrors);
    return r;
}

nlohmann::json optionalJson(const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

} // namespace

DesignSimulation simulateDesign(const StudyDesign& design, const DesignSimulationSettings& settings,
                                const std::filesystem::path& folder) {
    std::vector<PsychometricFunction> planted;
    for (const Condition& c : design.conditions) {
        planted.push_back(
            plantedFunction(design, c, settings.threshold, settings.slope, settings.lapse));
    }
    DesignSimulation sim;
    std::vector<std::string> codes;
    for (uint32_t i = 0; i < settings.observers; ++i) {
        char code[16];
        std::snprintf(code, sizeof code, "sim%03u", i + 1);
        codes.emplace_back(code);
        sim.journals.push_back(folder / (design.name + "_" + code + ".jsonl"));
        // A journal already there would be resumed: a simulation always starts afresh.
        if (std::filesystem::exists(std::filesystem::symlink_status(sim.journals.back()))) {
            throw JournalError(sim.journals.back().string() +
                               ": exists (a journal of an earlier run); simulate into an empty "
                               "folder");
        }
    }
    for (uint32_t i = 0; i < settings.observers; ++i) {
        if (settings.beforeParticipant) {
            settings.beforeParticipant();
        }
        SimulatedParticipant participant(design, planted, settings.seed * 100003 + i);
        Journal journal(sim.journals[i]);
        runSimulatedParticipant(design, codes[i], journal, participant);
    }
    sim.analysis = analyseJournals(
        sim.journals, {false, settings.bootstrap, settings.seed, settings.beforeParticipant});
    for (std::size_t c = 0; c < design.conditions.size(); ++c) {
        sim.conditions.push_back(recovery(sim.analysis, design.conditions[c], planted[c]));
    }
    return sim;
}

nlohmann::json toJson(const StudyDesign& design, const ConditionRecovery& r) {
    const Condition* condition = nullptr;
    for (const Condition& c : design.conditions) {
        if (c.name == r.condition) {
            condition = &c;
        }
    }
    return {{"condition", r.condition},
            {"parameter", condition ? std::string(infoOf(condition->vary).name) : ""},
            {"placement", condition ? placementKindName(condition->placement.kind) : ""},
            {"planted_threshold", r.planted.threshold},
            {"planted_slope", r.planted.slope},
            {"planted_guess", r.planted.guess},
            {"lapse", r.planted.lapse},
            {"fitted", r.fitted},
            {"covered", r.covered},
            {"coverage", r.fitted > 0 ? nlohmann::json(static_cast<double>(r.covered) / r.fitted)
                                      : nlohmann::json(nullptr)},
            {"trials_median", optionalJson(r.trialsMedian)},
            {"threshold_median", optionalJson(r.thresholdMedian)},
            {"error_median", optionalJson(r.errorMedian)},
            {"rule_error_median", optionalJson(r.ruleErrorMedian)}};
}

} // namespace gt::study
