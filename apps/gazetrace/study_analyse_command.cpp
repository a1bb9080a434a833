#include "study_analyse_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include "analysis.hpp"
#include "atomic_write.hpp"
#include "core/error.hpp"
#include "design.hpp"
#include "eval_plots.hpp"
#include "journal.hpp"
#include "observer.hpp"
#include "scene/image_io.hpp"
#include "session.hpp"

namespace gt::app {

namespace fs = std::filesystem;
using nlohmann::json;

// The simulation's bootstrap per fit: fewer than analyse's default, since it fits every
// simulated participant; enough for a 95 % percentile interval.
constexpr uint32_t kSimulateBootstrap = 200;

namespace {

// ---- study analyse -------------------------------------------------------------------------

std::string csvNumber(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    return text;
}

std::string csvOptional(const std::optional<double>& v) {
    return v ? csvNumber(*v) : std::string();
}

// One row per participant and condition, then one per condition's group ("row" says which);
// an empty cell is a value that does not apply (no fit, no rule).
std::string thresholdsCsv(const study::Analysis& a) {
    std::ostringstream out;
    out << "row,condition,parameter,participant,participants,trials,flagged_trials,threshold,"
           "threshold_low,threshold_high,threshold_sd,slope,guess,lapse,rule_threshold\n";
    for (const study::ParticipantCondition& pc : a.participants) {
        const study::PsychometricFit& f = pc.fit;
        uint32_t trials = 0;
        for (const study::LevelCount& c : pc.counts)
            trials += c.trials;
        out << "participant," << pc.condition << ',' << pc.parameter << ',' << pc.participant
            << ",1," << trials << ',' << pc.flaggedTrials << ',';
        if (pc.fitted) {
            out << csvNumber(f.function.threshold) << ',' << csvNumber(f.thresholdLow) << ','
                << csvNumber(f.thresholdHigh) << ",," << csvNumber(f.function.slope) << ','
                << csvNumber(f.function.guess) << ',' << csvNumber(f.function.lapse) << ',';
        } else {
            out << ",,,,,,,";
        }
        out << csvOptional(pc.ruleThreshold) << '\n';
    }
    for (const study::ConditionSummary& s : a.conditions) {
        const study::GroupThreshold& g = s.group;
        out << "group," << s.condition << ',' << s.parameter << ",," << g.participants << ','
            << (s.fitted ? std::to_string(g.pooled.trials) : std::string()) << ",,";
        if (g.participants > 0) {
            out << csvNumber(g.mean) << ',' << csvNumber(g.low) << ',' << csvNumber(g.high) << ','
                << csvNumber(g.sd) << ',';
        } else {
            out << ",,,,";
        }
        if (s.fitted) {
            out << csvNumber(g.pooled.function.slope) << ',' << csvNumber(g.pooled.function.guess)
                << ',' << csvNumber(g.pooled.function.lapse) << ',';
        } else {
            out << ",,,";
        }
        out << csvOptional(s.ruleMean) << '\n';
    }
    return out.str();
}

// The plot's x range: the levels tested, widened to the group interval.
std::pair<double, double> levelRange(const study::Analysis& a, const std::string& condition) {
    double lo = 1e300, hi = -1e300;
    for (const study::ParticipantCondition& pc : a.participants) {
        if (pc.condition != condition) continue;
        for (const study::LevelCount& c : pc.counts) {
            lo = std::min(lo, c.level);
            hi = std::max(hi, c.level);
        }
        if (pc.ruleThreshold) {
            lo = std::min(lo, *pc.ruleThreshold);
            hi = std::max(hi, *pc.ruleThreshold);
        }
    }
    if (lo > hi) return {0.0, 1.0};
    if (hi - lo < 1e-12)
        return {lo - 0.5 * std::max(std::abs(lo), 1e-3), hi + 0.5 * std::max(std::abs(hi), 1e-3)};
    return {lo, hi};
}

PsychometricPanel panelOf(const study::Analysis& a, const study::ConditionSummary& s) {
    PsychometricPanel panel;
    panel.title = "condition " + s.condition;
    std::tie(panel.xMin, panel.xMax) = levelRange(a, s.condition);
    panel.xTitle = s.parameter + " (level)";
    for (const study::ParticipantCondition& pc : a.participants) {
        if (pc.condition != s.condition) continue;
        PsychometricSeries series;
        series.name = pc.participant;
        for (const study::LevelCount& c : pc.counts) {
            if (c.trials == 0) continue;
            series.points.push_back({c.level, static_cast<double>(c.positive) / c.trials,
                                     static_cast<double>(c.trials)});
        }
        if (pc.fitted) {
            constexpr int kSamples = 200;
            for (int i = 0; i <= kSamples; ++i) {
                const double x = panel.xMin + (panel.xMax - panel.xMin) * i / kSamples;
                series.curve.emplace_back(x, pc.fit.function.probability(x));
            }
        }
        panel.series.push_back(std::move(series));
    }
    if (s.group.participants > 0) panel.group = {{s.group.mean, s.group.low, s.group.high}};
    return panel;
}

} // namespace

nlohmann::json runStudyAnalyse(const StudyAnalyseOptions& options) {
    const std::vector<fs::path> journals(options.journals.begin(), options.journals.end());
    std::vector<io::RunFile> inputs;
    for (const fs::path& j : journals)
        inputs.push_back({"journals", j});
    std::vector<io::RunFile> outputs;
    for (const char* name : {"thresholds.json", "thresholds.csv", "psychometric.png"})
        outputs.push_back({"--out", fs::path(options.out) / name});
    io::refuseOutputThatIsInput(outputs, inputs);

    const study::Analysis analysis =
        study::analyseJournals(journals, {options.excludeFlagged, options.bootstrap, options.seed});
    json result = study::toJson(analysis);
    result["journals"] = options.journals;
    result["exclude_flagged"] = options.excludeFlagged;
    result["bootstrap"] = options.bootstrap;
    result["seed"] = options.seed;
    result["out"] = options.out;

    // Staged: a run that fails leaves an earlier run's files as they were.
    io::StagedFolder folder(options.out);
    io::writeFileAtomic(folder.file("thresholds.json"), result.dump(2) + "\n");
    io::writeFileAtomic(folder.file("thresholds.csv"), thresholdsCsv(analysis));
    std::vector<PsychometricPanel> panels;
    for (const study::ConditionSummary& s : analysis.conditions)
        panels.push_back(panelOf(analysis, s));
    const quality::RgbaImage plot = psychometricImage(panels);
    image::writePngAtomic(folder.file("psychometric.png"), plot.width, plot.height, plot.pixels);
    folder.commit();
    return result;
}

namespace {

// ---- study simulate ------------------------------------------------------------------------

// The observer planted in one condition: a logistic psychometric function of the level.
struct Planted {
    const study::Condition* condition = nullptr;
    study::PsychometricFunction function;
};

// Its threshold is --threshold or the middle of the condition's levels; its slope --slope or
// one whose core rises from 25 % to 75 % over a quarter of the levels' span (logistic: that
// width is 2 ln 3 / beta); a foveating parameter raises detection with the level.
Planted plantedFor(const study::StudyDesign& design, const study::Condition& c,
                   const StudySimulateOptions& o) {
    const study::LevelGrid& grid = c.placement.grid;
    const double lo = grid.values.empty() ? grid.min : grid.values.front();
    const double hi = grid.values.empty() ? grid.max : grid.values.back();
    Planted p;
    p.condition = &c;
    p.function.shape = study::PsychometricShape::Logistic;
    p.function.threshold = o.threshold > 0.0 ? o.threshold : 0.5 * (lo + hi);
    p.function.slope = o.slope > 0.0 ? o.slope : 8.0 * std::log(3.0) / (hi - lo);
    p.function.lapse = o.lapse;
    p.function.increasing = study::infoOf(c.vary).higherFoveatesMore;
    // The guess: a blind pick in a forced choice; in yes/no, false alarms as rare as lapses;
    // the pair, ramp and slider answer "same" when they see nothing.
    switch (design.procedure) {
    case study::Procedure::ForcedChoice:
        p.function.guess = 0.5;
        break;
    case study::Procedure::YesNo:
        p.function.guess = o.lapse;
        break;
    default:
        p.function.guess = 0.0;
        break;
    }
    return p;
}

// One simulated participant: an observer per condition, and the slider's state in a trial.
class SimulatedParticipant {
public:
    SimulatedParticipant(const std::vector<Planted>& planted, uint64_t seed) {
        for (std::size_t i = 0; i < planted.size(); ++i) {
            mObservers.emplace(planted[i].condition->name,
                               study::SimulatedObserver(planted[i].function, seed * 1000 + i));
        }
    }

    // The answer to what this frame shows, or none (keep watching).
    std::optional<study::Response> answer(const study::FrameShow& show,
                                          const study::StudySession& session,
                                          study::Procedure procedure) {
        using study::Response;
        const std::vector<Response> accepted = session.accepted();
        const auto accepts = [&](Response r) {
            return std::find(accepted.begin(), accepted.end(), r) != accepted.end();
        };
        if (show.phase == study::Phase::Instructions || show.phase == study::Phase::Break) {
            return accepts(Response::Continue) ? std::optional(Response::Continue) : std::nullopt;
        }
        if (show.phase != study::Phase::Response) return std::nullopt;
        const std::optional<study::StudySession::TrialInfo> t = session.currentTrial();
        if (!t) return std::nullopt;
        if (t->catchTrial)
            return mObservers.at(t->condition).answerCatch() ? Response::Yes : Response::No;
        study::SimulatedObserver& observer = mObservers.at(t->condition);
        switch (procedure) {
        case study::Procedure::ForcedChoice:
            return observer.answer(t->level) == t->conditionFirst ? Response::First
                                                                  : Response::Second;
        case study::Procedure::YesNo:
            return observer.answer(t->level) ? Response::Yes : Response::No;
        case study::Procedure::Pair:
            // Positive: the reference judged better; else the two look the same.
            if (!observer.answer(t->level)) return Response::Same;
            return t->conditionFirst ? Response::Second : Response::First;
        case study::Procedure::Ramp:
            if (!observer.answer(t->level)) return Response::Same;
            return t->rampUp ? Response::Up : Response::Down;
        case study::Procedure::Slider:
            return sliderAnswer(*t, observer, session.trialsDone());
        }
        return std::nullopt;
    }

private:
    // Guenter et al. 2012's slider: raise quality while the foveation is seen, then compare with
    // the reference and accept.
    study::Response sliderAnswer(const study::StudySession::TrialInfo& t,
                                 study::SimulatedObserver& observer, uint32_t trial) {
        if (trial != mSliderTrial) {
            mSliderTrial = trial;
            mSliderSteps = 0;
            mComparedReference = false;
        }
        if (mComparedReference) return study::Response::Accept;
        if (++mSliderSteps < kMaxSliderSteps && observer.answer(t.level)) {
            return study::Response::Up;
        }
        mComparedReference = true;
        return study::Response::Reference;
    }

    static constexpr uint32_t kMaxSliderSteps = 1000;
    std::map<std::string, study::SimulatedObserver> mObservers;
    uint32_t mSliderTrial = ~0u;
    uint32_t mSliderSteps = 0;
    bool mComparedReference = false;
};

// A folder for the journals, removed when the run ends, where --journals names none: tmpfs
// where there is one (every trial's line is fsync'd).
class ScratchFolder {
public:
    ScratchFolder() {
        const fs::path base =
            fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
        std::random_device device;
        mPath = base / ("gazetrace-simulate-" + std::to_string(::getpid()) + "-" +
                        std::to_string(device()));
        fs::create_directories(mPath);
    }
    ~ScratchFolder() {
        std::error_code ignored;
        fs::remove_all(mPath, ignored);
    }
    ScratchFolder(const ScratchFolder&) = delete;
    ScratchFolder& operator=(const ScratchFolder&) = delete;
    [[nodiscard]] const fs::path& path() const noexcept { return mPath; }

private:
    fs::path mPath;
};

// One participant's whole run, headless: the real session fed one frame per refresh period,
// with the gaze on the fixation point and the answers of the simulated participant.
void runParticipant(const study::StudyDesign& design, const std::string& code,
                    const fs::path& journalPath, SimulatedParticipant& participant) {
    study::Journal journal(journalPath);
    study::SessionSettings settings;
    settings.participant = code;
    const double refreshHz = design.timing.refreshHz > 0.0 ? design.timing.refreshHz : 60.0;
    settings.refreshHz = refreshHz;
    study::StudySession session(design, settings, journal);
    // A trial that never ends would be a fault of the session: give up after an hour of frames.
    const uint64_t maxFramesPerTrial = static_cast<uint64_t>(3600.0 * refreshHz);
    uint64_t frame = 0, trialStart = 0;
    uint32_t done = session.trialsDone();
    std::optional<study::Response> pending;
    while (!session.finished()) {
        study::FrameInput input;
        input.timeMs = static_cast<double>(frame) * 1000.0 / refreshHz;
        input.gaze = study::GazeAngles{0.0, 0.0};
        input.response = pending;
        const study::FrameShow show = session.frame(input);
        pending = participant.answer(show, session, design.procedure);
        ++frame;
        if (session.trialsDone() != done) {
            done = session.trialsDone();
            trialStart = frame;
        } else if (frame - trialStart > maxFramesPerTrial) {
            throw Error("study simulate: " + code + "'s trial " + std::to_string(done) +
                        " did not end in an hour of frames");
        }
    }
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

json optionalMedian(const std::vector<double>& v) {
    return v.empty() ? json(nullptr) : json(median(v));
}

// Per condition: how often the fits' 95 % intervals hold the planted threshold, and how many
// trials and how close the fits (and the procedure's own rule) came.
json conditionReport(const study::Analysis& a, const Planted& p) {
    const std::string& name = p.condition->name;
    const double planted = p.function.threshold;
    uint32_t fitted = 0, covered = 0;
    std::vector<double> trials, errors, ruleErrors, thresholds;
    for (const study::ParticipantCondition& pc : a.participants) {
        if (pc.condition != name) continue;
        uint32_t n = 0;
        for (const study::LevelCount& c : pc.counts)
            n += c.trials;
        trials.push_back(n);
        if (pc.fitted) {
            ++fitted;
            covered += pc.fit.thresholdLow <= planted && planted <= pc.fit.thresholdHigh ? 1 : 0;
            errors.push_back(std::abs(pc.fit.function.threshold - planted));
            thresholds.push_back(pc.fit.function.threshold);
        }
        if (pc.ruleThreshold) ruleErrors.push_back(std::abs(*pc.ruleThreshold - planted));
    }
    return {{"condition", name},
            {"parameter", std::string(study::infoOf(p.condition->vary).name)},
            {"placement", study::placementKindName(p.condition->placement.kind)},
            {"planted_threshold", planted},
            {"planted_slope", p.function.slope},
            {"planted_guess", p.function.guess},
            {"lapse", p.function.lapse},
            {"fitted", fitted},
            {"covered", covered},
            {"coverage", fitted > 0 ? json(static_cast<double>(covered) / fitted) : json()},
            {"trials_median", optionalMedian(trials)},
            {"threshold_median", optionalMedian(thresholds)},
            {"error_median", optionalMedian(errors)},
            {"rule_error_median", optionalMedian(ruleErrors)}};
}

} // namespace

nlohmann::json runStudySimulate(const StudySimulateOptions& options) {
    const std::vector<io::RunFile> inputs{{"--design", options.design}};
    io::refuseOutputThatIsInput(std::vector<io::RunFile>{{"--json", options.json}}, inputs);
    if (!options.json.empty()) io::checkOutputFile(options.json);
    const study::StudyDesign design = study::loadDesign(options.design);

    std::optional<ScratchFolder> scratch;
    fs::path folder;
    if (options.journals.empty()) {
        folder = scratch.emplace().path();
    } else {
        folder = options.journals;
        fs::create_directories(folder);
    }
    std::vector<Planted> planted;
    for (const study::Condition& c : design.conditions)
        planted.push_back(plantedFor(design, c, options));

    std::vector<fs::path> journals;
    for (uint32_t i = 0; i < options.observers; ++i) {
        char code[16];
        std::snprintf(code, sizeof code, "sim%03u", i + 1);
        journals.push_back(folder / (design.name + "_" + code + ".jsonl"));
        // A journal already there would be resumed: a simulation always starts afresh.
        if (fs::exists(fs::symlink_status(journals.back()))) {
            throw Error("study simulate: " + journals.back().string() +
                        " exists (a journal of an earlier run); pick an empty --journals folder");
        }
    }
    for (uint32_t i = 0; i < options.observers; ++i) {
        SimulatedParticipant participant(planted, options.seed * 100003 + i);
        char code[16];
        std::snprintf(code, sizeof code, "sim%03u", i + 1);
        runParticipant(design, code, journals[i], participant);
    }
    const study::Analysis analysis =
        study::analyseJournals(journals, {false, kSimulateBootstrap, options.seed});

    json conditions = json::array();
    for (const Planted& p : planted)
        conditions.push_back(conditionReport(analysis, p));
    json result{{"design", design.name},
                {"procedure", study::procedureName(design.procedure)},
                {"observers", options.observers},
                {"seed", options.seed},
                {"bootstrap", kSimulateBootstrap},
                {"journals", options.journals.empty() ? json(nullptr) : json(options.journals)},
                {"conditions", std::move(conditions)}};
    if (!options.json.empty()) io::writeFileAtomic(options.json, result.dump(2) + "\n");
    return result;
}

} // namespace gt::app
