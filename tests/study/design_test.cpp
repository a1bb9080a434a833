#include <gtest/gtest.h>

#include "design.hpp"

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace gt::study {
namespace {

using nlohmann::json;

json minimalDesign() {
    return json::parse(R"({
        "name": "thesis-scale",
        "procedure": "forced-choice",
        "conditions": [
            {"name": "scale", "vary": "scale", "levels": {"min": 1.0, "max": 3.0, "step": 0.1}}
        ]
    })");
}

// The one-line message parseDesign gives for `design`, or "" when it parses.
std::string errorOf(const json& design) {
    try {
        (void)parseDesign(design, "t.json");
    } catch (const DesignError& e) {
        return e.what();
    }
    return "";
}

TEST(Design, MinimalDesignFillsTheDefaults) {
    const StudyDesign d = parseDesign(minimalDesign(), "t.json");
    EXPECT_EQ(d.name, "thesis-scale");
    EXPECT_EQ(d.procedure, Procedure::ForcedChoice);
    ASSERT_EQ(d.conditions.size(), 1u);
    const Condition& c = d.conditions[0];
    EXPECT_EQ(c.vary, Parameter::Scale);
    EXPECT_EQ(c.base.method, Method::Foveated);
    EXPECT_DOUBLE_EQ(c.placement.grid.min, 1.0);
    EXPECT_DOUBLE_EQ(c.placement.grid.max, 3.0);
    EXPECT_TRUE(c.placement.higherFoveatesMore);
    // A staircase starts at the easiest level: the most foveated (the largest scale).
    EXPECT_DOUBLE_EQ(c.placement.start, 3.0);
    EXPECT_DOUBLE_EQ(c.placement.step, 0.2);
    EXPECT_DOUBLE_EQ(c.placement.finalStep, 0.1);
    EXPECT_DOUBLE_EQ(c.placement.guess, 0.5);
    ASSERT_EQ(d.scenes.size(), 1u);
    EXPECT_EQ(d.scenes[0].scene, "builtin:market");
    EXPECT_FALSE(c.comparison);
    EXPECT_EQ(comparisonOf(c).method, Method::Reference);
}

TEST(Design, ReadsEveryField) {
    json j = minimalDesign();
    j["procedure"] = "yes-no";
    j["catch_rate"] = 0.2;
    j["seed"] = 18446744073709551615ULL;
    j["timing"] = {{"interval_ms", 800}, {"refresh_hz", 90}};
    j["gaze"] = {{"fixation_radius_deg", 2.5}, {"repeat_on_saccade", true}};
    j["scenes"] =
        json::array({"builtin:cornell", {{"scene", "builtin:market"}, {"camera_path", "p.csv"}}});
    j["conditions"].push_back(
        json::parse(R"({"name": "mar", "vary": "slope", "levels": [0.03, 0.01, 0.02],
        "layers": 4, "comparison": {"slope": "B"},
        "placement": {"kind": "thesis-series", "step": 0.02, "final_step": 0.01}})"));
    const StudyDesign d = parseDesign(j, "t.json");
    EXPECT_EQ(d.seed, 18446744073709551615ULL);
    EXPECT_DOUBLE_EQ(d.catchRate, 0.2);
    EXPECT_DOUBLE_EQ(d.timing.intervalMs, 800.0);
    EXPECT_DOUBLE_EQ(d.timing.refreshHz, 90.0);
    EXPECT_DOUBLE_EQ(d.gaze.fixationRadiusDeg, 2.5);
    ASSERT_EQ(d.scenes.size(), 2u);
    EXPECT_EQ(d.scenes[0].scene, "builtin:cornell");
    EXPECT_EQ(d.scenes[1].cameraPath, "p.csv");
    const Condition& mar = d.conditions[1];
    EXPECT_EQ(mar.base.method, Method::Layers); // slope is the layers method's
    EXPECT_EQ(mar.base.layers, 4u);
    EXPECT_EQ(mar.placement.grid.values, (std::vector<double>{0.01, 0.02, 0.03}));
    // The thesis series ascends from the least foveated level: the smallest slope.
    EXPECT_DOUBLE_EQ(mar.placement.start, 0.01);
    ASSERT_TRUE(mar.comparison);
    EXPECT_DOUBLE_EQ(mar.comparison->slope, 0.0220);
    EXPECT_EQ(mar.comparison->layers, 4u); // the comparison starts from the condition's settings
}

TEST(Design, RoundTripsThroughItsJson) {
    json j = minimalDesign();
    j["conditions"][0]["interp"] = "msm";
    j["conditions"][0]["comparison"] = {{"method", "layers"}, {"slope", 0.02}};
    const StudyDesign d = parseDesign(j, "t.json");
    const json written = designToJson(d);
    const StudyDesign again = parseDesign(written, "journal");
    EXPECT_EQ(designToJson(again), written);
    EXPECT_EQ(designHash(again), designHash(d));
    j["conditions"][0]["levels"]["max"] = 2.9;
    EXPECT_NE(designHash(parseDesign(j, "t.json")), designHash(d));
}

TEST(Design, UnknownParameterNamesTheFieldAndTheKnownOnes) {
    json j = minimalDesign();
    j["conditions"][0]["vary"] = "scal";
    EXPECT_EQ(errorOf(j), "t.json: conditions[0].vary: unknown parameter 'scal' (one of: scale, "
                          "rays-per-point, k, slope, layers)");
}

TEST(Design, LevelOutsideTheParametersRange) {
    json j = minimalDesign();
    j["conditions"][0]["levels"]["max"] = 9.0;
    EXPECT_EQ(errorOf(j), "t.json: conditions[0].levels.max: 9 is outside scale's range [0.25, 8]");
    j = minimalDesign();
    j["conditions"][0]["vary"] = "layers";
    j["conditions"][0]["levels"] = json::array({2, 3, 6});
    EXPECT_EQ(errorOf(j), "t.json: conditions[0].levels[2]: 6 is outside layers's range [2, 5]");
    j["conditions"][0]["levels"] = json::array({2, 2.5});
    EXPECT_EQ(errorOf(j), "t.json: conditions[0].levels[1]: 2.5 is not a whole number (layers "
                          "takes whole numbers)");
}

TEST(Design, EmptyConditionList) {
    json j = minimalDesign();
    j["conditions"] = json::array();
    EXPECT_EQ(errorOf(j), "t.json: conditions: the list of conditions is empty (at least one)");
    j.erase("conditions");
    EXPECT_EQ(errorOf(j), "t.json: conditions: missing");
}

TEST(Design, UnknownKeyNamesItsPathAndTheAllowedKeys) {
    json j = minimalDesign();
    j["timing"] = {{"interval", 500}};
    EXPECT_EQ(errorOf(j), "t.json: timing.interval: unknown key (allowed: fixation_ms, "
                          "interval_ms, blank_ms, response_timeout_ms, refresh_hz)");
    j = minimalDesign();
    j["conditions"][0]["placement"] = {{"kind", "staircase"}, {"revresals", 4}};
    const std::string e = errorOf(j);
    EXPECT_EQ(e.rfind("t.json: conditions[0].placement.revresals: unknown key (allowed: kind, ", 0),
              0u)
        << e;
    j = minimalDesign();
    j["rays_per_point"] = 2;
    EXPECT_EQ(errorOf(j).rfind("t.json: rays_per_point: unknown key", 0), 0u);
}

TEST(Design, WrongTypeNamesTheField) {
    json j = minimalDesign();
    j["conditions"][0]["levels"]["step"] = "0.1";
    EXPECT_EQ(errorOf(j), "t.json: conditions[0].levels.step: must be a number, not a string");
    j = minimalDesign();
    j["gaze"] = {{"repeat_on_saccade", 1}};
    EXPECT_EQ(errorOf(j), "t.json: gaze.repeat_on_saccade: must be true or false, not a number");
    j = minimalDesign();
    j["practice_trials"] = 2.5;
    EXPECT_EQ(errorOf(j), "t.json: practice_trials: 2.5 is not a whole number");
    EXPECT_EQ(errorOf(json::array()), "t.json: a design is a JSON object, not a list");
}

TEST(Design, ConditionNamesAreUniqueAndNotEmpty) {
    json j = minimalDesign();
    j["conditions"].push_back(j["conditions"][0]);
    EXPECT_EQ(errorOf(j), "t.json: conditions[1].name: 'scale' names an earlier condition too");
    j = minimalDesign();
    j["conditions"][0]["name"] = "two\nlines";
    EXPECT_EQ(errorOf(j), "t.json: conditions[0].name: 'two\\x0alines' is not 1-64 letters, "
                          "digits, '_', '.', '-'");
    j = minimalDesign();
    j["conditions"][0]["name"] = "";
    EXPECT_EQ(errorOf(j).rfind("t.json: conditions[0].name: '' is not", 0), 0u);
}

TEST(Design, CombinationsThatCannotWork) {
    json j = minimalDesign();
    j["procedure"] = "slider";
    j["conditions"][0]["placement"] = {{"kind", "quest-plus"}};
    EXPECT_EQ(errorOf(j).rfind("t.json: conditions[0].placement.kind: the slider test moves", 0),
              0u);
    j = minimalDesign();
    j["conditions"][0]["placement"] = {{"kind", "weighted-staircase"}, {"target", 0.4}};
    EXPECT_EQ(errorOf(j).rfind("t.json: conditions[0].placement.target: 0.4 is not above the "
                               "guess rate 0.5",
                               0),
              0u);
    j = minimalDesign();
    j["conditions"][0]["placement"] = {{"start", 3.5}};
    EXPECT_EQ(errorOf(j),
              "t.json: conditions[0].placement.start: 3.5 is outside the levels [1, 3]");
    j = minimalDesign();
    j["conditions"][0]["placement"] = {{"step", 0.05}};
    EXPECT_EQ(errorOf(j).rfind("t.json: conditions[0].placement.step: 0.05 is below", 0), 0u);
    j = minimalDesign();
    j["conditions"][0]["vary"] = "slope";
    j["conditions"][0]["levels"] = {{"min", 0.01}, {"max", 0.04}};
    j["conditions"][0]["method"] = "foveated";
    EXPECT_EQ(errorOf(j), "t.json: conditions[0].vary: slope is a setting of the layers method, "
                          "not of foveated");
    j = minimalDesign();
    j["conditions"][0]["scale"] = 2.0;
    EXPECT_EQ(errorOf(j), "t.json: conditions[0].scale: is the varied parameter: its levels come "
                          "from \"levels\"");
    j = minimalDesign();
    j["conditions"][0]["levels"].erase("step");
    EXPECT_EQ(errorOf(j), "t.json: conditions[0].levels.step: a staircase moves on a grid: give a "
                          "step > 0 (every level's point set is built before the first trial)");
    j["conditions"][0]["placement"] = {{"kind", "quest-plus"}};
    EXPECT_EQ(errorOf(j), "");
    j = minimalDesign();
    j["catch_rate"] = 0.1;
    EXPECT_EQ(errorOf(j), "t.json: catch_rate: only the yes-no procedure has catch trials");
}

TEST(Design, LoadDesignNamesTheFile) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("gt-design-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const auto file = dir / "bad.json";
    std::ofstream(file) << "{\"name\": \"x\",\n \"procedure\": }";
    try {
        (void)loadDesign(file);
        ADD_FAILURE() << "no error";
    } catch (const DesignError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(file.string() + ": not JSON: parse error at line 2", 0), 0u) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos);
    }
    // A number too large for a double is the parser's range error, not a parse error: still one
    // line naming the file.
    std::ofstream(file) << "{\"name\": \"x\", \"seed\": 1e400}";
    try {
        (void)loadDesign(file);
        ADD_FAILURE() << "no error";
    } catch (const DesignError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(file.string() + ": not JSON: number overflow", 0), 0u) << what;
    }
    std::ofstream(file) << minimalDesign().dump();
    EXPECT_EQ(loadDesign(file).name, "thesis-scale");
    EXPECT_THROW((void)loadDesign(dir / "missing.json"), DesignError);
    EXPECT_THROW((void)loadDesign(dir), DesignError); // a folder
    std::filesystem::remove_all(dir);
}

} // namespace
} // namespace gt::study
