#include "design.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "input_file.hpp"
#include "limits.hpp"

namespace gt::study {

namespace {

using nlohmann::json;

template <typename E> struct Named {
    E value;
    std::string_view name;
};

constexpr std::array<Named<Procedure>, 5> kProcedures{{{Procedure::ForcedChoice, "forced-choice"},
                                                       {Procedure::YesNo, "yes-no"},
                                                       {Procedure::Pair, "pair"},
                                                       {Procedure::Ramp, "ramp"},
                                                       {Procedure::Slider, "slider"}}};
constexpr std::array<Named<PlacementKind>, 5> kKinds{
    {{PlacementKind::Staircase, "staircase"},
     {PlacementKind::WeightedStaircase, "weighted-staircase"},
     {PlacementKind::ThesisSeries, "thesis-series"},
     {PlacementKind::QuestPlus, "quest-plus"},
     {PlacementKind::ConstantStimuli, "constant"}}};
constexpr std::array<Named<Method>, 3> kMethods{
    {{Method::Foveated, "foveated"}, {Method::Layers, "layers"}, {Method::Reference, "reference"}}};
constexpr std::array<Named<Interpolation>, 3> kInterps{{{Interpolation::NearestNeighbour, "nn"},
                                                        {Interpolation::ModifiedShepard, "msm"},
                                                        {Interpolation::Rbf, "rbf"}}};
constexpr std::array<Named<PsychometricShape>, 3> kShapes{
    {{PsychometricShape::Logistic, "logistic"},
     {PsychometricShape::CumulativeNormal, "cumulative-normal"},
     {PsychometricShape::Weibull, "weibull"}}};

// Guenter et al. 2012's two quality targets, as the render command's --slope takes them.
constexpr double kSlopeA = 0.0275;
constexpr double kSlopeB = 0.0220;

template <typename E, std::size_t N>
std::string nameOf(const std::array<Named<E>, N>& table, E value) {
    for (const auto& n : table) {
        if (n.value == value) {
            return std::string(n.name);
        }
    }
    return "?";
}

template <typename E, std::size_t N> std::string namesOf(const std::array<Named<E>, N>& table) {
    std::string names;
    for (const auto& n : table) {
        names += (names.empty() ? "" : ", ") + std::string(n.name);
    }
    return names;
}

// The shortest text that reads back as the same double ("0.1", not "0.10000000000000001").
std::string num(double v) {
    std::string s = json(v).dump();
    if (s.size() > 2 && s.compare(s.size() - 2, 2, ".0") == 0) {
        s.resize(s.size() - 2);
    }
    return s;
}

// A message stays on one line whatever the file holds: control characters in a name or a key
// are written as \xNN.
std::string oneLine(const std::string& text) {
    std::string out;
    for (const char c : text) {
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
            std::array<char, 8> hex{};
            std::snprintf(hex.data(), hex.size(), "\\x%02x", static_cast<unsigned char>(c));
            out += hex.data();
        } else {
            out += c;
        }
    }
    return out;
}

std::string child(const std::string& path, std::string_view key) {
    return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string item(const std::string& path, std::size_t i) {
    return path + "[" + std::to_string(i) + "]";
}

std::string typeName(const json& j) {
    if (j.is_number()) {
        return "a number";
    }
    if (j.is_string()) {
        return "a string";
    }
    if (j.is_boolean()) {
        return "true or false";
    }
    if (j.is_array()) {
        return "a list";
    }
    if (j.is_object()) {
        return "an object";
    }
    return "null";
}

bool namePattern(const std::string& s, std::string_view extra, std::size_t maxLength) {
    if (s.empty() || s.size() > maxLength) {
        return false;
    }
    return std::all_of(s.begin(), s.end(), [&](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
               extra.find(c) != std::string_view::npos;
    });
}

// Reads one JSON document into typed values, failing with "SOURCE: path: what" on the first bad
// field.
class Reader {
public:
    explicit Reader(std::string source) : mSource(std::move(source)) {}

    [[noreturn]] void fail(const std::string& path, const std::string& what) const {
        throw DesignError(oneLine(mSource + ": " + (path.empty() ? "" : path + ": ") + what));
    }

    void requireObject(const json& j, const std::string& path) const {
        if (!j.is_object()) {
            fail(path, "must be an object, not " + typeName(j));
        }
    }

    void checkKeys(const json& j, const std::string& path,
                   std::initializer_list<std::string_view> allowed) const {
        for (const auto& [key, value] : j.items()) {
            if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) {
                continue;
            }
            std::string list;
            for (std::string_view a : allowed) {
                list += (list.empty() ? "" : ", ") + std::string(a);
            }
            fail(child(path, key), "unknown key (allowed: " + list + ")");
        }
    }

    [[nodiscard]] double number(const json& j, const std::string& path, double min,
                                double max) const {
        if (!j.is_number()) {
            fail(path, "must be a number, not " + typeName(j));
        }
        const double v = j.get<double>();
        if (!std::isfinite(v) || v < min || v > max) {
            fail(path, num(v) + " is outside [" + num(min) + ", " + num(max) + "]");
        }
        return v;
    }

    [[nodiscard]] uint64_t whole(const json& j, const std::string& path, uint64_t min,
                                 uint64_t max) const {
        if (j.is_number_unsigned()) {
            const uint64_t v = j.get<uint64_t>();
            if (v < min || v > max) {
                fail(path, std::to_string(v) + " is outside [" + std::to_string(min) + ", " +
                               std::to_string(max) + "]");
            }
            return v;
        }
        const double v = number(j, path, static_cast<double>(min), static_cast<double>(max));
        if (v != std::floor(v)) {
            fail(path, num(v) + " is not a whole number");
        }
        return static_cast<uint64_t>(v);
    }

    [[nodiscard]] bool boolean(const json& j, const std::string& path) const {
        if (!j.is_boolean()) {
            fail(path, "must be true or false, not " + typeName(j));
        }
        return j.get<bool>();
    }

    [[nodiscard]] std::string text(const json& j, const std::string& path) const {
        if (!j.is_string()) {
            fail(path, "must be a string, not " + typeName(j));
        }
        return j.get<std::string>();
    }

    template <typename E, std::size_t N>
    [[nodiscard]] E choice(const json& j, const std::string& path,
                           const std::array<Named<E>, N>& table) const {
        const std::string s = text(j, path);
        for (const auto& n : table) {
            if (n.name == s) {
                return n.value;
            }
        }
        fail(path, "unknown value '" + s + "' (one of: " + namesOf(table) + ")");
    }

    [[nodiscard]] const std::string& source() const { return mSource; }

private:
    std::string mSource;
};

// Optional fields: `key` read into `out` when present.
const json* field(const json& j, std::string_view key) {
    const auto it = j.find(std::string(key));
    return it == j.end() ? nullptr : &*it;
}

void readTiming(const Reader& r, const json& j, const std::string& path, Timing& t) {
    r.requireObject(j, path);
    r.checkKeys(j, path,
                {"fixation_ms", "interval_ms", "blank_ms", "response_timeout_ms", "refresh_hz"});
    constexpr double kMaxMs = 600000.0;
    if (const json* f = field(j, "fixation_ms")) {
        t.fixationMs = r.number(*f, child(path, "fixation_ms"), 0, kMaxMs);
    }
    if (const json* f = field(j, "interval_ms")) {
        t.intervalMs = r.number(*f, child(path, "interval_ms"), 1, kMaxMs);
    }
    if (const json* f = field(j, "blank_ms")) {
        t.blankMs = r.number(*f, child(path, "blank_ms"), 0, kMaxMs);
    }
    if (const json* f = field(j, "response_timeout_ms")) {
        t.responseTimeoutMs = r.number(*f, child(path, "response_timeout_ms"), 0, kMaxMs);
    }
    if (const json* f = field(j, "refresh_hz")) {
        t.refreshHz = r.number(*f, child(path, "refresh_hz"), 0, 1000);
        if (t.refreshHz > 0 && t.refreshHz < 1) {
            r.fail(child(path, "refresh_hz"), "0 or [1, 1000]");
        }
    }
}

void readGaze(const Reader& r, const json& j, const std::string& path, GazeRules& g) {
    r.requireObject(j, path);
    r.checkKeys(j, path,
                {"fixation_radius_deg", "repeat_on_saccade", "saccade_deg_per_s", "max_repeats",
                 "gaze_lost_ms"});
    if (const json* f = field(j, "fixation_radius_deg")) {
        g.fixationRadiusDeg = r.number(*f, child(path, "fixation_radius_deg"), 0, 90);
    }
    if (const json* f = field(j, "repeat_on_saccade")) {
        g.repeatOnSaccade = r.boolean(*f, child(path, "repeat_on_saccade"));
    }
    if (const json* f = field(j, "saccade_deg_per_s")) {
        g.saccadeDegPerS = r.number(*f, child(path, "saccade_deg_per_s"), 1e-3, 10000);
    }
    if (const json* f = field(j, "max_repeats")) {
        g.maxRepeats = static_cast<uint32_t>(r.whole(*f, child(path, "max_repeats"), 0, 100));
    }
    if (const json* f = field(j, "gaze_lost_ms")) {
        g.gazeLostMs = r.number(*f, child(path, "gaze_lost_ms"), 1e-3, 600000);
    }
}

std::vector<SceneChoice> readScenes(const Reader& r, const json& j, const std::string& path) {
    if (!j.is_array()) {
        r.fail(path, "must be a list, not " + typeName(j));
    }
    if (j.empty()) {
        r.fail(path, "is empty (name at least one scene, or leave it out)");
    }
    std::vector<SceneChoice> scenes;
    for (std::size_t i = 0; i < j.size(); ++i) {
        const std::string p = item(path, i);
        SceneChoice s;
        if (j[i].is_string()) {
            s.scene = j[i].get<std::string>();
        } else {
            r.requireObject(j[i], p);
            r.checkKeys(j[i], p, {"scene", "camera", "camera_path"});
            const json* scene = field(j[i], "scene");
            if (scene == nullptr) {
                r.fail(child(p, "scene"), "missing");
            }
            s.scene = r.text(*scene, child(p, "scene"));
            if (const json* f = field(j[i], "camera")) {
                s.camera = r.text(*f, child(p, "camera"));
            }
            if (const json* f = field(j[i], "camera_path")) {
                s.cameraPath = r.text(*f, child(p, "camera_path"));
            }
        }
        if (s.scene.empty()) {
            r.fail(p, "the scene is empty");
        }
        scenes.push_back(std::move(s));
    }
    return scenes;
}

double readSlope(const Reader& r, const json& j, const std::string& path) {
    if (j.is_string()) {
        const std::string s = j.get<std::string>();
        if (s == "A") {
            return kSlopeA;
        }
        if (s == "B") {
            return kSlopeB;
        }
        r.fail(path, "unknown value '" + s + "' (A, B or a number)");
    }
    const ParameterInfo& info = infoOf(Parameter::Slope);
    return r.number(j, path, info.min, info.max);
}

// The render keys present in `j` over `out`; `varied` may not be set (its levels set it).
void readRender(const Reader& r, const json& j, const std::string& path,
                std::optional<Parameter> varied, RenderChoice& out) {
    for (const ParameterInfo& info : parameters()) {
        const json* f = field(j, info.name);
        if (f == nullptr) {
            continue;
        }
        const std::string p = child(path, info.name);
        if (varied == info.parameter) {
            r.fail(p, "is the varied parameter: its levels come from \"levels\"");
        }
        const double v = info.parameter == Parameter::Slope ? readSlope(r, *f, p)
                         : info.integer
                             ? static_cast<double>(r.whole(*f, p, static_cast<uint64_t>(info.min),
                                                           static_cast<uint64_t>(info.max)))
                             : r.number(*f, p, info.min, info.max);
        out = withLevel(out, info.parameter, v);
    }
    if (const json* f = field(j, "method")) {
        out.method = r.choice(*f, child(path, "method"), kMethods);
    }
    if (const json* f = field(j, "interp")) {
        out.interp = r.choice(*f, child(path, "interp"), kInterps);
    }
    if (const json* f = field(j, "spp")) {
        out.spp = static_cast<uint32_t>(r.whole(*f, child(path, "spp"), 1, 4096));
    }
    if (const json* f = field(j, "taa")) {
        out.taa = r.boolean(*f, child(path, "taa"));
    }
}

LevelGrid readLevels(const Reader& r, const json& j, const std::string& path,
                     const ParameterInfo& info) {
    const std::string range = "[" + num(info.min) + ", " + num(info.max) + "]";
    auto level = [&](const json& v, const std::string& p) {
        if (!v.is_number()) {
            r.fail(p, "must be a number, not " + typeName(v));
        }
        const double x = v.get<double>();
        if (!std::isfinite(x) || x < info.min || x > info.max) {
            r.fail(p, num(x) + " is outside " + std::string(info.name) + "'s range " + range);
        }
        if (info.integer && x != std::floor(x)) {
            r.fail(p, num(x) + " is not a whole number (" + std::string(info.name) +
                          " takes whole numbers)");
        }
        return x;
    };
    LevelGrid grid;
    if (j.is_array()) {
        if (j.empty()) {
            r.fail(path, "the list of levels is empty");
        }
        for (std::size_t i = 0; i < j.size(); ++i) {
            grid.values.push_back(level(j[i], item(path, i)));
        }
        std::sort(grid.values.begin(), grid.values.end());
        grid.values.erase(std::unique(grid.values.begin(), grid.values.end()), grid.values.end());
        grid.min = grid.values.front();
        grid.max = grid.values.back();
        grid.step = 0.0;
        return grid;
    }
    if (!j.is_object()) {
        r.fail(path, "must be {\"min\", \"max\", \"step\"} or a list of levels");
    }
    r.checkKeys(j, path, {"min", "max", "step"});
    for (std::string_view key : {"min", "max"}) {
        if (field(j, key) == nullptr) {
            r.fail(child(path, key), "missing");
        }
    }
    grid.min = level(j["min"], child(path, "min"));
    grid.max = level(j["max"], child(path, "max"));
    if (grid.min >= grid.max) {
        r.fail(child(path, "max"), num(grid.max) + " is not above min " + num(grid.min));
    }
    grid.step = info.integer ? 1.0 : 0.0;
    if (const json* f = field(j, "step")) {
        grid.step = r.number(*f, child(path, "step"), 0, (grid.max - grid.min) * (1.0 + 1e-9));
        if (info.integer && (grid.step < 1 || grid.step != std::floor(grid.step))) {
            r.fail(child(path, "step"), num(grid.step) + " is not a whole number of at least 1 (" +
                                            std::string(info.name) + " takes whole numbers)");
        }
    }
    return grid;
}

// The grid's smallest step between two allowed levels: a staircase step below it never moves.
double gridStep(const LevelGrid& grid) {
    if (!grid.values.empty()) {
        double gap = std::numeric_limits<double>::infinity();
        for (std::size_t i = 1; i < grid.values.size(); ++i) {
            gap = std::min(gap, grid.values[i] - grid.values[i - 1]);
        }
        return std::isfinite(gap) ? gap : 1.0;
    }
    return grid.step > 0 ? grid.step : (grid.max - grid.min) / 63.0;
}

void readPlacementNumbers(const Reader& r, const json& j, const std::string& path,
                          PlacementSettings& s) {
    auto count = [&](std::string_view key, uint32_t& out, uint64_t min, uint64_t max) {
        if (const json* f = field(j, key)) {
            out = static_cast<uint32_t>(r.whole(*f, child(path, key), min, max));
        }
    };
    count("down", s.down, 1, 10);
    count("up", s.up, 1, 10);
    count("reversals", s.reversals, 1, 1000);
    count("skip_reversals", s.skipReversals, 0, 1000);
    count("max_trials", s.maxTrials, 1, 10000);
    count("repeats", s.repeats, 1, 1000);
    if (s.skipReversals >= s.reversals) {
        r.fail(child(path, "skip_reversals"), std::to_string(s.skipReversals) +
                                                  " leaves none of the " +
                                                  std::to_string(s.reversals) + " reversals");
    }
    if (const json* f = field(j, "target")) {
        s.target = r.number(*f, child(path, "target"), 1e-3, 0.999);
    }
    if (const json* f = field(j, "guess")) {
        s.guess = r.number(*f, child(path, "guess"), 0, 0.99);
    }
    if (const json* f = field(j, "shape")) {
        s.shape = r.choice(*f, child(path, "shape"), kShapes);
    }
    auto list = [&](std::string_view key, std::vector<double>& out, double min, double max) {
        const json* f = field(j, key);
        if (f == nullptr) {
            return;
        }
        const std::string p = child(path, key);
        if (!f->is_array() || f->empty()) {
            r.fail(p, "must be a non-empty list of numbers");
        }
        out.clear();
        for (std::size_t i = 0; i < f->size(); ++i) {
            out.push_back(r.number((*f)[i], item(p, i), min, max));
        }
    };
    list("quest_slopes", s.questSlopes, 1e-3, 1e4);
    list("quest_lapses", s.questLapses, 0, 0.5);
}

// Settings that cannot work together, found before the first trial.
void checkPlacement(const Reader& r, const std::string& path, Procedure procedure,
                    const PlacementSettings& s) {
    if (procedure == Procedure::Slider && s.kind != PlacementKind::ConstantStimuli) {
        r.fail(child(path, "kind"), "the slider test moves the level itself: only \"constant\" "
                                    "works with it (\"repeats\": slider trials)");
    }
    if (s.kind == PlacementKind::WeightedStaircase && s.target <= s.guess) {
        r.fail(child(path, "target"), num(s.target) + " is not above the guess rate " +
                                          num(s.guess) + " (chance alone gets there)");
    }
    if (s.start < s.grid.min || s.start > s.grid.max) {
        r.fail(child(path, "start"), num(s.start) + " is outside the levels [" + num(s.grid.min) +
                                         ", " + num(s.grid.max) + "]");
    }
    const double minStep = gridStep(s.grid) * (1.0 - 1e-9);
    if (s.step < minStep) {
        r.fail(child(path, "step"), num(s.step) + " is below the levels' step " +
                                        num(gridStep(s.grid)) + " (the level would not move)");
    }
    if (s.finalStep < minStep) {
        r.fail(child(path, "final_step"), num(s.finalStep) + " is below the levels' step " +
                                              num(gridStep(s.grid)) +
                                              " (the level would not move)");
    }
    if (s.finalStep > s.step) {
        r.fail(child(path, "final_step"), num(s.finalStep) + " is larger than step " + num(s.step));
    }
}

PlacementSettings readPlacement(const Reader& r, const json* j, const std::string& path,
                                Procedure procedure, const LevelGrid& grid,
                                const ParameterInfo& info) {
    PlacementSettings s;
    s.grid = grid;
    s.higherFoveatesMore = info.higherFoveatesMore;
    s.kind =
        procedure == Procedure::Slider ? PlacementKind::ConstantStimuli : PlacementKind::Staircase;
    s.guess = procedure == Procedure::ForcedChoice ? 0.5 : 0.0;
    s.step = 2.0 * gridStep(grid);
    s.finalStep = gridStep(grid);
    if (j != nullptr) {
        r.requireObject(*j, path);
        r.checkKeys(*j, path,
                    {"kind", "start", "step", "final_step", "down", "up", "target", "reversals",
                     "skip_reversals", "max_trials", "repeats", "quest_slopes", "quest_lapses",
                     "guess", "shape"});
        if (const json* f = field(*j, "kind")) {
            s.kind = r.choice(*f, child(path, "kind"), kKinds);
        }
        readPlacementNumbers(r, *j, path, s);
    }
    const double mostFoveated = info.higherFoveatesMore ? grid.max : grid.min;
    const double leastFoveated = info.higherFoveatesMore ? grid.min : grid.max;
    s.start = s.kind == PlacementKind::ThesisSeries ? leastFoveated : mostFoveated;
    // A step as long as the whole range is allowed; the tolerance keeps 0.03 - 0.01 >= 0.02.
    const double span = (grid.max - grid.min) * (1.0 + 1e-9);
    if (j != nullptr) {
        if (const json* f = field(*j, "start")) {
            s.start = r.number(*f, child(path, "start"), -1e9, 1e9);
        }
        if (const json* f = field(*j, "step")) {
            s.step = r.number(*f, child(path, "step"), 1e-9, span);
        }
        if (const json* f = field(*j, "final_step")) {
            s.finalStep = r.number(*f, child(path, "final_step"), 1e-9, span);
        }
    }
    checkPlacement(r, path, procedure, s);
    try {
        (void)makePlacement(s, 1); // what the placement itself refuses, named here
    } catch (const std::invalid_argument& e) {
        r.fail(path, e.what());
    }
    return s;
}

// The method that uses `p`: the point set's settings are the foveated method's, the MAR slope
// and the layer count the layers method's (Guenter et al. 2012).
Method methodOf(Parameter p) {
    return p == Parameter::Slope || p == Parameter::Layers ? Method::Layers : Method::Foveated;
}

Condition readCondition(const Reader& r, const json& j, const std::string& path,
                        Procedure procedure) {
    r.requireObject(j, path);
    r.checkKeys(j, path,
                {"name", "vary", "levels", "placement", "comparison", "method", "scale",
                 "rays-per-point", "interp", "k", "slope", "layers", "spp", "taa"});
    Condition c;
    for (std::string_view key : {"name", "vary", "levels"}) {
        if (field(j, key) == nullptr) {
            r.fail(child(path, key), "missing");
        }
    }
    c.name = r.text(j["name"], child(path, "name"));
    if (!namePattern(c.name, "_.-", 64)) {
        r.fail(child(path, "name"), "'" + c.name + "' is not 1-64 letters, digits, '_', '.', '-'");
    }
    const std::string vary = r.text(j["vary"], child(path, "vary"));
    const std::optional<Parameter> p = parameterNamed(vary);
    if (!p) {
        r.fail(child(path, "vary"),
               "unknown parameter '" + vary + "' (one of: " + parameterNames() + ")");
    }
    c.vary = *p;
    const ParameterInfo& info = infoOf(c.vary);
    c.base.method = methodOf(c.vary);
    readRender(r, j, path, c.vary, c.base);
    if (c.base.method == Method::Reference) {
        r.fail(child(path, "method"), "a condition is foveated or layers; the reference is "
                                      "its comparison");
    }
    if (c.base.method != methodOf(c.vary)) {
        r.fail(child(path, "vary"), vary + " is a setting of the " + methodName(methodOf(c.vary)) +
                                        " method, not of " + methodName(c.base.method));
    }
    if (c.vary == Parameter::K && c.base.interp == Interpolation::NearestNeighbour) {
        r.fail(child(path, "vary"), "k needs interp msm or rbf (nn uses one neighbour)");
    }
    const LevelGrid grid = readLevels(r, j["levels"], child(path, "levels"), info);
    c.placement =
        readPlacement(r, field(j, "placement"), child(path, "placement"), procedure, grid, info);
    const PlacementKind kind = c.placement.kind;
    if (grid.values.empty() && grid.step == 0.0 && kind != PlacementKind::QuestPlus &&
        kind != PlacementKind::ConstantStimuli) {
        r.fail(child(path, "levels.step"), "a " + placementKindName(kind) +
                                               " moves on a grid: give a step > 0 (every level's "
                                               "point set is built before the first trial)");
    }
    if (const json* f = field(j, "comparison")) {
        const std::string cp = child(path, "comparison");
        r.requireObject(*f, cp);
        r.checkKeys(
            *f, cp,
            {"method", "scale", "rays-per-point", "interp", "k", "slope", "layers", "spp", "taa"});
        RenderChoice comparison = c.base;
        readRender(r, *f, cp, std::nullopt, comparison);
        c.comparison = comparison;
    }
    return c;
}

std::vector<Condition> readConditions(const Reader& r, const json& j, Procedure procedure) {
    if (!j.is_array()) {
        r.fail("conditions", "must be a list, not " + typeName(j));
    }
    if (j.empty()) {
        r.fail("conditions", "the list of conditions is empty (at least one)");
    }
    std::vector<Condition> conditions;
    for (std::size_t i = 0; i < j.size(); ++i) {
        Condition c = readCondition(r, j[i], item("conditions", i), procedure);
        for (const Condition& earlier : conditions) {
            if (earlier.name == c.name) {
                r.fail(item("conditions", i) + ".name",
                       "'" + c.name + "' names an earlier condition too");
            }
        }
        conditions.push_back(std::move(c));
    }
    return conditions;
}

void readSchedule(const Reader& r, const json& j, StudyDesign& d) {
    if (const json* f = field(j, "seed")) {
        d.seed = r.whole(*f, "seed", 0, std::numeric_limits<uint64_t>::max());
    }
    if (const json* f = field(j, "practice_trials")) {
        d.practiceTrials = static_cast<uint32_t>(r.whole(*f, "practice_trials", 0, 1000));
    }
    if (const json* f = field(j, "break_every")) {
        d.breakEvery = static_cast<uint32_t>(r.whole(*f, "break_every", 0, 100000));
    }
    if (const json* f = field(j, "break_between_conditions")) {
        d.breakBetweenConditions = r.boolean(*f, "break_between_conditions");
    }
    if (const json* f = field(j, "catch_rate")) {
        d.catchRate = r.number(*f, "catch_rate", 0, 0.5);
        if (d.catchRate > 0 && d.procedure != Procedure::YesNo) {
            r.fail("catch_rate", "only the yes-no procedure has catch trials");
        }
    }
    if (const json* f = field(j, "ramp_steps")) {
        d.rampSteps = static_cast<uint32_t>(r.whole(*f, "ramp_steps", 2, 20));
    }
    if (const json* f = field(j, "fixation_x")) {
        d.fixationX = r.number(*f, "fixation_x", 0, 1);
    }
    if (const json* f = field(j, "fixation_y")) {
        d.fixationY = r.number(*f, "fixation_y", 0, 1);
    }
    if (const json* f = field(j, "hmd")) {
        d.hmd = r.text(*f, "hmd");
    }
    if (const json* f = field(j, "width")) {
        d.width = static_cast<uint32_t>(r.whole(*f, "width", 16, 16384));
    }
    if (const json* f = field(j, "height")) {
        d.height = static_cast<uint32_t>(r.whole(*f, "height", 16, 16384));
    }
}

json renderToJson(const RenderChoice& c, std::optional<Parameter> varied) {
    json j{{"method", methodName(c.method)},
           {"interp", interpolationName(c.interp)},
           {"spp", c.spp},
           {"taa", c.taa}};
    const std::array<std::pair<Parameter, json>, 5> values{
        {{Parameter::Scale, c.scale},
         {Parameter::RaysPerPoint, c.raysPerPoint},
         {Parameter::K, c.k},
         {Parameter::Slope, c.slope},
         {Parameter::Layers, c.layers}}};
    for (const auto& [p, v] : values) {
        if (p != varied) {
            j[std::string(infoOf(p).name)] = v;
        }
    }
    return j;
}

json placementToJson(const PlacementSettings& s) {
    return json{{"kind", placementKindName(s.kind)},
                {"start", s.start},
                {"step", s.step},
                {"final_step", s.finalStep},
                {"down", s.down},
                {"up", s.up},
                {"target", s.target},
                {"reversals", s.reversals},
                {"skip_reversals", s.skipReversals},
                {"max_trials", s.maxTrials},
                {"repeats", s.repeats},
                {"quest_slopes", s.questSlopes},
                {"quest_lapses", s.questLapses},
                {"guess", s.guess},
                {"shape", nameOf(kShapes, s.shape)}};
}

json conditionToJson(const Condition& c) {
    json j = renderToJson(c.base, c.vary);
    j["name"] = c.name;
    j["vary"] = std::string(infoOf(c.vary).name);
    const LevelGrid& g = c.placement.grid;
    j["levels"] =
        g.values.empty() ? json{{"min", g.min}, {"max", g.max}, {"step", g.step}} : json(g.values);
    j["placement"] = placementToJson(c.placement);
    if (c.comparison) {
        j["comparison"] = renderToJson(*c.comparison, std::nullopt);
    }
    return j;
}

} // namespace

std::string procedureName(Procedure procedure) {
    return nameOf(kProcedures, procedure);
}
std::string placementKindName(PlacementKind kind) {
    return nameOf(kKinds, kind);
}
std::string methodName(Method method) {
    return nameOf(kMethods, method);
}
std::string interpolationName(Interpolation interp) {
    return nameOf(kInterps, interp);
}

StudyDesign parseDesign(const nlohmann::json& doc, const std::string& source) {
    const Reader r(source);
    if (!doc.is_object()) {
        r.fail("", "a design is a JSON object, not " + typeName(doc));
    }
    r.checkKeys(doc, "",
                {"name", "description", "procedure", "seed", "practice_trials", "break_every",
                 "break_between_conditions", "catch_rate", "ramp_steps", "fixation_x", "fixation_y",
                 "hmd", "width", "height", "timing", "gaze", "scenes", "conditions"});
    StudyDesign d;
    for (std::string_view key : {"name", "procedure", "conditions"}) {
        if (field(doc, key) == nullptr) {
            r.fail(std::string(key), "missing");
        }
    }
    d.name = r.text(doc["name"], "name");
    if (!namePattern(d.name, "_-", 64)) {
        r.fail("name", "'" + d.name + "' is not 1-64 letters, digits, '_' or '-'");
    }
    if (const json* f = field(doc, "description")) {
        d.description = r.text(*f, "description");
    }
    d.procedure = r.choice(doc["procedure"], "procedure", kProcedures);
    readSchedule(r, doc, d);
    if (const json* f = field(doc, "timing")) {
        readTiming(r, *f, "timing", d.timing);
    }
    if (const json* f = field(doc, "gaze")) {
        readGaze(r, *f, "gaze", d.gaze);
    }
    d.scenes = {SceneChoice{}};
    if (const json* f = field(doc, "scenes")) {
        d.scenes = readScenes(r, *f, "scenes");
    }
    d.conditions = readConditions(r, doc["conditions"], d.procedure);
    return d;
}

StudyDesign loadDesign(const std::filesystem::path& path) {
    std::string text;
    try {
        text = io::readInputFile(path, io::limits::kJsonDocumentBytes);
    } catch (const io::InputError& e) {
        throw DesignError(e.what());
    }
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        // nlohmann's text starts "[json.exception.parse_error.101] parse error at line 3, ...";
        // a number beyond a double's range is its out_of_range.406 ("number overflow ...").
        std::string what = e.what();
        const auto close = what.find("] ");
        if (close != std::string::npos) {
            what = what.substr(close + 2);
        }
        throw DesignError(oneLine(path.string() + ": not JSON: " + what));
    }
    return parseDesign(doc, path.string());
}

nlohmann::json designToJson(const StudyDesign& d) {
    json scenes = json::array();
    for (const SceneChoice& s : d.scenes) {
        scenes.push_back({{"scene", s.scene}, {"camera", s.camera}, {"camera_path", s.cameraPath}});
    }
    json conditions = json::array();
    for (const Condition& c : d.conditions) {
        conditions.push_back(conditionToJson(c));
    }
    return json{{"name", d.name},
                {"description", d.description},
                {"procedure", procedureName(d.procedure)},
                {"seed", d.seed},
                {"practice_trials", d.practiceTrials},
                {"break_every", d.breakEvery},
                {"break_between_conditions", d.breakBetweenConditions},
                {"catch_rate", d.catchRate},
                {"ramp_steps", d.rampSteps},
                {"fixation_x", d.fixationX},
                {"fixation_y", d.fixationY},
                {"hmd", d.hmd},
                {"width", d.width},
                {"height", d.height},
                {"timing",
                 {{"fixation_ms", d.timing.fixationMs},
                  {"interval_ms", d.timing.intervalMs},
                  {"blank_ms", d.timing.blankMs},
                  {"response_timeout_ms", d.timing.responseTimeoutMs},
                  {"refresh_hz", d.timing.refreshHz}}},
                {"gaze",
                 {{"fixation_radius_deg", d.gaze.fixationRadiusDeg},
                  {"repeat_on_saccade", d.gaze.repeatOnSaccade},
                  {"saccade_deg_per_s", d.gaze.saccadeDegPerS},
                  {"max_repeats", d.gaze.maxRepeats},
                  {"gaze_lost_ms", d.gaze.gazeLostMs}}},
                {"scenes", scenes},
                {"conditions", conditions}};
}

std::string designHash(const StudyDesign& design) {
    // FNV-1a, 64 bits: stable across builds and machines (std::hash is neither).
    uint64_t h = 14695981039346656037ULL;
    for (const unsigned char c : designToJson(design).dump()) {
        h = (h ^ c) * 1099511628211ULL;
    }
    std::array<char, 17> hex{};
    std::snprintf(hex.data(), hex.size(), "%016llx", static_cast<unsigned long long>(h));
    return hex.data();
}

RenderChoice comparisonOf(const Condition& condition) {
    if (condition.comparison) {
        return *condition.comparison;
    }
    RenderChoice reference = condition.base;
    reference.method = Method::Reference;
    return reference;
}

} // namespace gt::study
