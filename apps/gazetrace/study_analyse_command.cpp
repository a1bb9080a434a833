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
#include "scene/image_io.hpp"
#include "simulation.hpp"
#include "stop_request.hpp"

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
        for (const study::LevelCount& c : pc.counts) {
            trials += c.trials;
        }
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
        if (pc.condition != condition) {
            continue;
        }
        for (const study::LevelCount& c : pc.counts) {
            lo = std::min(lo, c.level);
            hi = std::max(hi, c.level);
        }
        if (pc.ruleThreshold) {
            lo = std::min(lo, *pc.ruleThreshold);
            hi = std::max(hi, *pc.ruleThreshold);
        }
    }
    if (lo > hi) {
        return {0.0, 1.0};
    }
    if (hi - lo < 1e-12) {
        return {lo - 0.5 * std::max(std::abs(lo), 1e-3), hi + 0.5 * std::max(std::abs(hi), 1e-3)};
    }
    return {lo, hi};
}

PsychometricPanel panelOf(const study::Analysis& a, const study::ConditionSummary& s) {
    PsychometricPanel panel;
    panel.title = "condition " + s.condition;
    std::tie(panel.xMin, panel.xMax) = levelRange(a, s.condition);
    panel.xTitle = s.parameter + " (level)";
    for (const study::ParticipantCondition& pc : a.participants) {
        if (pc.condition != s.condition) {
            continue;
        }
        PsychometricSeries series;
        series.name = pc.participant;
        for (const study::LevelCount& c : pc.counts) {
            if (c.trials == 0) {
                continue;
            }
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
    if (s.group.participants > 0) {
        panel.group = {{s.group.mean, s.group.low, s.group.high}};
    }
    return panel;
}

} // namespace

nlohmann::json runStudyAnalyse(const StudyAnalyseOptions& options) {
    const std::vector<fs::path> journals(options.journals.begin(), options.journals.end());
    std::vector<io::RunFile> inputs;
    inputs.reserve(journals.size());
    for (const fs::path& j : journals) {
        inputs.push_back({"journals", j});
    }
    std::vector<io::RunFile> outputs;
    for (const char* name : {"thresholds.json", "thresholds.csv", "psychometric.png"}) {
        outputs.push_back({"--out", fs::path(options.out) / name});
    }
    io::refuseOutputThatIsInput(outputs, inputs);

    const study::Analysis analysis = study::analyseJournals(
        journals, {options.excludeFlagged, options.bootstrap, options.seed, throwIfStopRequested});
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
    for (const study::ConditionSummary& s : analysis.conditions) {
        panels.push_back(panelOf(analysis, s));
    }
    const quality::RgbaImage plot = psychometricImage(panels);
    image::writePngAtomic(folder.file("psychometric.png"), plot.width, plot.height, plot.pixels);
    folder.commit();
    return result;
}

namespace {

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

} // namespace

nlohmann::json runStudySimulate(const StudySimulateOptions& options) {
    const std::vector<io::RunFile> inputs{{"--design", options.design}};
    io::refuseOutputThatIsInput(std::vector<io::RunFile>{{"--json", options.json}}, inputs);
    if (!options.json.empty()) {
        io::checkOutputFile(options.json);
    }
    const study::StudyDesign design = study::loadDesign(options.design);

    std::optional<ScratchFolder> scratch;
    fs::path folder;
    if (options.journals.empty()) {
        folder = scratch.emplace().path();
    } else {
        folder = options.journals;
        fs::create_directories(folder);
    }
    study::DesignSimulationSettings settings;
    settings.observers = options.observers;
    settings.threshold = options.threshold;
    settings.slope = options.slope;
    settings.lapse = options.lapse;
    settings.seed = options.seed;
    settings.bootstrap = kSimulateBootstrap;
    settings.beforeParticipant = throwIfStopRequested; // SIGINT: the scratch folder goes
    const study::DesignSimulation sim = study::simulateDesign(design, settings, folder);
    json conditions = json::array();
    for (const study::ConditionRecovery& c : sim.conditions) {
        conditions.push_back(study::toJson(design, c));
    }
    json result{{"design", design.name},
                {"procedure", study::procedureName(design.procedure)},
                {"observers", options.observers},
                {"seed", options.seed},
                {"bootstrap", kSimulateBootstrap},
                {"journals", options.journals.empty() ? json(nullptr) : json(options.journals)},
                {"conditions", std::move(conditions)}};
    if (!options.json.empty()) {
        io::writeFileAtomic(options.json, result.dump(2) + "\n");
    }
    return result;
}

} // namespace gt::app
