#pragma once
// A whole design run by simulated participants, headless: the real StudySession (its plan,
// placements, gaze rules and journal) fed one frame per refresh period with the gaze on the
// fixation point, each trial answered by a SimulatedObserver per condition, then the journals
// analysed as `study analyse` would. `gazetrace study simulate` prints what comes back: how
// often the fits' 95 % intervals hold the planted threshold, in how many trials, how close.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis.hpp"
#include "design.hpp"
#include "observer.hpp"
#include "session.hpp"

namespace gt::study {

// The function planted in a condition: logistic, threshold `threshold` (0: the middle of the
// condition's levels), slope `slope` (0: a core rising from 25 % to 75 % over a quarter of the
// levels' span), the lapse rate, and the guess its procedure implies (forced choice 0.5; yes/no
// false alarms as rare as lapses; pair, ramp and slider 0: "same" when nothing is seen).
[[nodiscard]] PsychometricFunction plantedFunction(const StudyDesign& design,
                                                   const Condition& condition, double threshold,
                                                   double slope, double lapse);

// One simulated participant: an observer per condition, answering what a session shows.
class SimulatedParticipant {
public:
    // `functions[i]` is planted in design.conditions[i].
    SimulatedParticipant(const StudyDesign& design,
                         const std::vector<PsychometricFunction>& functions, uint64_t seed);
    // The answer to this frame (Continue at instructions and breaks, the trial's answer in the
    // response phase), or none: keep watching.
    [[nodiscard]] std::optional<Response> answer(const FrameShow& show,
                                                 const StudySession& session);

private:
    Response sliderAnswer(const StudySession::TrialInfo& trial, SimulatedObserver& observer,
                          uint32_t trialsDone);

    Procedure mProcedure;
    std::map<std::string, SimulatedObserver> mObservers;
    uint32_t mSliderTrial = ~0u;
    uint32_t mSliderSteps = 0;
    bool mComparedReference = false;
};

// Runs one participant's whole session into `journal`. Throws std::logic_error when a trial does
// not end within an hour of frames (a fault of the session).
void runSimulatedParticipant(const StudyDesign& design, const std::string& participant,
                             Journal& journal, SimulatedParticipant& simulated);

struct DesignSimulationSettings {
    uint32_t observers = 100;
    double threshold = 0.0; // see plantedFunction
    double slope = 0.0;
    double lapse = 0.02;
    uint64_t seed = 1;
    uint32_t bootstrap = 200; // per fit: enough for a 95 % percentile interval
    // Called before each participant's run and each fit: the app's stop check (SIGINT throws
    // from there).
    std::function<void()> beforeParticipant;
};

// How well one condition's planted threshold came back.
struct ConditionRecovery {
    std::string condition;
    PsychometricFunction planted;
    uint32_t fitted = 0;  // participants with a fit (the slider has none)
    uint32_t covered = 0; // ... whose 95 % interval holds the planted threshold
    std::optional<double> trialsMedian;
    std::optional<double> thresholdMedian; // of the fits
    std::optional<double> errorMedian;     // |fit - planted|
    std::optional<double> ruleErrorMedian; // |the procedure's rule - planted|
};

struct DesignSimulation {
    std::vector<std::filesystem::path> journals;
    Analysis analysis;
    std::vector<ConditionRecovery> conditions;
};

// Writes one journal per participant into `folder` (DESIGN_simNNN.jsonl; an existing one is a
// JournalError: a simulation never resumes), then analyses them.
[[nodiscard]] DesignSimulation simulateDesign(const StudyDesign& design,
                                              const DesignSimulationSettings& settings,
                                              const std::filesystem::path& folder);

[[nodiscard]] nlohmann::json toJson(const StudyDesign& design, const ConditionRecovery& c);

} // namespace gt::study
