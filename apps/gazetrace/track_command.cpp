#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>

#include <opencv2/core/utility.hpp>

#include "capture/frame_source.hpp"
#include "core/error.hpp"
#include "eye_commands.hpp"
#include "eye_source_parsing.hpp"
#include "formats/atomic_file.hpp"
#include "formats/contact_sheet.hpp"
#include "formats/csv_tables.hpp"
#include "gaze/calibration.hpp"
#include "gaze/calibration_set.hpp"
#include "gaze/eye_pipeline.hpp"
#include "gaze/gaze_filter.hpp"
#include "gaze/gaze_mailbox.hpp"
#include "net/udp_emitter.hpp"
#include "option_parsing.hpp"
#include "pupil/pupil_detector.hpp"
#include "score/detection_score.hpp"
#include "stats.hpp"
#include "stop_request.hpp"

namespace gt::app {

namespace {

constexpr double kSettleMs = 300.0; // validation samples count once the eye is on the target

std::unique_ptr<eyetrack::GazeMapper> openGazeMapper(const TrackOptions& o) {
    const auto set = eyetrack::CalibrationSet::load(o.calibration);
    return gazeMapper(set.eye(o.eye), gazeModel(o.model), eyeCamera(o.camera));
}

// --truth: rows by frame number (eyesim writes every frame, hand labels only some).
struct TrackTruth {
    std::optional<eyetrack::CsvTable> table;
    std::map<std::uint64_t, std::size_t> rows;
    bool hasDoubtful = false;
};

TrackTruth loadTrackTruth(const TrackOptions& o) {
    TrackTruth truth;
    if (o.truth.empty()) return truth;
    truth.table = eyetrack::CsvTable::loadTruth(o.truth, {"frame", "cx", "cy", "visibility"});
    for (std::size_t i = 0; i < truth.table->rows(); ++i) {
        const double f = truth.table->number(i, "frame");
        if (!(f >= 0.0) || f != std::floor(f))
            throw ArgumentError("--truth " + o.truth + ": row " + std::to_string(i + 2) +
                                " has no whole frame number");
        truth.rows[static_cast<std::uint64_t>(f)] = i;
    }
    truth.hasDoubtful = truth.table->has("doubtful");
    return truth;
}

// The detector and the gaze scored against the truth, frame by frame.
class TrackScore {
public:
    explicit TrackScore(const TrackTruth& truth) : mTruth(truth) {}
    void add(const eyetrack::Frame& frame, const eyetrack::EyeStep& step,
             const eyetrack::EyePipeline& pipeline) {
        if (!mTruth.table) return;
        const auto found = mTruth.rows.find(frame.sequence);
        if (found == mTruth.rows.end()) return;
        const eyetrack::CsvTable& truth = *mTruth.table;
        const std::size_t row = found->second;
        const eyetrack::PupilResult& p = step.pupil;
        if (step.screen && truth.has("phase") && truth.has("target_x")) {
            // Gaze accuracy on the settled validation targets, as calibrate measures it.
            if (truth.text(row, "phase") == "validation") {
                const cv::Point2d target(truth.number(row, "target_x"),
                                         truth.number(row, "target_y"));
                if (target != mLastTarget) {
                    mLastTarget = target;
                    mTargetOnsetMs = frame.tMs;
                }
                if (frame.tMs - mTargetOnsetMs >= kSettleMs && p.confidence >= 0.6)
                    mGazeErrors.push_back(
                        pipeline.mapper()->display().angularDistanceDeg(*step.screen, target));
            }
        }
        const bool certain = !mTruth.hasDoubtful || truth.number(row, "doubtful") == 0.0;
        addRecord(truth, row, p, certain);
        if (truth.number(row, "visibility") >= eyetrack::kVisibleShare) {
            ++mVisible;
            if (certain) ++mCertainVisible;
            if (p.found) {
                const double e = std::hypot(p.centre().x - truth.number(row, "cx"),
                                            p.centre().y - truth.number(row, "cy"));
                mErrors.push_back(e);
                if (e <= 5.0) {
                    ++mWithin5;
                    if (certain) ++mCertainWithin5;
                }
            }
        }
    }
    void addJson(nlohmann::json& j) const {
        if (!mTruth.table) return;
        j["visible_frames"] = mVisible;
        j["detection_rate_5px"] = mVisible ? static_cast<double>(mWithin5) / mVisible : 0.0;
        j["median_error_px"] = eyetrack::median(mErrors);
        if (mTruth.hasDoubtful) {
            j["certain_visible_frames"] = mCertainVisible;
            j["detection_rate_5px_certain"] =
                mCertainVisible ? static_cast<double>(mCertainWithin5) / mCertainVisible : 0.0;
        }
        // The gaze filter's gate on the labelled frames' answers, as eyescore reports it.
        const double gate = eyetrack::GazeFilterConfig{}.minConfidence;
        const eyetrack::ThresholdRates rates = eyetrack::ratesAt(mRecords, gate);
        const eyetrack::DetectionScore s = eyetrack::scoreDetections(mRecords);
        j["threshold"] = gate;
        j["right_answers"] = s.right;
        j["wrong_answers"] = s.wrong;
        j["wrong_rejected"] = rates.wrongRejected;
        j["right_kept"] = rates.rightKept;
        if (mTruth.hasDoubtful) {
            const eyetrack::ThresholdRates certain = eyetrack::ratesAt(mCertainRecords, gate);
            j["right_kept_certain"] = certain.rightKept;
            j["wrong_rejected_certain"] = certain.wrongRejected;
        }
        if (!mGazeErrors.empty()) {
            double sum = 0.0;
            for (const double e : mGazeErrors)
                sum += e;
            j["gaze_accuracy_deg"] = sum / static_cast<double>(mGazeErrors.size());
            j["gaze_accuracy_samples"] = mGazeErrors.size();
        }
    }

private:
    // The frame's answer against its label, for the gate's rates (detection_score.hpp).
    void addRecord(const eyetrack::CsvTable& truth, std::size_t row, const eyetrack::PupilResult& p,
                   bool certain) {
        eyetrack::DetectionRecord r;
        r.visible = truth.number(row, "visibility") >= eyetrack::kVisibleShare;
        r.answered = p.confidence > 0.0;
        r.errorPx = r.visible ? std::hypot(p.centre().x - truth.number(row, "cx"),
                                           p.centre().y - truth.number(row, "cy"))
                              : 0.0;
        r.confidence = p.confidence;
        mRecords.push_back(r);
        if (certain) mCertainRecords.push_back(r);
    }

    const TrackTruth& mTruth;
    std::vector<eyetrack::DetectionRecord> mRecords, mCertainRecords;
    int mVisible = 0, mWithin5 = 0, mCertainVisible = 0, mCertainWithin5 = 0;
    cv::Point2d mLastTarget{-1e30, -1e30};
    double mTargetOnsetMs = 0.0;
    std::vector<double> mGazeErrors, mErrors;
};

void writePupilRow(std::ostream& s, const eyetrack::Frame& frame, const eyetrack::PupilResult& p) {
    s << frame.sequence << ',' << cv::format("%.3f", frame.tMs) << ',';
    if (p.found)
        s << cv::format("%.3f,%.3f,%.3f,%.3f,%.2f,%.3f", p.centre().x, p.centre().y, p.semiMajor(),
                        p.semiMinor(), p.majorAngleDeg(), p.confidence);
    else
        s << cv::format(",,,,,%.3f", p.confidence);
    s << '\n';
}

// Latency: frame timestamp to gaze out on live cameras (same monotonic clock); from the moment
// the source handed the frame over for recordings.
double latencyMs(const eyetrack::FrameSource& source, const eyetrack::Frame& frame,
                 std::chrono::steady_clock::time_point done) {
    if (source.liveClock())
        return std::chrono::duration<double, std::milli>(done.time_since_epoch()).count() -
               frame.tMs;
    return std::chrono::duration<double, std::milli>(done - frame.arrival).count();
}

} // namespace

nlohmann::json runTrack(const TrackOptions& o) {
    if (!o.sourceLeft.empty() || !o.sourceRight.empty() || !o.regions.empty()) {
        if (o.cold) throw ArgumentError("--cold scores one eye's detector (--source alone)");
        return runTrackBinocular(o);
    }
    if (!o.truthRight.empty()) throw ArgumentError("--truth-right is for two eyes");
    cv::setNumThreads(1); // the detector's budget is one core
    if (!o.out.empty() && o.calibration.empty())
        throw ArgumentError(
            "--out writes screen gaze and needs --calibration (see gazetrace calibrate)");
    if (!o.emit.empty() && o.calibration.empty())
        throw ArgumentError(
            "--emit sends screen gaze and needs --calibration (see gazetrace calibrate)");
    std::optional<eyetrack::ContactSheet> sheet;
    if (!o.contactSheet.empty()) {
        if (std::filesystem::path(o.contactSheet).extension() != ".png")
            throw ArgumentError("--contact-sheet " + o.contactSheet + ": must end in .png");
        sheet.emplace(o.contactSheet, o.sheetEvery);
    }
    if (o.model != "2d" && o.model != "3d")
        throw ArgumentError("--model " + o.model + ": expected 2d or 3d");
    if (o.model == "3d" && o.calibration.empty())
        throw ArgumentError("--model 3d maps to the screen and needs --calibration");
    std::unique_ptr<eyetrack::GazeMapper> mapper;
    if (!o.calibration.empty()) mapper = openGazeMapper(o);
    const TrackTruth truth = loadTrackTruth(o);
    TrackScore score(truth);
    std::unique_ptr<eyetrack::UdpEmitter> emitter;
    if (!o.emit.empty()) {
        emitter =
            std::make_unique<eyetrack::UdpEmitter>(parseUdpEndpoint(o.emit), mapper->display());
    }

    std::unique_ptr<eyetrack::AtomicFile> gazeCsv, pupilCsv;
    if (!o.out.empty()) {
        gazeCsv = std::make_unique<eyetrack::AtomicFile>(o.out);
        gazeCsv->stream() << "t_ms,x,y\n";
    }
    if (!o.pupils.empty()) {
        pupilCsv = std::make_unique<eyetrack::AtomicFile>(o.pupils);
        pupilCsv->stream() << "frame,t_ms,cx,cy,axis_a,axis_b,angle_deg,confidence\n";
    }

    const bool mapped = mapper != nullptr;
    eyetrack::EyePipeline pipeline(openFrameSource(o.source),
                                   eyetrack::makePupilDetector(pupilDetectorKind(o.detector)),
                                   std::move(mapper));
    eyetrack::FrameSource* source = &pipeline.source();
    eyetrack::GazeMailbox mailbox;

    int frames = 0, detected = 0, saccades = 0;
    double lastGazeT = -1e300;
    std::vector<double> latencies;
    const auto start = std::chrono::steady_clock::now();
    double busyMs = 0.0;
    while (o.maxFrames <= 0 || frames < o.maxFrames) {
        // SIGINT or SIGTERM: a camera's run ends here as at its last frame, its files written; a
        // recording's run fails and writes nothing.
        if (liveRunEnds(source->liveClock())) break;
        auto frame = pipeline.grab();
        if (!frame) break;
        const auto begin = std::chrono::steady_clock::now();
        if (o.cold) pipeline.detector().reset();
        const eyetrack::EyeStep step = pipeline.process(*frame);
        const eyetrack::PupilResult& p = step.pupil;
        ++frames;
        if (p.found) ++detected;
        if (sheet) sheet->add(frame->grey, p, frame->sequence);
        if (pupilCsv) writePupilRow(pupilCsv->stream(), *frame, p);
        if (step.sample) {
            const eyetrack::GazeSample& sample = *step.sample;
            mailbox.publish(sample);
            if (sample.saccade) ++saccades;
            if (gazeCsv && sample.tMs > lastGazeT) {
                gazeCsv->stream() << cv::format("%.3f,%.2f,%.2f\n", sample.tMs, sample.x, sample.y);
                lastGazeT = sample.tMs;
            }
            if (emitter) (void)emitter->send(sample);
        }
        const auto done = std::chrono::steady_clock::now();
        busyMs += std::chrono::duration<double, std::milli>(done - begin).count();
        latencies.push_back(latencyMs(*source, *frame, done));
        score.add(*frame, step, pipeline);
    }
    if (frames == 0) throw ArgumentError("--source " + o.source + ": no frames");
    if (gazeCsv) gazeCsv->commit();
    if (pupilCsv) pupilCsv->commit();
    if (sheet) sheet->write();
    const double wallMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

    nlohmann::json j{{"source", source->describe()},
                     {"frames", frames},
                     {"detected", detected},
                     {"dropped_frames", source->droppedFrames()},
                     {"fps", frames / (busyMs / 1000.0)},
                     {"fps_with_decoding", frames / (wallMs / 1000.0)},
                     {"median_latency_ms", eyetrack::median(latencies)}};
    score.addJson(j);
    if (mapped) {
        j["saccades"] = saccades;
        j["model"] = o.model;
    }
    j["detector"] = pipeline.detector().name();
    if (o.cold) j["cold"] = true;
    if (sheet) j["contact_sheet_tiles"] = sheet->tiles();
    if (const auto last = mailbox.latest()) j["last_gaze"] = {last->x, last->y};
    return j;
}

} // namespace gt::app
