// `gazetrace study` end to end, headless (lavapipe, validation on): a simulated observer answers
// real rendered trials, the journal holds every trial with its fields, an interrupted run resumes
// to the whole plan, and bad inputs fail in one line without writing a journal.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli_run.hpp"
#include "support/gpu_test_context.hpp"

namespace gt {
namespace {

using test::Result;

// A forced-choice staircase on the point-set scale in a 160 x 90 view: intervals of three frames
// at 60 Hz, six trials in all.
nlohmann::json tinyDesign() {
    return nlohmann::json::parse(R"({
        "name": "tiny",
        "procedure": "forced-choice",
        "seed": 7,
        "width": 160, "height": 90,
        "timing": {"fixation_ms": 20, "interval_ms": 40, "blank_ms": 20},
        "conditions": [{"name": "scale", "vary": "scale",
                        "levels": {"min": 1.0, "max": 3.0, "step": 0.5},
                        "rays-per-point": 1,
                        "placement": {"kind": "staircase", "max_trials": 6}}]
    })");
}

std::filesystem::path writeDesign(const std::filesystem::path& dir, const nlohmann::json& d,
                                  const std::string& name = "design.json") {
    const auto file = dir / name;
    std::ofstream(file) << d.dump(2);
    return file;
}

std::vector<nlohmann::json> journalLines(const std::filesystem::path& file) {
    std::vector<nlohmann::json> lines;
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);) {
        lines.push_back(nlohmann::json::parse(line));
    }
    return lines;
}

std::vector<nlohmann::json> trialsOf(const std::vector<nlohmann::json>& lines) {
    std::vector<nlohmann::json> trials;
    for (const auto& l : lines) {
        if (l.value("type", "") == "trial") trials.push_back(l);
    }
    return trials;
}

// The shared point-set cache: every test renders the same 160 x 90 sets.
std::string cacheArg() {
    return " --cache " +
           (std::filesystem::temp_directory_path() / "gazetrace_study_cache").string();
}

std::string studyArgs(const std::filesystem::path& design, const std::filesystem::path& journal,
                      const std::string& extra) {
    return "study --design " + design.string() + " --participant P01 --journal " +
           journal.string() + " --display headless --validate" + cacheArg() + " " + extra;
}

// A trial a forced-choice observer answered: "first" or "second", positive when it chose the
// interval that held the condition.
void expectForcedChoiceTrial(const nlohmann::json& t, uint32_t index) {
    EXPECT_EQ(t["trial"], index);
    EXPECT_EQ(t["condition"], "scale");
    EXPECT_EQ(t["parameter"], "scale");
    const double level = t["level"];
    EXPECT_GE(level, 1.0);
    EXPECT_LE(level, 3.0);
    const std::string response = t["response"];
    ASSERT_TRUE(response == "first" || response == "second") << response;
    EXPECT_EQ(t["positive"].get<bool>(), (response == "first") == t["condition_first"].get<bool>());
    ASSERT_EQ(t["intervals"].size(), 2u);
    for (const auto& i : t["intervals"]) {
        EXPECT_GE(i["frames"].get<int>(), 2) << i;
        EXPECT_GE(i["expected_frames"].get<int>(), 2) << i;
    }
}

TEST(Study, HeadlessLevelObserverRendersAndJournalsEveryTrial) {
    const auto dir = test::tempDir("study_level");
    const auto design = writeDesign(dir, tinyDesign());
    const auto journal = dir / "p01.jsonl";
    // The observer sees every level (threshold far below the grid): every answer is right.
    const Result r =
        test::run(studyArgs(design, journal, "--observer level:0.1,50 --max-trials 4"));
    ASSERT_EQ(r.status, 0) << r.err;
    const auto summary = nlohmann::json::parse(r.out);
    EXPECT_EQ(summary["trials_done"], 4);
    EXPECT_EQ(summary["trials_journaled"], 4);
    EXPECT_EQ(summary["seed"], 7);
    EXPECT_GE(summary["frames_rendered"].get<int>(), 4 * 4);
    const auto lines = journalLines(journal);
    ASSERT_FALSE(lines.empty());
    EXPECT_EQ(lines.front()["type"], "start");
    const auto trials = trialsOf(lines);
    ASSERT_EQ(trials.size(), 4u);
    for (uint32_t i = 0; i < trials.size(); ++i) {
        expectForcedChoiceTrial(trials[i], i);
        EXPECT_TRUE(trials[i]["positive"].get<bool>()) << trials[i];
    }
    // Every level's point set was built before the first trial: five scales and the reference.
    EXPECT_EQ(summary["stimuli"]["builtin:market"].size(), 6u) << summary["stimuli"];
}

TEST(Study, HeadlessFlipObserverAnswersFromTheRenderedFrames) {
    const auto dir = test::tempDir("study_flip");
    const auto design = writeDesign(dir, tinyDesign());
    const auto journal = dir / "p01.jsonl";
    // Any FLIP above 1e-4 is seen: the foveated frames differ from the reference's.
    const Result r =
        test::run(studyArgs(design, journal, "--observer flip:0.0001,100000 --max-trials 2"));
    ASSERT_EQ(r.status, 0) << r.err;
    const auto summary = nlohmann::json::parse(r.out);
    EXPECT_GT(summary["flip_last"].get<double>(), 0.0001);
    EXPECT_LT(summary["flip_last"].get<double>(), 1.0);
    const auto trials = trialsOf(journalLines(journal));
    ASSERT_EQ(trials.size(), 2u);
    for (uint32_t i = 0; i < trials.size(); ++i) {
        expectForcedChoiceTrial(trials[i], i);
        EXPECT_TRUE(trials[i]["positive"].get<bool>()) << trials[i];
    }
}

TEST(Study, InterruptedRunResumesToTheWholePlan) {
    const auto dir = test::tempDir("study_resume");
    const auto design = writeDesign(dir, tinyDesign());
    const auto journal = dir / "p01.jsonl";
    const std::string observer = "--observer level:2,3 ";
    const Result first = test::run(studyArgs(design, journal, observer + "--max-trials 2"));
    ASSERT_EQ(first.status, 0) << first.err;
    EXPECT_FALSE(nlohmann::json::parse(first.out)["finished"].get<bool>());
    // Without --resume the journal is not touched.
    const std::string before = test::slurp(journal);
    const Result refused = test::run(studyArgs(design, journal, observer));
    EXPECT_NE(refused.status, 0);
    EXPECT_NE(refused.err.find("--resume"), std::string::npos) << refused.err;
    EXPECT_EQ(test::slurp(journal), before);
    const Result rest = test::run(studyArgs(design, journal, observer + "--resume"));
    ASSERT_EQ(rest.status, 0) << rest.err;
    const auto summary = nlohmann::json::parse(rest.out);
    EXPECT_TRUE(summary["finished"].get<bool>());
    const auto trials = trialsOf(journalLines(journal));
    EXPECT_EQ(summary["trials_journaled"], trials.size());
    ASSERT_EQ(trials.size(), 6u);
    for (uint32_t i = 0; i < trials.size(); ++i) {
        EXPECT_EQ(trials[i]["trial"], i) << "trial indices continue across the resumption";
    }
}

TEST(Study, BadInputsFailInOneLineAndWriteNoJournal) {
    const auto dir = test::tempDir("study_bad");
    const auto journal = dir / "p01.jsonl";
    const auto good = writeDesign(dir, tinyDesign());
    const std::string level = "--observer level:2";
    test::expectCleanFailure(test::run(studyArgs(dir / "missing.json", journal, level)),
                             "missing.json", journal);
    nlohmann::json unknown = tinyDesign();
    unknown["conditions"][0]["vary"] = "scal";
    test::expectCleanFailure(
        test::run(studyArgs(writeDesign(dir, unknown, "bad.json"), journal, level)),
        "conditions[0].vary", journal);
    test::expectCleanFailure(test::run(studyArgs(good, journal, "--observer level:x")),
                             "--observer", journal);
    test::expectCleanFailure(test::run(studyArgs(good, journal, "--observer guess:1")),
                             "--observer", journal);
    test::expectCleanFailure(test::run(studyArgs(good, journal, "")), "--observer", journal);
    test::expectCleanFailure(test::run("study --design " + good.string() +
                                       " --participant 'Jane Doe' --journal " + journal.string() +
                                       " --display headless " + level),
                             "--participant", journal);
    test::expectCleanFailure(test::run(studyArgs(good, journal, level + " --resume")), "--resume",
                             journal);
    test::expectCleanFailure(test::run(studyArgs(good, journal, level + " --width 8")), "--width",
                             journal);
    nlohmann::json camera = tinyDesign();
    camera["scenes"] = nlohmann::json::array({{{"scene", "builtin:market"}, {"camera", "1,2,3"}}});
    test::expectCleanFailure(
        test::run(studyArgs(writeDesign(dir, camera, "camera.json"), journal, level)),
        "scenes[0].camera", journal);
}

TEST(Study, RunThatFailsBeforeItsFirstTrialLeavesNoJournal) {
    const auto dir = test::tempDir("study_nothing");
    const auto design = writeDesign(dir, tinyDesign());
    const auto journal = dir / "p01.jsonl";
    // No such device: the renderer fails once the journal is open and its first line written;
    // the failed start takes that line back.
    constexpr const char* kNoDevice = "GAZETRACE_DEVICE=no-such-device";
    const Result r = test::runWith(kNoDevice, studyArgs(design, journal, "--observer level:2"));
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("no-such-device"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(journal));
    // A journal resumed by a run that fails the same way is left as it was.
    const Result first = test::run(studyArgs(design, journal, "--observer level:2 --max-trials 1"));
    ASSERT_EQ(first.status, 0) << first.err;
    const std::string before = test::slurp(journal);
    const Result resumed =
        test::runWith(kNoDevice, studyArgs(design, journal, "--observer level:2 --resume"));
    EXPECT_NE(resumed.status, 0);
    EXPECT_EQ(test::slurp(journal), before);
}

// The window display under Xvfb: the same session, its frames presented, the observer answering
// in the keys' place.
TEST(Study, WindowRunsTrialsUnderXvfb) {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        GTEST_SKIP() << "xvfb-run is not installed";
    }
    const auto dir = test::tempDir("study_window");
    const auto design = writeDesign(dir, tinyDesign());
    const auto journal = dir / "w01.jsonl";
    const Result r =
        test::runWith("xvfb-run -a -s '-screen 0 1280x720x24'",
                      "study --design " + design.string() + " --participant W01 --journal " +
                          journal.string() + " --display window --gaze fixed:80,45 --validate" +
                          cacheArg() + " --observer level:0.1,50 --max-trials 2");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto summary = nlohmann::json::parse(r.out);
    EXPECT_EQ(summary["display"], "window");
    EXPECT_EQ(summary["trials_done"], 2);
    EXPECT_GT(summary["frames_rendered"].get<int>(), 0);
    const auto trials = trialsOf(journalLines(journal));
    ASSERT_EQ(trials.size(), 2u);
    for (uint32_t i = 0; i < trials.size(); ++i) {
        EXPECT_EQ(trials[i]["trial"], i);
        EXPECT_TRUE(trials[i]["positive"].get<bool>()) << trials[i];
        for (const auto& interval : trials[i]["intervals"]) {
            EXPECT_GE(interval["frames"].get<int>(), 1) << interval;
            ASSERT_FALSE(interval["gaze"].empty()) << interval;
            // The fixed gaze is the view's centre: within a pixel's angle of (0, 0).
            EXPECT_LT(std::abs(interval["gaze"][0][1].get<double>()), 0.05) << interval;
            EXPECT_LT(std::abs(interval["gaze"][0][2].get<double>()), 0.05) << interval;
        }
    }
}

// A design over two scenes in the window: both scenes on the window's device, every stimulus of
// each built before the first trial, the trials cycling through the scenes.
TEST(Study, WindowRunsTrialsOfTwoScenesUnderXvfb) {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        GTEST_SKIP() << "xvfb-run is not installed";
    }
    const auto dir = test::tempDir("study_window_scenes");
    nlohmann::json d = tinyDesign();
    d["scenes"] =
        nlohmann::json::array({{{"scene", "builtin:market"}}, {{"scene", "builtin:cornell"}}});
    const auto design = writeDesign(dir, d);
    const auto journal = dir / "w02.jsonl";
    const Result r =
        test::runWith("xvfb-run -a -s '-screen 0 1280x720x24'",
                      "study --design " + design.string() + " --participant W02 --journal " +
                          journal.string() + " --display window --gaze fixed:80,45 --validate" +
                          cacheArg() + " --observer level:0.1,50 --max-trials 4");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto summary = nlohmann::json::parse(r.out);
    EXPECT_EQ(summary["trials_done"], 4);
    for (const char* scene : {"builtin:market", "builtin:cornell"}) {
        ASSERT_TRUE(summary["stimuli"].contains(scene)) << summary["stimuli"];
        EXPECT_FALSE(summary["stimuli"][scene].empty()) << scene;
    }
    EXPECT_NE(r.err.find("stimuli of builtin:market, builtin:cornell ready"), std::string::npos)
        << r.err;
    std::set<uint32_t> scenes;
    for (const auto& t : trialsOf(journalLines(journal))) {
        scenes.insert(t["scene"].get<uint32_t>());
        for (const auto& interval : t["intervals"]) {
            EXPECT_GE(interval["frames"].get<int>(), 1) << interval;
        }
    }
    EXPECT_EQ(scenes, (std::set<uint32_t>{0, 1}));
}

// The gaze from a trace, in the session's angles: a gaze that leaves the fixation region (1 deg)
// during an interval repeats the trial; the trials kept saw it inside.
TEST(Study, GazeLeavingTheFixationRegionRepeatsTheTrial) {
    const auto dir = test::tempDir("study_gaze");
    nlohmann::json d = tinyDesign();
    d["gaze"] = {{"fixation_radius_deg", 1.0}, {"max_repeats", 2}};
    const auto design = writeDesign(dir, d);
    // On the view's centre, except every fourth 50 ms, when it is 70 px to the left (2 deg).
    const auto trace = dir / "gaze.csv";
    {
        std::ofstream out(trace);
        out << "t_ms,x,y\n";
        for (int i = 0; i < 400; ++i) {
            const int x = i % 4 == 3 ? 10 : 80;
            out << i * 50 << "," << x << ",45\n" << i * 50 + 49 << "," << x << ",45\n";
        }
    }
    const auto journal = dir / "p01.jsonl";
    const Result r = test::run(studyArgs(
        design, journal, "--observer level:2,3 --max-trials 4 --gaze trace:" + trace.string()));
    ASSERT_EQ(r.status, 0) << r.err;
    const auto lines = journalLines(journal);
    int repeats = 0;
    for (const auto& l : lines) {
        if (l.value("type", "") == "repeat") ++repeats;
        if (l.value("type", "") != "trial") continue;
        for (const auto& interval : l["intervals"]) {
            for (const auto& g : interval["gaze"]) {
                EXPECT_LT(std::hypot(g[1].get<double>(), g[2].get<double>()), 1.0) << g;
            }
        }
    }
    EXPECT_GE(repeats, 1);
    EXPECT_EQ(trialsOf(lines).size(), 4u);
}

// A long plan (200 trials) a signal interrupts after a few seconds.
std::filesystem::path longDesign(const std::filesystem::path& dir) {
    nlohmann::json d = tinyDesign();
    d["conditions"][0]["placement"]["max_trials"] = 200;
    d["conditions"][0]["placement"]["reversals"] = 200;
    return writeDesign(dir, d, "long.json");
}

// SIGINT ends a window run as Esc does: after the frame shown, exit 0, every trial answered in
// the journal, and the run resumes from there.
TEST(Study, SigintEndsAWindowRunWithItsJournalComplete) {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        GTEST_SKIP() << "xvfb-run is not installed";
    }
    const auto dir = test::tempDir("study_sigint_window");
    const auto design = longDesign(dir);
    const auto journal = dir / "p01.jsonl";
    // SIGINT once the first trial is journaled, however long the stimuli took to build.
    const Result r = test::runInterruptedWhen(
        "xvfb-run -a -s '-screen 0 1280x720x24'",
        "study --design " + design.string() + " --participant P01 --journal " + journal.string() +
            " --display window --gaze fixed:80,45" + cacheArg() + " --observer level:2,3",
        journal, "\"type\":\"trial\"", 300);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto summary = nlohmann::json::parse(r.out);
    EXPECT_TRUE(summary["ended_early"].get<bool>()) << r.out;
    const auto trials = trialsOf(journalLines(journal));
    ASSERT_GE(trials.size(), 1u) << "no trial in five minutes: " << r.err;
    EXPECT_EQ(summary["trials_journaled"], trials.size());
    const Result more = test::run(studyArgs(design, journal,
                                            "--observer level:2,3 --resume "
                                            "--max-trials 2"));
    ASSERT_EQ(more.status, 0) << more.err;
    const auto all = trialsOf(journalLines(journal));
    ASSERT_EQ(all.size(), trials.size() + 2);
    for (uint32_t i = 0; i < all.size(); ++i) {
        EXPECT_EQ(all[i]["trial"], i);
    }
}

// SIGINT interrupts a headless run (exit 130, as other fixed-length runs) and keeps every trial
// answered before it.
TEST(Study, SigintInterruptsAHeadlessRunAndKeepsItsTrials) {
    const auto dir = test::tempDir("study_sigint_headless");
    const auto design = longDesign(dir);
    const auto journal = dir / "p01.jsonl";
    const Result r = test::runInterruptedWhen(
        "", studyArgs(design, journal, "--observer level:2,3 --frame-ms 200"), journal,
        "\"type\":\"trial\"", 300);
    EXPECT_EQ(r.status, 130) << r.err;
    EXPECT_NE(r.err.find("interrupted"), std::string::npos) << r.err;
    const auto trials = trialsOf(journalLines(journal));
    ASSERT_GE(trials.size(), 1u) << "no trial in five minutes";
    for (uint32_t i = 0; i < trials.size(); ++i) {
        EXPECT_EQ(trials[i]["trial"], i);
    }
}

} // namespace
} // namespace gt
