#include <gtest/gtest.h>

#include "session.hpp"

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace gt::study {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kPeriod = 1000.0 / 60.0;

// One condition varying the scale on a 2IFC, ending after `maxTrials` trials.
json forcedChoice(uint32_t maxTrials) {
    return json{
        {"name", "fc"},
        {"procedure", "forced-choice"},
        {"seed", 7},
        {"timing", {{"fixation_ms", 500}, {"interval_ms", 1000}, {"blank_ms", 500}}},
        {"conditions",
         json::array({{{"name", "scale"},
                       {"vary", "scale"},
                       {"levels", {{"min", 1.0}, {"max", 3.0}, {"step", 0.5}}},
                       {"placement", {{"kind", "staircase"}, {"max_trials", maxTrials}}}}})}};
}

// Two interleaved conditions with short intervals: many trials, quickly.
json interleaved() {
    json condition = {{"vary", "scale"},
                      {"levels", {{"min", 1.0}, {"max", 3.0}, {"step", 0.1}}},
                      {"placement", {{"kind", "staircase"}, {"max_trials", 14}}}};
    json a = condition;
    a["name"] = "a";
    json b = condition;
    b["name"] = "b";
    b["interp"] = "msm";
    return json{{"name", "two"},
                {"procedure", "forced-choice"},
                {"seed", 42},
                {"practice_trials", 1},
                {"break_every", 9},
                {"timing", {{"fixation_ms", 0}, {"interval_ms", 50}, {"blank_ms", 0}}},
                {"gaze", {{"fixation_radius_deg", 2.0}}},
                {"conditions", json::array({a, b})}};
}

StudyDesign designOf(const json& j) {
    return parseDesign(j, "test.json");
}

Response correct(const StudySession::TrialInfo& t) {
    return t.conditionFirst ? Response::First : Response::Second;
}

// Plays a participant frame by frame at 60 Hz: Continue at instructions and breaks, an answer
// after `responseFrames` frames of the response phase, gaze and latency from the script.
struct Player {
    // The gaze of frame k; `prev` is what the frame before showed.
    std::function<std::optional<GazeAngles>(uint64_t, const FrameShow*)> gaze =
        [](uint64_t, const FrameShow*) { return std::optional<GazeAngles>(GazeAngles{}); };
    std::function<Response(const StudySession::TrialInfo&)> answer = correct;
    std::function<double(uint64_t)> latency = [](uint64_t) { return 0.0; };
    std::set<uint64_t> skip; // frames the display dropped
    uint32_t responseFrames = 10;

    uint64_t k = 0;
    Phase last = Phase::Done;
    uint32_t inResponse = 0;
    std::vector<std::pair<Phase, int>> runs;
    std::vector<FrameShow> shows;

    FrameShow step(StudySession& s) {
        while (skip.count(k) != 0)
            ++k;
        FrameInput in;
        in.timeMs = static_cast<double>(k) * kPeriod;
        in.gaze = gaze(k, shows.empty() ? nullptr : &shows.back());
        in.latencyMs = latency(k);
        if (!shows.empty() && (last == Phase::Instructions || last == Phase::Break)) {
            in.response = Response::Continue;
        } else if (last == Phase::Response && inResponse == responseFrames) {
            in.response = answer(*s.currentTrial());
        }
        const FrameShow show = s.frame(in);
        inResponse = show.phase == Phase::Response ? inResponse + 1 : 0;
        if (runs.empty() || runs.back().first != show.phase) {
            runs.emplace_back(show.phase, 0);
        }
        ++runs.back().second;
        last = show.phase;
        shows.push_back(show);
        ++k;
        return show;
    }

    void untilDone(StudySession& s, uint64_t maxFrames = 200000) {
        for (uint64_t i = 0; i < maxFrames && !s.finished(); ++i)
            step(s);
    }
};

class SessionTest : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = fs::temp_directory_path() /
               ("gt-session-" + std::to_string(::getpid()) + "-" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(mDir);
        fs::create_directories(mDir);
    }
    void TearDown() override { fs::remove_all(mDir); }
    [[nodiscard]] fs::path journalPath(const std::string& name = "p01.jsonl") const {
        return mDir / name;
    }
    static std::vector<json> linesOfType(const fs::path& p, const std::string& type) {
        std::vector<json> out;
        for (const json& j : readJournal(p)) {
            if (j["type"] == type) out.push_back(j);
        }
        return out;
    }
    fs::path mDir;
};

SessionSettings participant(const std::string& code = "P01") {
    SessionSettings s;
    s.participant = code;
    s.refreshHz = 60.0;
    return s;
}

TEST_F(SessionTest, TwoIntervalForcedChoiceFrameByFrame) {
    Journal journal(journalPath());
    StudySession session(designOf(forcedChoice(2)), participant(), journal);
    EXPECT_EQ(session.seed(), 7u);
    Player player;
    player.untilDone(session);
    // At 60 Hz: 500 ms of fixation = 30 frames, 1000 ms intervals = 60, the 500 ms blank = 30;
    // the answer comes on the 11th response frame, which begins the next trial.
    const std::vector<std::pair<Phase, int>> trial{{Phase::Fixation, 30},
                                                   {Phase::Interval, 60},
                                                   {Phase::Blank, 30},
                                                   {Phase::Interval, 60},
                                                   {Phase::Response, 10}};
    std::vector<std::pair<Phase, int>> expected{{Phase::Instructions, 1}};
    expected.insert(expected.end(), trial.begin(), trial.end());
    expected.insert(expected.end(), trial.begin(), trial.end());
    expected.emplace_back(Phase::Done, 1);
    EXPECT_EQ(player.runs, expected);

    // The intervals show the condition at the staircase's start (the most foveated level, 3)
    // and the reference, in the order the plan drew.
    const FrameShow& first = player.shows[1 + 30];
    const FrameShow& second = player.shows[1 + 30 + 60 + 30];
    ASSERT_TRUE(first.stimulus && second.stimulus);
    const auto records = linesOfType(journalPath(), "trial");
    ASSERT_EQ(records.size(), 2u);
    const TrialRecord r = trialFromJson(records[0]);
    const FrameShow& cond = r.conditionFirst ? first : second;
    const FrameShow& comp = r.conditionFirst ? second : first;
    EXPECT_EQ(cond.stimulus->render.method, Method::Foveated);
    EXPECT_DOUBLE_EQ(cond.stimulus->render.scale, 3.0);
    EXPECT_EQ(comp.stimulus->render.method, Method::Reference);
    EXPECT_TRUE(player.shows[1].showFixationMark);

    EXPECT_EQ(r.trial, 0u);
    EXPECT_DOUBLE_EQ(r.level, 3.0);
    EXPECT_TRUE(r.positive);
    EXPECT_EQ(r.response, r.conditionFirst ? "first" : "second");
    EXPECT_NEAR(r.reactionMs, 10 * kPeriod, 1e-9);
    ASSERT_EQ(r.intervals.size(), 2u);
    for (const IntervalRecord& i : r.intervals) {
        EXPECT_EQ(i.frames, 60u);
        EXPECT_EQ(i.expectedFrames, 60u);
        EXPECT_EQ(i.droppedFrames, 0u);
        EXPECT_EQ(i.gaze.size(), 60u);
    }
    EXPECT_TRUE(r.flags.empty());
    const auto all = readJournal(journalPath());
    ASSERT_EQ(all.size(), 4u);
    EXPECT_EQ(all[0]["type"], "start");
    EXPECT_EQ(all[0]["seed"], 7u);
    EXPECT_EQ(all[0]["participant"], "P01");
    EXPECT_EQ(all[0]["design_hash"], designHash(designOf(forcedChoice(2))));
    EXPECT_EQ(all[0]["design"], designToJson(designOf(forcedChoice(2))));
    EXPECT_EQ(all[3]["type"], "end");
}

TEST_F(SessionTest, OnlyTheAcceptedAnswersCount) {
    Journal journal(journalPath());
    StudySession session(designOf(forcedChoice(1)), participant(), journal);
    EXPECT_EQ(session.accepted(), std::vector<Response>{Response::Continue});
    FrameInput in;
    in.response = Response::Yes; // not an answer here
    EXPECT_EQ(session.frame(in).phase, Phase::Instructions);
    in.response = Response::Continue;
    EXPECT_EQ(session.frame(in).phase, Phase::Fixation);
    EXPECT_TRUE(session.accepted().empty());
}

TEST_F(SessionTest, LeavingTheFixationRegionRepeatsTheTrial) {
    json j = forcedChoice(1);
    j["gaze"] = {{"fixation_radius_deg", 2.0}, {"max_repeats", 1}};
    Journal journal(journalPath());
    StudySession session(designOf(j), participant(), journal);
    Player player;
    // Trial 0: the gaze 5 degrees off in the first interval's 10th frame; trial 1 (the repeat)
    // the same; being its last repeat, it is kept and flagged.
    player.gaze = [](uint64_t k, const FrameShow*) {
        const bool off = k == 1 + 30 + 9 || k == 1 + 30 + 9 + 31 + 9;
        return std::optional<GazeAngles>(GazeAngles{off ? 5.0 : 0.5, 0.0});
    };
    player.untilDone(session);
    // The repeat's fixation begins on the frame the gaze was off, so it holds from the next:
    // 31 frames.
    const std::vector<std::pair<Phase, int>> expected{
        {Phase::Instructions, 1}, {Phase::Fixation, 30}, {Phase::Interval, 9},
        {Phase::Fixation, 31},    {Phase::Interval, 60}, {Phase::Blank, 30},
        {Phase::Interval, 60},    {Phase::Response, 10}, {Phase::Done, 1}};
    EXPECT_EQ(player.runs, expected);
    const auto lines = readJournal(journalPath());
    ASSERT_EQ(lines.size(), 4u);
    EXPECT_EQ(lines[1]["type"], "repeat");
    EXPECT_EQ(lines[1]["why"], "fixation");
    EXPECT_EQ(lines[1]["trial"], 0u);
    EXPECT_EQ(lines[1]["condition"], "scale");
    const TrialRecord r = trialFromJson(lines[2]);
    EXPECT_EQ(r.trial, 1u);
    EXPECT_EQ(r.flags, std::vector<std::string>{"max_repeats"});
    EXPECT_EQ(session.trialsDone(), 1u);
}

TEST_F(SessionTest, FixationWaitsForTheGazeInsideTheRegion) {
    json j = forcedChoice(1);
    j["gaze"] = {{"fixation_radius_deg", 2.0}};
    Journal journal(journalPath());
    StudySession session(designOf(j), participant(), journal);
    Player player;
    // Outside for the first 12 fixation frames, or lost: the 500 ms count starts after.
    player.gaze = [](uint64_t k, const FrameShow*) {
        if (k >= 1 && k <= 6) return std::optional<GazeAngles>();
        return std::optional<GazeAngles>(GazeAngles{k <= 12 ? 3.0 : 0.0, 0.0});
    };
    for (int i = 0; i < 1 + 42 + 1; ++i)
        player.step(session);
    ASSERT_GE(player.runs.size(), 3u);
    EXPECT_EQ(player.runs[1], std::make_pair(Phase::Fixation, 42));
    EXPECT_EQ(player.runs[2].first, Phase::Interval);
}

TEST_F(SessionTest, SaccadeDuringAnIntervalRepeatsTheTrial) {
    json j = forcedChoice(1);
    j["gaze"] = {{"repeat_on_saccade", true}, {"saccade_deg_per_s", 100}};
    Journal journal(journalPath());
    StudySession session(designOf(j), participant(), journal);
    Player player;
    // 2 degrees in one frame (120 deg/s) in the second interval of the first trial.
    player.gaze = [](uint64_t k, const FrameShow*) {
        return std::optional<GazeAngles>(GazeAngles{k >= 1 + 30 + 60 + 30 + 5 ? 2.0 : 0.0, 0.0});
    };
    player.untilDone(session);
    const auto repeats = linesOfType(journalPath(), "repeat");
    ASSERT_EQ(repeats.size(), 1u);
    EXPECT_EQ(repeats[0]["why"], "saccade");
    EXPECT_EQ(linesOfType(journalPath(), "trial").size(), 1u);
}

TEST_F(SessionTest, DroppedFramesAndLostGazeAreFlagged) {
    Journal journal(journalPath());
    StudySession session(designOf(forcedChoice(2)), participant(), journal);
    Player player;
    // Trial 0: frame 50 (in the first interval, frames 31-90) is never shown; the gaze is lost
    // for 7 frames (117 ms > 100 ms) in the second interval (frames 121-180).
    // Trial 1 (from frame 191): the gaze lost for 6 frames (100 ms, not more): not flagged.
    player.skip = {50};
    player.gaze = [](uint64_t k, const FrameShow*) {
        const bool lost = (k >= 130 && k < 137) || (k >= 321 && k < 327);
        return lost ? std::optional<GazeAngles>() : std::optional<GazeAngles>(GazeAngles{});
    };
    player.latency = [](uint64_t k) { return k % 2 == 0 ? 10.0 : 20.0; };
    player.untilDone(session);
    const auto trials = linesOfType(journalPath(), "trial");
    ASSERT_EQ(trials.size(), 2u);
    const TrialRecord r0 = trialFromJson(trials[0]);
    ASSERT_EQ(r0.intervals.size(), 2u);
    EXPECT_EQ(r0.intervals[0].frames, 59u);
    EXPECT_EQ(r0.intervals[0].expectedFrames, 60u);
    EXPECT_EQ(r0.intervals[0].droppedFrames, 1u);
    EXPECT_EQ(r0.intervals[1].droppedFrames, 0u);
    EXPECT_EQ(r0.intervals[1].gazeLostFrames, 7u);
    EXPECT_EQ(r0.intervals[1].gaze.size(), 53u);
    EXPECT_DOUBLE_EQ(r0.intervals[1].latencyMsMean, 15.0);
    EXPECT_DOUBLE_EQ(r0.intervals[1].latencyMsMax, 20.0);
    EXPECT_EQ(r0.flags, (std::vector<std::string>{"gaze_lost", "dropped_frame"}));
    const TrialRecord r1 = trialFromJson(trials[1]);
    EXPECT_EQ(r1.intervals[0].gazeLostFrames + r1.intervals[1].gazeLostFrames, 6u);
    EXPECT_TRUE(r1.flags.empty());
}

// The deterministic observer of the resume tests: right above scale 2, wrong below, so the
// staircases reverse; trial 3's first attempt looks away (a repeat in the journal).
Player resumePlayer() {
    Player p;
    p.responseFrames = 2;
    p.answer = [](const StudySession::TrialInfo& t) {
        const bool right = t.level >= 2.0;
        return t.conditionFirst == right ? Response::First : Response::Second;
    };
    p.gaze = [](uint64_t, const FrameShow* prev) {
        const bool away = prev != nullptr && prev->trial == 3 && prev->phase == Phase::Interval;
        return std::optional<GazeAngles>(GazeAngles{away ? 9.0 : 0.0, 0.0});
    };
    return p;
}

TEST_F(SessionTest, ResumeContinuesWithTheNextTrialAndTheSamePlacements) {
    const StudyDesign design = designOf(interleaved());
    // The uninterrupted run.
    std::vector<json> whole;
    double nextA = 0;
    double nextB = 0;
    constexpr uint32_t kStop = 11;
    {
        Journal journal(journalPath("whole.jsonl"));
        StudySession session(design, participant(), journal);
        Player player = resumePlayer();
        while (!session.finished() && session.trialsDone() < kStop)
            player.step(session);
        nextA = session.placement("a")->next();
        nextB = session.placement("b")->next();
        player.untilDone(session);
        whole = linesOfType(journalPath("whole.jsonl"), "trial");
    }
    ASSERT_GT(whole.size(), kStop + 4);
    // The run holds a repeat (trial 3) before the cut, and practice trials.
    ASSERT_EQ(linesOfType(journalPath("whole.jsonl"), "repeat").size(), 1u);
    ASSERT_TRUE(whole[0]["practice"].get<bool>());
    // The same run cut off in the middle of trial kStop's interval, then resumed.
    const fs::path cut = journalPath("cut.jsonl");
    {
        Journal journal(cut);
        StudySession session(design, participant(), journal);
        Player player = resumePlayer();
        while (session.trialsDone() < kStop)
            player.step(session);
        while (player.last != Phase::Interval)
            player.step(session);
    }
    {
        Journal journal(cut);
        StudySession session(design, participant(), journal);
        EXPECT_EQ(session.trialsDone(), kStop);
        EXPECT_DOUBLE_EQ(session.placement("a")->next(), nextA);
        EXPECT_DOUBLE_EQ(session.placement("b")->next(), nextB);
        Player player = resumePlayer();
        player.k = 100000; // the clock of a later sitting
        player.step(session);
        EXPECT_EQ(player.last, Phase::Instructions);
        player.step(session);
        EXPECT_EQ(player.shows.back().trial, whole[kStop]["trial"].get<uint32_t>());
        player.untilDone(session);
    }
    const auto resumed = linesOfType(cut, "trial");
    ASSERT_EQ(resumed.size(), whole.size());
    for (std::size_t i = 0; i < whole.size(); ++i) {
        for (const char* key :
             {"trial", "condition", "level", "practice", "condition_first", "positive"}) {
            EXPECT_EQ(resumed[i][key], whole[i][key]) << "trial line " << i << " " << key;
        }
    }
    EXPECT_EQ(linesOfType(cut, "resume").size(), 1u);
    EXPECT_EQ(linesOfType(cut, "repeat").size(),
              linesOfType(journalPath("whole.jsonl"), "repeat").size());
}

TEST_F(SessionTest, ADifferentDesignRefusesToResume) {
    {
        Journal journal(journalPath());
        StudySession session(designOf(forcedChoice(3)), participant(), journal);
        Player player;
        for (int i = 0; i < 300; ++i)
            player.step(session);
        ASSERT_EQ(session.trialsDone(), 1u);
    }
    Journal journal(journalPath());
    try {
        StudySession session(designOf(forcedChoice(4)), participant(), journal);
        ADD_FAILURE() << "resumed";
    } catch (const JournalError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(journalPath().string() + ": written for design 'fc' (hash ", 0), 0u)
            << what;
        EXPECT_NE(what.find("start a new journal"), std::string::npos);
    }
    EXPECT_THROW(StudySession(designOf(forcedChoice(3)), participant("P02"), journal),
                 JournalError);
    StudySession same(designOf(forcedChoice(3)), participant(), journal);
    EXPECT_EQ(same.trialsDone(), 1u);
}

TEST_F(SessionTest, TornJournalResumesWithTheCompleteTrialsOnly) {
    {
        Journal journal(journalPath());
        StudySession session(designOf(forcedChoice(3)), participant(), journal);
        Player player;
        while (session.trialsDone() < 2)
            player.step(session);
    }
    std::ofstream(journalPath(), std::ios::app) << "{\"type\":\"trial\",\"trial\":2,\"cond";
    Journal journal(journalPath());
    EXPECT_TRUE(journal.droppedTornLine());
    StudySession session(designOf(forcedChoice(3)), participant(), journal);
    EXPECT_EQ(session.trialsDone(), 2u);
    Player player;
    player.untilDone(session);
    const auto trials = linesOfType(journalPath(), "trial");
    ASSERT_EQ(trials.size(), 3u);
    EXPECT_EQ(trials[2]["trial"], 2u);
}

TEST_F(SessionTest, AKilledRunKeepsEveryTrialItAnswered) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        Journal journal(journalPath());
        StudySession session(designOf(forcedChoice(10)), participant(), journal);
        Player player;
        while (session.trialsDone() < 4)
            player.step(session);
        ::raise(SIGKILL);
        ::_exit(0);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status));
    EXPECT_EQ(linesOfType(journalPath(), "trial").size(), 4u);
}

TEST_F(SessionTest, ParticipantIsACode) {
    Journal journal(journalPath());
    try {
        StudySession session(designOf(forcedChoice(1)), participant("Jane Doe"), journal);
        ADD_FAILURE() << "accepted";
    } catch (const SessionError& e) {
        EXPECT_EQ(std::string(e.what()), "participant 'Jane Doe': a code of 1-32 letters, "
                                         "digits, '_' or '-' (nothing personal)");
    }
    EXPECT_TRUE(readJournal(journalPath()).empty());
}

TEST_F(SessionTest, PracticeAndCatchTrialsStayOutOfThePlacement) {
    json j = forcedChoice(6);
    j["procedure"] = "yes-no";
    j["practice_trials"] = 2;
    j["catch_rate"] = 0.5;
    j["timing"] = {{"fixation_ms", 0}, {"interval_ms", 50}, {"blank_ms", 0}};
    Journal journal(journalPath());
    StudySession session(designOf(j), participant(), journal);
    Player player;
    player.responseFrames = 1;
    player.answer = [](const StudySession::TrialInfo& t) {
        return t.catchTrial ? Response::No : Response::Yes;
    };
    player.untilDone(session);
    const auto trials = linesOfType(journalPath(), "trial");
    uint32_t fed = 0;
    uint32_t catches = 0;
    for (std::size_t i = 0; i < trials.size(); ++i) {
        const TrialRecord r = trialFromJson(trials[i]);
        EXPECT_EQ(r.practice, i < 2);
        if (r.practice) {
            EXPECT_DOUBLE_EQ(r.level, 3.0); // the most foveated, the easiest
            EXPECT_FALSE(r.catchTrial);
        }
        if (r.catchTrial) {
            ++catches;
            EXPECT_EQ(r.intervals.at(0).shown, "comparison");
            EXPECT_FALSE(r.positive);
        } else if (!r.practice) {
            ++fed;
        }
    }
    EXPECT_GT(catches, 0u);
    EXPECT_EQ(session.placement("scale")->trials(), fed);
    EXPECT_EQ(fed, 6u);
}

TEST_F(SessionTest, SliderRecordsWhereTheParticipantStoppedRaisingQuality) {
    json j = forcedChoice(1);
    j["procedure"] = "slider";
    j["conditions"][0]["placement"] = {{"kind", "constant"}, {"repeats", 1}};
    j["timing"] = {{"fixation_ms", 0}, {"interval_ms", 50}, {"blank_ms", 0}};
    Journal journal(journalPath());
    StudySession session(designOf(j), participant(), journal);
    const std::vector<std::optional<Response>> script{
        Response::Continue, std::nullopt, Response::Up, Response::Up,   Response::Reference,
        std::nullopt,       std::nullopt, std::nullopt, Response::Up,   Response::Reference,
        std::nullopt,       std::nullopt, std::nullopt, Response::Down, Response::Accept};
    double t = 0;
    std::vector<FrameShow> shows;
    for (const auto& r : script) {
        FrameInput in;
        in.timeMs = t;
        in.response = r;
        shows.push_back(session.frame(in));
        t += kPeriod;
    }
    EXPECT_TRUE(session.finished());
    // Starts at the least quality (scale 3), two steps up to 2, the reference for 3 frames.
    EXPECT_DOUBLE_EQ(shows[1].stimulus->render.scale, 3.0);
    EXPECT_DOUBLE_EQ(shows[3].stimulus->render.scale, 2.0);
    EXPECT_EQ(shows[4].phase, Phase::Interval);
    EXPECT_EQ(shows[4].stimulus->render.method, Method::Reference);
    EXPECT_EQ(shows[7].phase, Phase::Response);
    const TrialRecord r = trialFromJson(linesOfType(journalPath(), "trial").at(0));
    EXPECT_EQ(r.response, "accept");
    EXPECT_DOUBLE_EQ(r.level, 2.0); // accepted: up to 1.5, then down to 2
    EXPECT_EQ(r.sliderLevel, 2.0);  // where the raising stopped first
    // Each level shown is a segment: 3, 2.5, 2, the reference, 2, 1.5, the reference, 1.5, 2.
    ASSERT_EQ(r.intervals.size(), 9u);
    EXPECT_EQ(r.intervals[2].shown, "condition@2");
    EXPECT_EQ(r.intervals[3].shown, "comparison");
    EXPECT_EQ(r.intervals[3].frames, 3u);
    EXPECT_EQ(r.intervals[8].shown, "condition@2");
}

TEST_F(SessionTest, RampShowsItsStepsInTheDrawnDirection) {
    json j = forcedChoice(1);
    j["procedure"] = "ramp";
    j["ramp_steps"] = 5;
    j["conditions"][0]["placement"] = {{"kind", "constant"}, {"repeats", 2}};
    j["conditions"][0]["levels"] = json::array({1.0, 2.0, 3.0});
    j["timing"] = {{"fixation_ms", 0}, {"interval_ms", 50}, {"blank_ms", 0}};
    Journal journal(journalPath());
    StudySession session(designOf(j), participant(), journal);
    EXPECT_EQ(session.allStimuli().size(), 4u); // three levels and the reference
    Player player;
    player.responseFrames = 1;
    player.answer = [](const StudySession::TrialInfo& t) {
        return t.rampUp ? Response::Up : Response::Down;
    };
    player.untilDone(session);
    const auto trials = linesOfType(journalPath(), "trial");
    ASSERT_EQ(trials.size(), 6u);
    std::map<double, std::string> directions; // each level once up, once down
    for (const json& line : trials) {
        const TrialRecord r = trialFromJson(line);
        directions[r.level] += r.response == "up" ? "u" : "d";
        EXPECT_TRUE(r.positive);
        ASSERT_EQ(r.intervals.size(), 5u);
        // From the trial's level to the least foveated level (1) when quality goes up.
        const bool up = r.response == "up";
        const std::string from = up ? r.intervals.front().shown : r.intervals.back().shown;
        const std::string to = up ? r.intervals.back().shown : r.intervals.front().shown;
        char level[32];
        std::snprintf(level, sizeof level, "condition@%g", r.level);
        EXPECT_EQ(from, level);
        EXPECT_EQ(to, "condition@1");
    }
    ASSERT_EQ(directions.size(), 3u);
    for (auto [level, d] : directions) {
        std::ranges::sort(d);
        EXPECT_EQ(d, "du") << level;
    }
}

TEST_F(SessionTest, ConditionsOneAfterAnotherWithABreakBetween) {
    json j = interleaved();
    j["break_between_conditions"] = true;
    j["break_every"] = 0;
    j["gaze"] = json::object();
    for (json& c : j["conditions"])
        c["placement"]["max_trials"] = 3;
    Journal journal(journalPath());
    StudySession session(designOf(j), participant(), journal);
    Player player;
    player.responseFrames = 1;
    player.untilDone(session);
    std::string order;
    for (const json& t : linesOfType(journalPath(), "trial")) {
        order += t["condition"].get<std::string>() + (t["practice"].get<bool>() ? "p" : "");
    }
    EXPECT_EQ(order, "apaaabpbbb");
    const auto breaks = std::ranges::count_if(
        player.runs, [](const auto& run) { return run.first == Phase::Break; });
    EXPECT_EQ(breaks, 1);
}

TEST_F(SessionTest, BreaksEveryNTrials) {
    json j = interleaved();
    j["break_every"] = 4;
    j["practice_trials"] = 0;
    j["gaze"] = json::object();
    for (json& c : j["conditions"])
        c["placement"]["max_trials"] = 5;
    Journal journal(journalPath());
    StudySession session(designOf(j), participant(), journal);
    Player player;
    player.responseFrames = 1;
    player.untilDone(session);
    ASSERT_EQ(linesOfType(journalPath(), "trial").size(), 10u);
    const auto breaks = std::ranges::count_if(
        player.runs, [](const auto& run) { return run.first == Phase::Break; });
    EXPECT_EQ(breaks, 2); // after trials 4 and 8
}

TEST_F(SessionTest, NoAnswerBeforeTheTimeoutRepeatsTheTrial) {
    json j = forcedChoice(1);
    j["timing"] = {
        {"fixation_ms", 0}, {"interval_ms", 50}, {"blank_ms", 0}, {"response_timeout_ms", 200}};
    Journal journal(journalPath());
    StudySession session(designOf(j), participant(), journal);
    Player player;
    player.responseFrames = 1000;
    for (int i = 0; i < 100 && linesOfType(journalPath(), "repeat").empty(); ++i) {
        player.step(session);
    }
    ASSERT_EQ(linesOfType(journalPath(), "repeat").size(), 1u);
    // 200 ms at 60 Hz: 12 frames of the response phase, the 13th begins the repeat (the two
    // 50 ms intervals, 3 frames each with no blank between, log as one run).
    const std::vector<std::pair<Phase, int>> expected{{Phase::Instructions, 1},
                                                      {Phase::Interval, 6},
                                                      {Phase::Response, 12},
                                                      {Phase::Interval, 1}};
    EXPECT_EQ(player.runs, expected);
    EXPECT_EQ(linesOfType(journalPath(), "repeat")[0]["why"], "timeout");
    player.responseFrames = 1;
    player.untilDone(session);
    const auto trials = linesOfType(journalPath(), "trial");
    ASSERT_EQ(trials.size(), 1u);
    EXPECT_EQ(trials[0]["trial"], 1u);
}

TEST(Responses, NamesRoundTrip) {
    for (const Response r : {Response::First, Response::Second, Response::Same, Response::Yes,
                             Response::No, Response::Up, Response::Down, Response::Reference,
                             Response::Accept, Response::Continue}) {
        EXPECT_EQ(responseNamed(responseName(r)), r) << responseName(r);
    }
    EXPECT_EQ(responseName(Response::First), "first");
    EXPECT_FALSE(responseNamed("1"));
}

} // namespace
} // namespace gt::study
