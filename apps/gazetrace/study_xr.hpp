#pragma once
// `gazetrace study --display xr`: a participant's run in an OpenXR session. Each frame the
// runtime paces drives the session: its predicted display time is the frame clock, the gaze is
// the runtime's (XR_EXT_eye_gaze_interaction) where it reports one, else the run's own source,
// the answers are the controller buttons (xr/response_actions.hpp, mapped by
// study_xr_buttons.hpp) or the simulated observer's. An interval shows its stimulus to both eyes
// (the same condition, each eye's pose and field of view, the scene placed at the stimulus's
// camera); fixation frames show a cross at the fixation point, every other frame is black.
// Every stimulus is built for the runtime's eye images before the first trial.
#include <memory>

#include <nlohmann/json.hpp>

#include "session.hpp"
#include "study_run.hpp"

namespace gt::app {

// The runtime, the renderer on its device and the OpenXR session, opened before the study's
// session so its frame counts use the headset's refresh:
//   StudyXrDisplay xr(setup);
//   settings.refreshHz = xr.refreshHz();
//   study::StudySession session(design, settings, journal);
//   summary = xr.run(session);
// The eye images are the runtime's recommended size, scaled down (never up) to fit the run's
// view (setup.view: --width/--height or the design's). Every scene of the design is loaded on
// the runtime's Vulkan device before the first trial. Throws ArgumentError for a flip observer
// (it reads frames back); gt::Error when the runtime fails.
class StudyXrDisplay {
public:
    explicit StudyXrDisplay(const StudySetup& setup);
    ~StudyXrDisplay();
    StudyXrDisplay(const StudyXrDisplay&) = delete;
    StudyXrDisplay& operator=(const StudyXrDisplay&) = delete;

    // The headset's refresh rate (frames are run, nothing shown, until the runtime paces one).
    [[nodiscard]] double refreshHz();
    // Runs `session` until it is finished, setup.maxTrials were done, the runtime ends the
    // OpenXR session or a stop is requested; its summary.
    [[nodiscard]] nlohmann::json run(study::StudySession& session);

private:
    class Run;
    std::unique_ptr<Run> mRun;
};

} // namespace gt::app
