// `gazetrace study simulate` and `study analyse` end to end: simulated participants' journals,
// analysed into thresholds.json, thresholds.csv and psychometric.png; journals of two designs and
// a simulation into an earlier run's journals fail in one line.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scene/image_io.hpp"
#include "support/cli_run.hpp"
#include "support/gpu_test_context.hpp"

namespace gt {
namespace {

using test::Result;
namespace fs = std::filesystem;

// A forced choice at constant stimuli on the scale, short intervals: a simulated participant
// runs it in a fraction of a second.
fs::path writeDesign(const fs::path& dir, const std::string& name, const std::string& procedure) {
    const nlohmann::json d{{"name", name},
                           {"procedure", procedure},
                           {"seed", 3},
                           {"timing", {{"fixation_ms", 20}, {"interval_ms", 50}, {"blank_ms", 20}}},
                           {"conditions",
                            {{{"name", "nn"},
                              {"vary", "scale"},
                              {"levels", {{"min", 1.0}, {"max", 3.0}, {"step", 0.25}}},
                              {"placement", {{"kind", "constant"}, {"repeats", 8}}}}}}};
    const fs::path file = dir / (name + ".json");
    std::ofstream(file) << d.dump(2);
    return file;
}

int lineCount(const fs::path& file) {
    std::ifstream in(file);
    int n = 0;
    for (std::string line; std::getline(in, line);)
        ++n;
    return n;
}

TEST(StudyAnalyse, SimulatedJournalsAnalyseIntoThresholdsAndAPlot) {
    const fs::path dir = test::tempDir("study_analyse");
    const fs::path design = writeDesign(dir, "tiny-2ifc", "forced-choice");
    const Result sim = test::run(
        "study simulate --design " + design.string() + " --observers 4 --threshold 2 " +
        "--journals " + (dir / "journals").string() + " --json " + (dir / "sim.json").string());
    ASSERT_EQ(sim.status, 0) << sim.err;
    const auto summary = nlohmann::json::parse(test::slurp(dir / "sim.json"));
    EXPECT_EQ(summary, nlohmann::json::parse(sim.out)) << "printed and written alike";
    const auto& c = summary.at("conditions").at(0);
    EXPECT_EQ(c.at("planted_threshold"), 2.0);
    EXPECT_EQ(c.at("fitted"), 4);
    EXPECT_EQ(c.at("trials_median"), 9 * 8);
    EXPECT_LT(c.at("error_median").get<double>(), 0.3);

    const fs::path out = dir / "out";
    const Result a = test::run("study analyse " + (dir / "journals").string() + "/*.jsonl --out " +
                               out.string());
    ASSERT_EQ(a.status, 0) << a.err;
    const auto thresholds = nlohmann::json::parse(test::slurp(out / "thresholds.json"));
    ASSERT_EQ(thresholds.at("participants").size(), 4u);
    const auto& group = thresholds.at("conditions").at(0);
    EXPECT_EQ(group.at("participants"), 4);
    EXPECT_NEAR(group.at("threshold_mean").get<double>(), 2.0, 0.3);
    EXPECT_LT(group.at("threshold_low").get<double>(), group.at("threshold_mean").get<double>());
    EXPECT_GT(group.at("threshold_high").get<double>(), group.at("threshold_mean").get<double>());
    EXPECT_EQ(lineCount(out / "thresholds.csv"), 1 + 4 + 1) << "header, participants, group";
    const std::string png = test::slurp(out / "psychometric.png");
    const image::DecodedImage plot = image::decode(
        std::span(reinterpret_cast<const uint8_t*>(png.data()), png.size()), "psychometric.png");
    EXPECT_EQ(plot.width, 880u);
    EXPECT_EQ(plot.height, 430u) << "one panel per condition";
    fs::remove_all(dir);
}

TEST(StudyAnalyse, JournalsOfTwoDesignsFailInOneLine) {
    const fs::path dir = test::tempDir("study_analyse");
    for (const char* procedure : {"forced-choice", "yes-no"}) {
        const fs::path design = writeDesign(dir, std::string("d-") + procedure, procedure);
        const Result sim = test::run("study simulate --design " + design.string() +
                                     " --observers 1 --journals " + (dir / "j").string());
        ASSERT_EQ(sim.status, 0) << sim.err;
    }
    const fs::path out = dir / "out";
    const Result a =
        test::run("study analyse " + (dir / "j").string() + "/*.jsonl --out " + out.string());
    test::expectCleanFailure(a, "design", out);
    // A simulation never appends to an earlier run's journals.
    const Result again = test::run("study simulate --design " + (dir / "d-yes-no.json").string() +
                                   " --observers 1 --journals " + (dir / "j").string());
    EXPECT_NE(again.status, 0);
    EXPECT_NE(again.err.find("exists"), std::string::npos) << again.err;
    fs::remove_all(dir);
}

} // namespace
} // namespace gt
