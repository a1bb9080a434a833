// `gazetrace track` with two eyes: --source-left/--source-right (a camera each), or --source with
// --regions (one camera seeing both eyes). Each eye runs its own EyePipeline with its own
// calibration ("left" / "right" of one calibration file); the filtered samples are paired by time
// (gaze/binocular.hpp) into a combined gaze and the vergence. Two recordings are read in time
// order (the one whose next frame is older goes first), as two free-running cameras deliver.
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>

#include <opencv2/core/utility.hpp>

#include "capture/frame_source.hpp"
#include "capture/region_source.hpp"
#include "core/error.hpp"
#include "eye_commands.hpp"
#include "eye_source_parsing.hpp"
#include "formats/atomic_file.hpp"
#include "formats/csv_tables.hpp"
#include "gaze/binocular.hpp"
#include "gaze/calibration_set.hpp"
#include "gaze/eye_pipeline.hpp"
#include "net/udp_emitter.hpp"
#include "option_parsing.hpp"
#include "score/detection_score.hpp"
#include "stats.hpp"
#include "stop_request.hpp"

namespace gt::app {

namespace {

struct EyeTruthTable {
    std::optional<eyetrack::CsvTable> table;
    int visible = 0, within5 = 0;
};

// The truth vergence of a row: the angle at the fixated point between the two eyes.
double truthVergenceDeg(const eyetrack::CsvTable& t, std::size_t row, double ipdMm) {
    const cv::Vec3d f(t.number(row, "fix_x_mm"), t.number(row, "fix_y_mm"),
                      t.number(row, "fix_z_mm"));
    const cv::Vec3d a = cv::normalize(f - cv::Vec3d(-0.5 * ipdMm, 0, 0));
    const cv::Vec3d b = cv::normalize(f - cv::Vec3d(0.5 * ipdMm, 0, 0));
    return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / CV_PI;
}

void checkBinocularOptions(const TrackOptions& o) {
    const bool split = !o.regions.empty();
    if (split && (o.source.empty() || !o.sourceLeft.empty() || !o.sourceRight.empty())) {
        throw ArgumentError("--regions splits the one --source; without --source-left/-right");
    }
    if (!split && (o.sourceLeft.empty() || o.sourceRight.empty())) {
        throw ArgumentError("two eyes need both --source-left and --source-right");
    }
    if (o.calibration.empty()) {
        throw ArgumentError("two eyes need --calibration with a left and a right eye (gazetrace "
                            "calibrate --source-left/--source-right)");
    }
    if (o.model != "2d" && o.model != "3d") {
        throw ArgumentError("--model " + o.model + ": expected 2d or 3d");
    }
}

// The left or right eye's detection against its truth (rows by frame number).
void scoreEye(EyeTruthTable& t, const eyetrack::Frame& frame, const eyetrack::EyeStep& step) {
    if (t.table) {
        const auto row = static_cast<std::size_t>(frame.sequence);
        if (row < t.table->rows() &&
            t.table->number(row, "visibility") >= eyetrack::kVisibleShare) {
            ++t.visible;
            if (step.pupil.found &&
                std::hypot(step.pupil.centre().x - t.table->number(row, "cx"),
                           step.pupil.centre().y - t.table->number(row, "cy")) <= 5.0) {
                ++t.within5;
            }
        }
    }
}

// Each eye's sample with its own angles, then the combined gaze with the vergence.
void sendBinocular(eyetrack::UdpEmitter& emitter, const eyetrack::DisplayGeometry& display,
                   double ipdMm, int e, const eyetrack::GazeSample& s,
                   const eyetrack::BinocularSample& b) {
    const char* const names[2] = {"left", "right"};
    (void)emitter.sendEye(
        s, names[e],
        eyetrack::eyeAnglesDeg(display, ipdMm, e == 0 ? eyetrack::Eye::Left : eyetrack::Eye::Right,
                               {s.x, s.y}));
    (void)emitter.sendCombined(b.combined,
                               b.vergence ? std::optional(b.vergence->angleDeg) : std::nullopt,
                               b.vergence ? std::optional(b.vergence->distanceCm) : std::nullopt);
}

// One row of --out: the combined gaze, both eyes' when paired, the vergence when known.
void writeBinocularRow(std::ostream& s, const eyetrack::BinocularSample& b) {
    s << cv::format("%.3f,%.2f,%.2f,", b.combined.tMs, b.combined.x, b.combined.y);
    if (b.left && b.right) {
        s << cv::format("%.2f,%.2f,%.2f,%.2f,", b.left->x, b.left->y, b.right->x, b.right->y);
    } else {
        s << ",,,,";
    }
    if (b.vergence) {
        s << cv::format("%.3f,%.2f", b.vergence->angleDeg, b.vergence->distanceCm);
    } else {
        s << ',';
    }
    s << '\n';
}

// What a two-eye run counted, for its summary.
struct BinocularTally {
    int frames[2] = {0, 0};
    int pairs = 0, withVergence = 0;
    double maxSkew = 0.0;
    std::vector<double> vergenceErrors, vergenceErrorsFree, busyMs;

    [[nodiscard]] nlohmann::json json(const TrackOptions& o,
                                      const EyeTruthTable (&truth)[2]) const {
        const char* const kEyeNames[2] = {"left", "right"};
        nlohmann::json j{{"eyes", 2},
                         {"frames_left", frames[0]},
                         {"frames_right", frames[1]},
                         {"pairs", pairs},
                         {"max_pair_skew_ms", maxSkew},
                         {"samples_with_vergence", withVergence},
                         {"model", o.model},
                         {"detector", o.detector},
                         {"fps_per_eye", busyMs.empty() ? 0.0 : 1000.0 / eyetrack::median(busyMs)}};
        for (int e = 0; e < 2; ++e) {
            if (!truth[e].table) {
                continue;
            }
            j[std::string("detection_rate_5px_") + kEyeNames[e]] =
                truth[e].visible ? static_cast<double>(truth[e].within5) / truth[e].visible : 0.0;
        }
        if (!vergenceErrors.empty()) {
            j["vergence_error_deg_median"] = eyetrack::median(vergenceErrors);
            j["vergence_error_deg_median_free_viewing"] = eyetrack::median(vergenceErrorsFree);
        }
        return j;
    }
};

} // namespace

nlohmann::json runTrackBinocular(const TrackOptions& o) {
    cv::setNumThreads(1);
    checkBinocularOptions(o);
    const bool split = !o.regions.empty();
    std::pair<cv::Rect, cv::Rect> regions;
    if (split) {
        regions = parseEyeRegions(o.regions);
    }
    const auto set = eyetrack::CalibrationSet::load(o.calibration);
    const auto camera = eyeCamera(o.camera);
    std::unique_ptr<eyetrack::FrameSource> shared;
    std::unique_ptr<eyetrack::EyePipeline> pipes[2];
    const char* names[2] = {"left", "right"};
    if (split) {
        shared = openFrameSource(o.source);
    }
    for (int e = 0; e < 2; ++e) {
        auto source = split ? nullptr : openFrameSource(e == 0 ? o.sourceLeft : o.sourceRight);
        pipes[e] = std::make_unique<eyetrack::EyePipeline>(
            std::move(source), eyetrack::makePupilDetector(pupilDetectorKind(o.detector)),
            gazeMapper(set.eye(names[e]), gazeModel(o.model), camera));
    }
    const eyetrack::DisplayGeometry display = pipes[0]->mapper()->display();
    eyetrack::BinocularCombiner combiner(display, o.ipdMm);
    std::unique_ptr<eyetrack::UdpEmitter> emitter;
    if (!o.emit.empty()) {
        emitter = std::make_unique<eyetrack::UdpEmitter>(parseUdpEndpoint(o.emit), display);
    }
    std::unique_ptr<eyetrack::AtomicFile> gazeCsv;
    if (!o.out.empty()) {
        gazeCsv = std::make_unique<eyetrack::AtomicFile>(o.out);
        gazeCsv->stream() << "t_ms,x,y,left_x,left_y,right_x,right_y,vergence_deg,fixation_cm\n";
    }
    EyeTruthTable truth[2];
    const std::vector<std::string> columns{"frame", "cx",       "cy",       "visibility",
                                           "phase", "fix_x_mm", "fix_y_mm", "fix_z_mm"};
    if (!o.truth.empty()) {
        truth[0].table = eyetrack::CsvTable::loadTruth(o.truth, columns);
    }
    if (!o.truthRight.empty()) {
        truth[1].table = eyetrack::CsvTable::loadTruth(o.truthRight, columns);
    }

    BinocularTally tally;
    std::optional<eyetrack::Frame> pending[2];
    auto process = [&](int e, const eyetrack::Frame& frame) {
        const auto begin = std::chrono::steady_clock::now();
        const eyetrack::EyeStep step = pipes[e]->process(frame);
        tally.busyMs.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin)
                .count());
        ++tally.frames[e];
        scoreEye(truth[e], frame, step);
        const eyetrack::BinocularSample b =
            combiner.push(e == 0 ? eyetrack::Eye::Left : eyetrack::Eye::Right, *step.sample);
        if (b.left && b.right) {
            ++tally.pairs;
            tally.maxSkew = std::max(tally.maxSkew, std::abs(b.left->tMs - b.right->tMs));
        }
        if (b.vergence) {
            ++tally.withVergence;
            const auto row = static_cast<std::size_t>(frame.sequence);
            if (truth[0].table && row < truth[0].table->rows()) {
                const double err = std::abs(b.vergence->angleDeg -
                                            truthVergenceDeg(*truth[0].table, row, o.ipdMm));
                tally.vergenceErrors.push_back(err);
                if (truth[0].table->text(row, "phase") == "free") {
                    tally.vergenceErrorsFree.push_back(err);
                }
            }
        }
        if (emitter) sendBinocular(*emitter, display, o.ipdMm, e, *step.sample, b);
        if (gazeCsv) writeBinocularRow(gazeCsv->stream(), b);
    };
    // Cameras end at SIGINT or SIGTERM as at their last frame; recordings fail (track_command).
    const bool live = split ? shared->liveClock()
                            : pipes[0]->source().liveClock() || pipes[1]->source().liveClock();
    for (;;) {
        if (o.maxFrames > 0 && tally.frames[0] + tally.frames[1] >= 2 * o.maxFrames) {
            break;
        }
        if (liveRunEnds(live)) break;
        if (split) {
            auto f = shared->next();
            if (!f) {
                break;
            }
            process(0, eyetrack::cropFrame(*f, regions.first));
            process(1, eyetrack::cropFrame(*f, regions.second));
            continue;
        }
        for (int e = 0; e < 2; ++e) {
            if (!pending[e]) {
                pending[e] = pipes[e]->grab();
            }
        }
        if (!pending[0] && !pending[1]) {
            break;
        }
        const int e = !pending[1]                          ? 0
                      : !pending[0]                        ? 1
                      : pending[0]->tMs <= pending[1]->tMs ? 0
                                                           : 1;
        process(e, *pending[e]);
        pending[e].reset();
    }
    if (tally.frames[0] == 0 || tally.frames[1] == 0) {
        throw ArgumentError(std::string("the ") + (tally.frames[0] == 0 ? "left" : "right") +
                            " eye's source gave no frames");
    }
    if (gazeCsv) {
        gazeCsv->commit();
    }
    return tally.json(o, truth);
}

} // namespace gt::app
