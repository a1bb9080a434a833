#include "analysis.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>
#include <tuple>

#include "design.hpp"
#include "journal.hpp"

namespace gt::study {

namespace {

using nlohmann::json;

// What a journal's "start" line says about its run.
struct RunStart {
    std::string participant;
    std::string designName;
    std::string designHash;
    StudyDesign design;
};

std::string lineType(const json& line) {
    const auto it = line.find("type");
    return it != line.end() && it->is_string() ? it->get<std::string>() : std::string();
}

RunStart readStart(const std::vector<json>& lines, const std::filesystem::path& path) {
    const std::string name = path.filename().string();
    if (lines.empty() || lineType(lines.front()) != "start") {
        throw JournalError(name + ": no \"start\" line (not a study journal)");
    }
    const json& start = lines.front();
    if (!start.contains("design") || !start.at("design").is_object()) {
        throw JournalError(name + ": the \"start\" line holds no design");
    }
    RunStart run;
    try {
        run.participant = start.at("participant").get<std::string>();
        run.design = parseDesign(start.at("design"), name);
    } catch (const DesignError& e) {
        throw JournalError(e.what());
    } catch (const json::exception& e) {
        throw JournalError(name + ": the \"start\" line: " + e.what());
    }
    run.designName = run.design.name;
    const auto hash = start.find("design_hash");
    run.designHash = hash != start.end() && hash->is_string() ? hash->get<std::string>()
                                                              : designHash(run.design);
    return run;
}

// One participant's trials of one condition, in the order they were answered.
struct Cell {
    std::string participant;
    std::string condition;
    std::vector<TrialRecord> trials; // practice left out; flagged ones left out when asked
    uint32_t flagged = 0;
};

bool flagged(const TrialRecord& t) {
    return std::any_of(t.flags.begin(), t.flags.end(), [](const std::string& f) {
        return f == "dropped_frame" || f == "gaze_lost";
    });
}

const Condition& conditionNamed(const StudyDesign& design, const std::string& name,
                                const std::string& journal) {
    for (const Condition& c : design.conditions) {
        if (c.name == name) {
            return c;
        }
    }
    throw JournalError(journal + ": a trial of condition '" + name + "', which the design lacks");
}

// Adds one journal's trial lines to `cells` (keyed by participant and condition).
void collectTrials(const std::vector<json>& lines, const RunStart& run,
                   const std::filesystem::path& path, const AnalysisSettings& settings,
                   std::map<std::pair<std::string, std::string>, Cell>& cells) {
    const std::string name = path.filename().string();
    std::set<uint32_t> seen; // a trial journaled twice (a resumed run) counts once
    for (const json& line : lines) {
        if (lineType(line) != "trial") {
            continue;
        }
        TrialRecord t = trialFromJson(line);
        if (t.practice || !seen.insert(t.trial).second) {
            continue;
        }
        const Condition& condition = conditionNamed(run.design, t.condition, name);
        Cell& cell = cells[{run.participant, condition.name}];
        cell.participant = run.participant;
        cell.condition = condition.name;
        if (flagged(t)) {
            ++cell.flagged;
            if (settings.excludeFlagged) {
                continue;
            }
        }
        cell.trials.push_back(std::move(t));
    }
}

// Yes/no catch trials (the reference shown alone): how many, how many answered "yes".
std::pair<uint32_t, uint32_t> catchCounts(const std::vector<TrialRecord>& trials) {
    uint32_t n = 0, yes = 0;
    for (const TrialRecord& t : trials) {
        if (!t.catchTrial) {
            continue;
        }
        ++n;
        yes += t.positive ? 1u : 0u;
    }
    return {n, yes};
}

std::vector<LevelCount> countsOf(const std::vector<TrialRecord>& trials) {
    std::vector<double> levels;
    std::vector<bool> positive;
    for (const TrialRecord& t : trials) {
        if (t.catchTrial) {
            continue;
        }
        levels.push_back(t.level);
        positive.push_back(t.positive);
    }
    return countByLevel(levels, positive);
}

// The fit's guess rate per procedure: two-interval forced choice 0.5 (a blind pick is right
// half the time); yes/no the false-alarm rate, fitted with the function from the catch trials'
// "yes" answers (Kingdom & Prins, ch. 4: in yes/no, gamma is the rate of "yes" with no signal;
// without catch trials it is fitted from the levels alone, within [0, 0.5]); the pair and ramp
// tests 0 (their positive answer, "the reference was better" or "the ramp went this way", is a
// detection that a participant who sees no difference does not give: they answer "same"); the
// slider has no fit (its rule is the threshold).
FitSettings fitSettingsFor(const StudyDesign& design, const Condition& condition,
                           const std::vector<TrialRecord>& trials, const AnalysisSettings& settings,
                           uint64_t seed) {
    FitSettings fit;
    fit.shape = condition.placement.shape;
    fit.increasing = infoOf(condition.vary).higherFoveatesMore;
    fit.guess = design.procedure == Procedure::ForcedChoice ? 0.5 : 0.0;
    if (design.procedure == Procedure::YesNo) {
        fit.fitGuess = true;
        std::tie(fit.catchTrials, fit.catchPositive) = catchCounts(trials);
    }
    fit.levelMin = condition.placement.grid.min;
    fit.levelMax = condition.placement.grid.max;
    fit.bootstrap = settings.bootstrap;
    fit.seed = seed;
    return fit;
}

} // namespace

// The thesis's series (its 6.2): a reversal is a trial whose answer differs from the trial
// before (the staircase turns there; the ascending start counts as "no", so a first "yes" is
// the first reversal); the first is not counted, the next `counted` are averaged
// ("until each subject reported four threshold values per setting"). Catch trials do not move
// the series and are skipped. Empty without a counted reversal.
std::optional<double> seriesThreshold(const std::vector<TrialRecord>& trials, uint32_t counted) {
    std::vector<double> reversals;
    bool previous = false; // the series ascends until the first "yes"
    for (const TrialRecord& t : trials) {
        if (t.catchTrial) {
            continue;
        }
        if (t.positive != previous) {
            reversals.push_back(t.level);
        }
        previous = t.positive;
    }
    if (reversals.size() < 2) {
        return std::nullopt;
    }
    const auto first = reversals.begin() + 1;
    const auto last = reversals.begin() + std::min<std::size_t>(reversals.size(), 1u + counted);
    return std::accumulate(first, last, 0.0) / static_cast<double>(last - first);
}

// Guenter et al. 2012's pair and ramp rules: the lowest quality (the level that foveates most)
// "reported as equal to or better in quality than the non-foveated reference" (pair) or whose
// ramp was "incorrectly labeled ... or reported that quality did not change" (ramp). A level
// counts as so judged when at most half its trials were positive (the pair test shows each level
// four times, the ramp test twice). Empty when every level was told apart.
std::optional<double> lowestQualityJudgedEqual(std::span<const LevelCount> counts,
                                               bool higherFoveatesMore) {
    std::optional<double> found;
    for (const LevelCount& c : counts) {
        if (c.trials == 0 || 2 * c.positive > c.trials) {
            continue;
        }
        if (!found || (higherFoveatesMore ? c.level > *found : c.level < *found)) {
            found = c.level;
        }
    }
    return found;
}

// Guenter et al. 2012's slider: the level recorded when the participant stopped raising
// quality and compared with the reference; a participant's threshold is the mean over trials.
std::optional<double> sliderThreshold(const std::vector<TrialRecord>& trials) {
    double sum = 0.0;
    uint32_t n = 0;
    for (const TrialRecord& t : trials) {
        if (!t.sliderLevel) {
            continue;
        }
        sum += *t.sliderLevel;
        ++n;
    }
    return n == 0 ? std::nullopt : std::optional<double>(sum / n);
}

namespace {

std::optional<double> ruleThreshold(const StudyDesign& design, const Condition& condition,
                                    const std::vector<TrialRecord>& trials,
                                    std::span<const LevelCount> counts) {
    if (condition.placement.kind == PlacementKind::ThesisSeries) {
        return seriesThreshold(trials, condition.placement.reversals);
    }
    switch (design.procedure) {
    case Procedure::Pair:
    case Procedure::Ramp:
        return lowestQualityJudgedEqual(counts, infoOf(condition.vary).higherFoveatesMore);
    case Procedure::Slider:
        return sliderThreshold(trials);
    case Procedure::ForcedChoice:
    case Procedure::YesNo:
        break;
    }
    return std::nullopt;
}

ParticipantCondition analyseCell(const Cell& cell, const StudyDesign& design,
                                 const Condition& condition, const AnalysisSettings& settings,
                                 uint64_t seed) {
    ParticipantCondition pc;
    pc.participant = cell.participant;
    pc.condition = condition.name;
    pc.parameter = std::string(infoOf(condition.vary).name);
    pc.counts = countsOf(cell.trials);
    pc.flaggedTrials = cell.flagged;
    if (design.procedure != Procedure::Slider && !pc.counts.empty()) {
        if (settings.beforeFit) {
            settings.beforeFit();
        }
        pc.fit = fitPsychometric(pc.counts,
                                 fitSettingsFor(design, condition, cell.trials, settings, seed));
        pc.fitted = true;
    }
    pc.ruleThreshold = ruleThreshold(design, condition, cell.trials, pc.counts);
    return pc;
}

double mean(std::span<const double> v) {
    return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

// The sample standard deviation (n - 1); 0 for one value.
double sampleSd(std::span<const double> v) {
    if (v.size() < 2) {
        return 0.0;
    }
    const double m = mean(v);
    double ss = 0.0;
    for (const double x : v) {
        ss += (x - m) * (x - m);
    }
    return std::sqrt(ss / static_cast<double>(v.size() - 1));
}

// The group of rule thresholds alone (the slider, which has no fit): their mean and a
// percentile bootstrap interval over participants, as poolParticipants gives for fits.
GroupThreshold groupOfRules(std::span<const double> rules, uint32_t resamples, uint64_t seed) {
    GroupThreshold g;
    g.participants = static_cast<uint32_t>(rules.size());
    g.mean = mean(rules);
    g.sd = sampleSd(rules);
    std::mt19937_64 random(seed);
    std::uniform_int_distribution<std::size_t> pick(0, rules.size() - 1);
    std::vector<double> means(std::max(1u, resamples));
    for (double& m : means) {
        double sum = 0.0;
        for (std::size_t i = 0; i < rules.size(); ++i) {
            sum += rules[pick(random)];
        }
        m = sum / static_cast<double>(rules.size());
    }
    std::sort(means.begin(), means.end());
    const auto at = [&](double q) {
        return means[static_cast<std::size_t>(
            std::lround(q * static_cast<double>(means.size() - 1)))];
    };
    g.low = at(0.025);
    g.high = at(0.975);
    return g;
}

ConditionSummary summarise(const Condition& condition, const StudyDesign& design,
                           std::span<const ParticipantCondition> cells,
                           const std::vector<TrialRecord>& allTrials,
                           const AnalysisSettings& settings, uint64_t seed) {
    ConditionSummary summary;
    summary.condition = condition.name;
    summary.parameter = std::string(infoOf(condition.vary).name);
    std::vector<PsychometricFit> fits;
    std::vector<std::vector<LevelCount>> counts;
    std::vector<double> rules;
    for (const ParticipantCondition& pc : cells) {
        if (pc.fitted) {
            fits.push_back(pc.fit);
            counts.push_back(pc.counts);
        }
        if (pc.ruleThreshold) {
            rules.push_back(*pc.ruleThreshold);
        }
    }
    if (!rules.empty()) {
        summary.ruleMean = mean(rules);
        summary.ruleSd = sampleSd(rules);
    }
    if (!fits.empty()) {
        if (settings.beforeFit) {
            settings.beforeFit();
        }
        summary.group = poolParticipants(
            fits, counts, fitSettingsFor(design, condition, allTrials, settings, seed));
        summary.fitted = true;
    } else if (!rules.empty()) {
        summary.group = groupOfRules(rules, settings.bootstrap, seed);
    }
    return summary;
}

} // namespace

Analysis analyseJournals(std::span<const std::filesystem::path> journals,
                         const AnalysisSettings& settings) {
    if (journals.empty()) {
        throw JournalError("study analyse: no journal given");
    }
    std::optional<RunStart> first;
    std::string firstName;
    std::map<std::pair<std::string, std::string>, Cell> cells;
    for (const std::filesystem::path& path : journals) {
        const std::vector<json> lines = readJournal(path);
        RunStart run = readStart(lines, path);
        if (!first) {
            first = run;
            firstName = path.filename().string();
        } else if (run.designName != first->designName || run.designHash != first->designHash) {
            throw JournalError(path.filename().string() + ": design '" + run.designName +
                               "' (hash " + run.designHash + ") is not " + firstName + "'s '" +
                               first->designName + "' (hash " + first->designHash +
                               "): analyse one design's journals together");
        }
        collectTrials(lines, run, path, settings, cells);
    }
    const StudyDesign& design = first->design;
    Analysis analysis;
    analysis.design = design.name;
    uint64_t seed = settings.seed;
    for (const Condition& condition : design.conditions) {
        const std::size_t begin = analysis.participants.size();
        std::vector<TrialRecord> allTrials;
        for (const auto& [key, cell] : cells) {
            if (key.second != condition.name) {
                continue;
            }
            analysis.participants.push_back(analyseCell(cell, design, condition, settings, seed++));
            allTrials.insert(allTrials.end(), cell.trials.begin(), cell.trials.end());
        }
        const std::span<const ParticipantCondition> these(analysis.participants.data() + begin,
                                                          analysis.participants.size() - begin);
        analysis.conditions.push_back(
            summarise(condition, design, these, allTrials, settings, seed++));
    }
    return analysis;
}

namespace {

const char* shapeName(PsychometricShape shape) {
    switch (shape) {
    case PsychometricShape::Logistic:
        return "logistic";
    case PsychometricShape::CumulativeNormal:
        return "cumulative-normal";
    case PsychometricShape::Weibull:
        return "weibull";
    }
    return "logistic";
}

json fitJson(const PsychometricFit& fit) {
    const PsychometricFunction& f = fit.function;
    return {{"shape", shapeName(f.shape)},
            {"threshold", f.threshold},
            {"threshold_low", fit.thresholdLow},
            {"threshold_high", fit.thresholdHigh},
            {"slope", f.slope},
            {"slope_low", fit.slopeLow},
            {"slope_high", fit.slopeHigh},
            {"guess", f.guess},
            {"lapse", f.lapse},
            {"increasing", f.increasing},
            {"trials", fit.trials},
            {"log_likelihood", fit.logLikelihood},
            {"converged", fit.converged}};
}

json optionalJson(const std::optional<double>& v) {
    return v ? json(*v) : json(nullptr);
}

} // namespace

json toJson(const Analysis& analysis) {
    json participants = json::array();
    for (const ParticipantCondition& pc : analysis.participants) {
        json counts = json::array();
        for (const LevelCount& c : pc.counts) {
            counts.push_back({{"level", c.level}, {"trials", c.trials}, {"positive", c.positive}});
        }
        participants.push_back({{"participant", pc.participant},
                                {"condition", pc.condition},
                                {"parameter", pc.parameter},
                                {"counts", std::move(counts)},
                                {"fit", pc.fitted ? fitJson(pc.fit) : json(nullptr)},
                                {"rule_threshold", optionalJson(pc.ruleThreshold)},
                                {"flagged_trials", pc.flaggedTrials}});
    }
    json conditions = json::array();
    for (const ConditionSummary& s : analysis.conditions) {
        const GroupThreshold& g = s.group;
        conditions.push_back({{"condition", s.condition},
                              {"parameter", s.parameter},
                              {"participants", g.participants},
                              {"threshold_mean", g.participants > 0 ? json(g.mean) : json()},
                              {"threshold_sd", g.participants > 0 ? json(g.sd) : json()},
                              {"threshold_low", g.participants > 0 ? json(g.low) : json()},
                              {"threshold_high", g.participants > 0 ? json(g.high) : json()},
                              {"pooled_fit", s.fitted ? fitJson(g.pooled) : json(nullptr)},
                              {"rule_mean", optionalJson(s.ruleMean)},
                              {"rule_sd", optionalJson(s.ruleSd)}});
    }
    return {{"design", analysis.design},
            {"participants", std::move(participants)},
            {"conditions", std::move(conditions)}};
}

} // namespace gt::study
