#include "study_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "core/error.hpp"
#include "design.hpp"
#include "gaze_mapping.hpp"
#include "observer.hpp"
#include "quality/eccentricity_bands.hpp"
#include "quality/flip.hpp"

namespace gt::app {

namespace {

// SplitMix64's finaliser: a trial's own seed from the run's, so each trial's draw is the same
// whether or not the run was interrupted before it.
uint64_t mixSeed(uint64_t seed, uint64_t trial, uint64_t answer) {
    uint64_t z = seed ^ ((trial + 1) * 0x9E3779B97F4A7C15ull) ^ (answer * 0xD1B54A32D192ED03ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

bool accepts(const std::vector<study::Response>& accepted, study::Response r) {
    return std::find(accepted.begin(), accepted.end(), r) != accepted.end();
}

} // namespace

study::GazeAngles anglesOfViewPixel(const StudyView& view, glm::vec2 px) {
    // Pixel centres lie at whole numbers: the view's centre is between its middle pixels.
    const glm::vec2 centre(0.5f * static_cast<float>(view.width - 1),
                           0.5f * static_cast<float>(view.height - 1));
    if (view.hmd) {
        const display::EyeTangents t = display::eyeTangents(*view.hmd, 0);
        const glm::vec2 a =
            render::anglesOfDirection(render::directionOfPixel(px, t, view.width, view.height));
        return {a.x, a.y};
    }
    const render::ScreenGeometry screen;
    const glm::vec2 screenCentre(0.5f * static_cast<float>(screen.widthPx),
                                 0.5f * static_cast<float>(screen.heightPx));
    const glm::vec2 a = screen.anglesOfPixel(screenCentre + (px - centre));
    return {a.x, a.y};
}

render::View stimulusView(StudyStimuli& stimuli, const StudyView& view,
                          const study::Stimulus& stimulus, glm::vec2 gazePx, double ms) {
    if (!view.hmd) {
        return stimuli.view(stimulus, view.stimuli, view.width, view.height, gazePx, ms);
    }
    // A headset's left eye, looking where the gaze pixel lies in its image.
    const render::StereoRig rig(*view.hmd, false);
    render::StereoGaze gaze;
    gaze.direction = rig.directionOfLeftPixel(gazePx);
    render::FoveationMethod& method =
        stimuli.method(stimulus, view.stimuli, view.width, view.height);
    const auto eyes = rig.views(stimuli.camera(stimulus.scene, ms), gaze, method,
                                StudyStimuli::post(stimulus), stimuli.exposure(stimulus));
    return eyes[0];
}

std::optional<ObserverSpec> parseObserver(const std::string& text) {
    if (text.empty()) {
        return std::nullopt;
    }
    const auto bad = [&](const std::string& why) {
        return ArgumentError("--observer: " + why +
                             " (expected level:T[,SLOPE[,LAPSE]] or flip:T[,SLOPE[,LAPSE]]), "
                             "got '" +
                             text + "'");
    };
    const auto colon = text.find(':');
    const std::string kind = text.substr(0, colon);
    if (colon == std::string::npos || (kind != "level" && kind != "flip")) {
        throw bad("unknown observer");
    }
    ObserverSpec spec;
    spec.basis = kind == "flip" ? ObserverBasis::Flip : ObserverBasis::Level;
    spec.slope = kind == "flip" ? kFlipObserverSlope : kLevelObserverSlope;
    std::vector<double> values;
    std::stringstream rest(text.substr(colon + 1));
    for (std::string item; std::getline(rest, item, ',');) {
        char* end = nullptr;
        const double v = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !std::isfinite(v)) {
            throw bad("'" + item + "'");
        }
        values.push_back(v);
    }
    if (values.empty() || values.size() > 3 || text.back() == ',') {
        throw bad("one to three numbers");
    }
    spec.threshold = values[0];
    if (values.size() > 1) {
        spec.slope = values[1];
    }
    if (values.size() > 2) {
        spec.lapse = values[2];
    }
    if (!(spec.slope > 0.0)) {
        throw bad("the slope must be above 0");
    }
    if (!(spec.lapse >= 0.0 && spec.lapse < 0.5)) {
        throw bad("the lapse rate must be in [0, 0.5)");
    }
    return spec;
}

double flipMetric(const quality::RgbaImage& reference, const quality::RgbaImage& test,
                  const foveation::DisplayProfile& display, glm::vec2 gazePx) {
    const double ppd = quality::pixelsPerDegree(display.width, display.viewingDistance);
    const std::vector<uint8_t> bands = quality::bandMap(display, test.width, test.height, gazePx);
    const auto counts = quality::pixelsPerBand(bands);
    // Band 0 at the display's own resolution, band b as the eye resolves it at its inner
    // eccentricity (eval's flip_ecc).
    double worst = 0.0;
    for (std::size_t b = 0; b < quality::kBands; ++b) {
        if (counts[b] == 0) {
            continue;
        }
        const double bandPpd =
            b == 0 ? ppd : ppd / quality::acuityFalloff(quality::kBandStartDeg[b]);
        const auto perBand =
            quality::meanPerBand(quality::flipErrorMap(reference, test, bandPpd), bands);
        worst = std::max(worst, perBand[b]);
    }
    return worst;
}

StudyObserver::StudyObserver(ObserverSpec spec, const study::StudyDesign& design,
                             const StudyView& view, Shot shot)
    : mSpec(spec), mDesign(design), mView(view), mShot(std::move(shot)) {
    check(spec, design);
}

void StudyObserver::check(const ObserverSpec& spec, const study::StudyDesign& design) {
    if (spec.basis != ObserverBasis::Flip) {
        return;
    }
    const study::Procedure p = design.procedure;
    if (p != study::Procedure::ForcedChoice && p != study::Procedure::YesNo &&
        p != study::Procedure::Pair) {
        throw ArgumentError("--observer flip: answers forced-choice, yes-no and pair designs; "
                            "give level:T for this one");
    }
}

void StudyObserver::frame(const study::FrameShow& show, const quality::RgbaImage* picture) {
    if (mTrial != show.trial) {
        mTrial = show.trial;
        mIntervals.clear();
    }
    if (show.phase == study::Phase::Interval && show.stimulus) {
        if (mPhase != study::Phase::Interval) {
            mIntervals.push_back({*show.stimulus, {}});
        }
        if (picture) {
            mIntervals.back().picture = *picture; // the interval's last frame counts
        }
    }
    mPhase = show.phase;
}

const study::Condition* StudyObserver::condition(const std::string& name) const {
    for (const study::Condition& c : mDesign.conditions) {
        if (c.name == name) {
            return &c;
        }
    }
    return nullptr;
}

double StudyObserver::metricOf(const study::StudySession::TrialInfo& trial) {
    if (mIntervals.empty() || mIntervals.front().picture.pixels.empty()) {
        throw Error("--observer flip: the trial's frames were not read back");
    }
    const Interval* shown = &mIntervals.front();
    quality::RgbaImage comparison;
    if (mIntervals.size() >= 2) {
        shown = &mIntervals[trial.conditionFirst ? 0 : 1];
        comparison = mIntervals[trial.conditionFirst ? 1 : 0].picture;
    } else {
        const study::Condition* c = condition(trial.condition);
        if (!c) {
            throw Error("--observer flip: no condition '" + trial.condition + "'");
        }
        comparison = mShot({study::comparisonOf(*c), shown->stimulus.scene});
    }
    return flipMetric(comparison, shown->picture, mView.stimuli.pointSets, mView.fixationPx);
}

bool StudyObserver::positive(const study::StudySession::TrialInfo& trial, uint64_t seed) {
    study::PsychometricFunction f;
    f.threshold = mSpec.threshold;
    f.slope = mSpec.slope;
    f.lapse = mSpec.lapse;
    f.guess = mDesign.procedure == study::Procedure::ForcedChoice ? 0.5 : 0.0;
    double x = trial.level;
    if (mSpec.basis == ObserverBasis::Flip) {
        x = metricOf(trial);
        mLastMetric = x;
    } else if (const study::Condition* c = condition(trial.condition)) {
        f.increasing = study::infoOf(c->vary).higherFoveatesMore;
    }
    study::SimulatedObserver observer(f, seed);
    return trial.catchTrial ? observer.answerCatch() : observer.answer(x);
}

std::optional<study::Response> StudyObserver::answer(const study::StudySession& session,
                                                     const study::FrameShow& show) {
    using study::Response;
    const std::vector<Response> accepted = session.accepted();
    if (accepted.empty()) {
        return std::nullopt;
    }
    const std::optional<study::StudySession::TrialInfo> trial = session.currentTrial();
    if (show.phase != study::Phase::Response || !trial) {
        return accepts(accepted, Response::Continue) ? std::optional(Response::Continue)
                                                     : std::nullopt;
    }
    const uint64_t answers = mAnswered == show.trial ? ++mAnswers : (mAnswers = 0);
    mAnswered = show.trial;
    const bool yes = positive(*trial, mixSeed(session.seed(), show.trial, answers));
    const bool first = trial->conditionFirst;
    Response r = Response::Continue;
    switch (mDesign.procedure) {
    case study::Procedure::ForcedChoice: // the interval that held the condition, when seen
        r = yes == first ? Response::First : Response::Second;
        break;
    case study::Procedure::YesNo:
        r = yes ? Response::Yes : Response::No;
        break;
    case study::Procedure::Pair: // the reference better when the difference is seen
        r = yes ? (first ? Response::Second : Response::First) : Response::Same;
        break;
    case study::Procedure::Ramp:
        r = yes ? (trial->rampUp ? Response::Up : Response::Down) : Response::Same;
        break;
    case study::Procedure::Slider: // raise quality while the foveation shows
        r = yes ? Response::Up : Response::Accept;
        break;
    }
    return accepts(accepted, r) ? r : accepted.front();
}

} // namespace gt::app
