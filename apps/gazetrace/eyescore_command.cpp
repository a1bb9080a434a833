// `gazetrace eyescore`: the pupil detector on sets of synthetic clips, rendered in memory — the
// numbers the eye-tracker issue asks for (detection within 5 px on visible frames, ROC area of
// the confidence, the gaze filter's gate at its threshold, speed) on any preset and seed range,
// so a held-out range can be scored the same way as the development one.
#include <chrono>
#include <cstdio>
#include <optional>

#include <opencv2/core/utility.hpp>

#include "core/error.hpp"
#include "eye_commands.hpp"
#include "eye_source_parsing.hpp"
#include "formats/atomic_file.hpp"
#include "formats/contact_sheet.hpp"
#include "gaze/gaze_filter.hpp"
#include "pupil/pupil_detector.hpp"
#include "pupil/starburst_detector.hpp"
#include "score/detection_score.hpp"
#include "sim/synthetic_eye.hpp"
#include "stats.hpp"
#include "stop_request.hpp"

namespace gt::app {

namespace {

// One row of --answers: the answer and the evidence its confidence weighed.
void writeAnswerRow(std::ostream& s, std::uint64_t seed, std::size_t frame,
                    const eyetrack::EyeTruth& truth, const eyetrack::DetectionRecord& r,
                    const eyetrack::PupilResult& p, const eyetrack::AnswerEvidence& e,
                    double radiusPx) {
    s << cv::format("%llu,%zu,%.3f,%.3f,%d,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.3f,%.3f,%.5f,"
                    "%.5f,%d,%.3f,%.4f,%.5f,%.5f,%.5f,%.5f,%llu\n",
                    static_cast<unsigned long long>(seed), frame, truth.visibility, r.errorPx,
                    eyetrack::isRight(r, radiusPx) ? 1 : 0, p.confidence, e.confidence,
                    e.visibleSupport, e.fill, e.axisRatio, e.score, e.rivalScore, e.inlierShare,
                    e.contrast, e.semiMajor, e.eyeAxisRatio, e.sizeFactor, e.sizeKnown ? 1 : 0,
                    e.lastDistance, e.levelExcess, e.supportAll, e.rankedConfidence, e.rankedScore,
                    e.rankedRivalScore, static_cast<unsigned long long>(e.earlierFrames));
}

// One row of --misses: the truth beside what was found.
void writeMissRow(std::ostream& s, std::uint64_t seed, std::size_t frame,
                  const eyetrack::EyeTruth& truth, const eyetrack::DetectionRecord& r,
                  const eyetrack::PupilResult& p) {
    s << cv::format("%llu,%zu,%.3f,%.2f,%.2f,%.2f,%.2f,%.2f,%.3f,%.2f,%.2f,%.2f,%.2f\n",
                    static_cast<unsigned long long>(seed), frame, truth.visibility, truth.centre.x,
                    truth.centre.y, p.centre().x, p.centre().y, r.answered ? r.errorPx : -1.0,
                    p.confidence, truth.axisA, truth.axisB, p.semiMajor(), p.semiMinor());
}

nlohmann::json eyescoreSummary(const EyescoreOptions& o,
                               const std::vector<eyetrack::DetectionRecord>& all, double threshold,
                               const std::vector<double>& fps, const nlohmann::json& perSeed) {
    const eyetrack::DetectionScore s = eyetrack::scoreDetections(all, o.radiusPx);
    const eyetrack::ThresholdRates gate = eyetrack::ratesAt(all, threshold, o.radiusPx);
    nlohmann::json sweep = nlohmann::json::array();
    for (int i = 2; i <= 8; ++i) {
        const eyetrack::ThresholdRates t = eyetrack::ratesAt(all, 0.1 * i, o.radiusPx);
        sweep.push_back({{"threshold", t.threshold},
                         {"wrong_rejected", t.wrongRejected},
                         {"right_kept", t.rightKept}});
    }
    return {{"preset", o.preset},
            {"detector", o.detector},
            {"seeds", o.seeds},
            {"frames", s.frames},
            {"visible_frames", s.visible},
            {"radius_px", o.radiusPx},
            {"detection_rate", s.detectionRate},
            {"median_error_px", s.medianErrorPx},
            {"right_answers", s.right},
            {"wrong_answers", s.wrong},
            {"wrong_answers_pupil_hidden", s.wrongHidden},
            {"roc_auc", s.rocAuc},
            {"threshold", threshold},
            {"wrong_rejected", gate.wrongRejected},
            {"right_kept", gate.rightKept},
            {"threshold_sweep", sweep},
            {"median_fps", eyetrack::median(fps)},
            {"per_seed", perSeed}};
}

} // namespace

std::pair<std::uint64_t, std::uint64_t> parseSeedRange(const std::string& s) {
    unsigned long long a = 0, b = 0;
    char dash = 0, extra = 0;
    const int n = std::sscanf(s.c_str(), "%llu%c%llu%c", &a, &dash, &b, &extra);
    if (n == 1 && s.find_first_not_of("0123456789") == std::string::npos) {
        return {a, a};
    }
    if (n != 3 || dash != '-' || b < a || b - a > 10000 ||
        s.find_first_of("+ ") != std::string::npos) {
        throw ArgumentError("--seeds " + s + ": expected N or A-B (A <= B, at most 10001 seeds)");
    }
    return {a, b};
}

// The values the options parser cannot check alone; the gate threshold to score at.
double checkedThreshold(const EyescoreOptions& o) {
    if (o.frames < 1 || o.frames > 100000) {
        throw ArgumentError("--frames " + std::to_string(o.frames) + ": expected 1..100000");
    }
    if (o.skip < 0 || o.skip > 1000000) {
        throw ArgumentError("--skip " + std::to_string(o.skip) + ": expected 0..1000000");
    }
    if (!(o.radiusPx > 0.0) || o.radiusPx > 1000.0) {
        throw ArgumentError("--radius: expected a positive number of pixels");
    }
    const double threshold =
        o.threshold >= 0.0 ? o.threshold : eyetrack::GazeFilterConfig{}.minConfidence;
    if (threshold > 1.0) {
        throw ArgumentError("--threshold: expected 0..1");
    }
    return threshold;
}

// A CSV named by an option, started with its header; none when the option was not given.
std::unique_ptr<eyetrack::AtomicFile> startCsv(const std::string& file, const char* header) {
    if (file.empty()) return nullptr;
    auto csv = std::make_unique<eyetrack::AtomicFile>(file);
    csv->stream() << header;
    return csv;
}

nlohmann::json runEyescore(const EyescoreOptions& o) {
    cv::setNumThreads(1); // the detector's budget is one core
    const double threshold = checkedThreshold(o);
    const auto [first, last] = parseSeedRange(o.seeds);
    // Semi-axes beside the centres: a fit off by a few pixels is often one too large or too
    // small for the arc it saw.
    const auto misses =
        startCsv(o.misses, "seed,frame,visibility,truth_x,truth_y,found_x,found_y,error_px,"
                           "confidence,truth_major,truth_minor,found_major,found_minor\n");
    const auto answers =
        startCsv(o.answers, "seed,frame,visibility,error_px,right,confidence,product,"
                            "visible_support,fill,axis_ratio,score,rival_score,inlier_share,"
                            "contrast,semi_major,eye_axis_ratio,size_factor,size_known,"
                            "last_distance,level_excess,support_all,ranked_product,"
                            "ranked_score,ranked_rival_score,earlier_frames\n");
    std::optional<eyetrack::ContactSheet> sheet;
    if (!o.missesSheet.empty()) {
        sheet.emplace(o.missesSheet, o.sheetEvery);
    }
    std::vector<eyetrack::DetectionRecord> all;
    std::vector<double> fps;
    nlohmann::json perSeed = nlohmann::json::array();
    for (std::uint64_t seed = first; seed <= last; ++seed) {
        eyetrack::EyeSimConfig c;
        c.seed = seed;
        c.frames = o.skip + o.frames;
        eyetrack::applyPreset(c, eyeSimPreset(o.preset));
        const eyetrack::SyntheticEye eye(c);
        std::vector<cv::Mat> images(static_cast<std::size_t>(o.frames));
        std::vector<eyetrack::EyeTruth> truths(images.size());
        for (int f = 0; f < o.frames; ++f) {
            throwIfStopRequested();
            images[f] = eye.render(o.skip + f, &truths[f]);
        }
        throwIfStopRequested(); // not inside the detector's timed loop: a step of its own

        const auto detector = eyetrack::makePupilDetector(pupilDetectorKind(o.detector));
        std::vector<eyetrack::DetectionRecord> records;
        const auto begin = std::chrono::steady_clock::now();
        std::vector<eyetrack::PupilResult> results;
        results.reserve(images.size());
        // The starburst detector's evidence for each answer, for --answers.
        const auto* starburst =
            answers ? dynamic_cast<const eyetrack::StarburstDetector*>(detector.get()) : nullptr;
        std::vector<eyetrack::AnswerEvidence> evidence;
        for (const cv::Mat& img : images) {
            if (o.cold) {
                detector->reset();
            }
            results.push_back(detector->detect(img));
            if (starburst != nullptr) {
                evidence.push_back(starburst->lastEvidence());
            }
        }
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin)
                .count();
        fps.push_back(o.frames / (ms / 1000.0));
        for (std::size_t f = 0; f < images.size(); ++f) {
            const eyetrack::PupilResult& p = results[f];
            eyetrack::DetectionRecord r;
            r.visible = truths[f].visibility >= eyetrack::kVisibleShare;
            r.answered = p.confidence > 0.0;
            r.errorPx = cv::norm(p.centre() - truths[f].centre);
            r.confidence = p.confidence;
            records.push_back(r);
            if (sheet && r.visible && !eyetrack::isRight(r, o.radiusPx)) {
                sheet->add(images[f], p, seed * 100000 + o.skip + f);
            }
            if (answers && r.answered && f < evidence.size()) {
                writeAnswerRow(answers->stream(), seed, o.skip + f, truths[f], r, p, evidence[f],
                               o.radiusPx);
            }
            // Every visible frame not found within the radius, and every answer on a hidden pupil.
            if (misses && !eyetrack::isRight(r, o.radiusPx) && (r.visible || r.answered)) {
                writeMissRow(misses->stream(), seed, o.skip + f, truths[f], r, p);
            }
        }
        const eyetrack::DetectionScore s = eyetrack::scoreDetections(records, o.radiusPx);
        const eyetrack::ThresholdRates g = eyetrack::ratesAt(records, threshold, o.radiusPx);
        perSeed.push_back({{"seed", seed},
                           {"detection_rate", s.detectionRate},
                           {"visible", s.visible},
                           {"median_error_px", s.medianErrorPx},
                           {"wrong", s.wrong},
                           {"wrong_rejected", g.wrongRejected},
                           {"right_kept", g.rightKept}});
        all.insert(all.end(), records.begin(), records.end());
    }
    throwIfStopRequested();
    if (misses) {
        misses->commit();
    }
    if (answers) {
        answers->commit();
    }
    if (sheet && sheet->tiles() > 0) {
        sheet->write();
    }
    nlohmann::json summary = eyescoreSummary(o, all, threshold, fps, perSeed);
    if (o.cold) {
        summary["cold"] = true;
    }
    return summary;
}

} // namespace gt::app
