#include "gaze_input.hpp"

#include <cmath>
#include <cstdio>

#include "capture/frame_source.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "error.hpp"
#include "eye_source_parsing.hpp"
#include "foveation/gaze_trace.hpp"
#include "gaze/calibration.hpp"
#include "gaze/gaze_tracker.hpp"
#include "net/udp_receiver.hpp"

namespace gt::app {

namespace {

class FixedGaze final : public GazeInput {
public:
    explicit FixedGaze(glm::vec2 p) : mPoint(p) {}
    std::optional<GazeReading> read(double) override {
        GazeReading r;
        r.screenPx = mPoint;
        r.sampled = SteadyClock::now();
        r.sequence = 1;
        return r;
    }
    std::string describe() const override { return "fixed"; }

private:
    glm::vec2 mPoint;
};

class MouseGaze final : public GazeInput {
public:
    explicit MouseGaze(std::function<glm::vec2()> cursor) : mCursor(std::move(cursor)) {}
    std::optional<GazeReading> read(double) override {
        GazeReading r;
        r.screenPx = mCursor();
        r.sampled = SteadyClock::now();
        r.sequence = ++mSequence;
        return r;
    }
    std::string describe() const override { return "mouse"; }

private:
    std::function<glm::vec2()> mCursor;
    uint64_t mSequence = 0;
};

class TraceGaze final : public GazeInput {
public:
    TraceGaze(foveation::GazeTrace trace, std::string file)
        : mTrace(std::move(trace)), mFile(std::move(file)) {}
    std::optional<GazeReading> read(double frameMs) override {
        const double t = mTrace.startMs() + frameMs;
        GazeReading r;
        r.sampled = SteadyClock::now();
        r.sequence = ++mSequence;
        r.sourceMs = t;
        if (mTrace.units() == foveation::GazeUnits::AnglesDeg) {
            r.anglesDeg = mTrace.at(t);
            if (mTrace.hasEye(foveation::GazeEye::Left)) {
                r.eyeAnglesDeg[0] = mTrace.at(t, foveation::GazeEye::Left);
            }
            if (mTrace.hasEye(foveation::GazeEye::Right)) {
                r.eyeAnglesDeg[1] = mTrace.at(t, foveation::GazeEye::Right);
            }
        } else {
            r.screenPx = mTrace.at(t);
        }
        return r;
    }
    std::string describe() const override { return "trace:" + mFile; }

private:
    foveation::GazeTrace mTrace;
    std::string mFile;
    uint64_t mSequence = 0;
};

class TrackerGaze final : public GazeInput {
public:
    TrackerGaze(const std::string& source, const std::string& calibrationFile, glm::uvec2 screen)
        : mSpec(source), mScreen(screen) {
        if (calibrationFile.empty()) {
            throw ArgumentError("--gaze track:" + source +
                                " needs --calibration (see gazetrace calibrate)");
        }
        eyetrack::Calibration calibration = eyetrack::Calibration::load(calibrationFile);
        mTracker.emplace(openFrameSource(source), std::move(calibration));
        (void)mTracker->waitForFirstSample(2000.0); // a camera may take a moment to stream
    }
    std::optional<GazeReading> read(double) override {
        if (const auto e = mTracker->error()) {
            throw Error("--gaze track:" + mSpec + ": " + *e);
        }
        const auto g = mTracker->mailbox().latest();
        if (!g) {
            return std::nullopt;
        }
        // The calibration's screen is the one the targets were shown on; scale to ours.
        const eyetrack::DisplayGeometry& d = mTracker->display();
        const glm::vec2 scale(static_cast<float>(mScreen.x) / static_cast<float>(d.widthPx),
                              static_cast<float>(mScreen.y) / static_cast<float>(d.heightPx));
        const uint64_t saccades = mTracker->saccades();
        const bool saccade = saccades != mSaccadesSeen;
        mSaccadesSeen = saccades;
        GazeReading r;
        r.screenPx = glm::vec2(g->x, g->y) * scale;
        r.windowPixels = false;
        r.sampled = SteadyClock::now();
        r.saccade = saccade;
        r.sequence = mTracker->frames();
        r.sourceMs = g->tMs;
        r.confidence = g->confidence;
        const cv::Point2d a = d.anglesDeg({g->x, g->y}); // its calibration fits angles
        r.anglesDeg = glm::vec2(static_cast<float>(a.x), static_cast<float>(a.y));
        return r;
    }
    std::string describe() const override { return "track:" + mSpec; }

private:
    std::string mSpec;
    glm::uvec2 mScreen;
    std::optional<eyetrack::GazeTracker> mTracker;
    uint64_t mSaccadesSeen = 0;
};

// Datagrams of `gazetrace track --emit` (eyetrack/net/gaze_datagram.hpp reads them). The
// newest one wins; a refused one is dropped and counted with a warning, and the session goes on.
class UdpGaze final : public GazeInput {
public:
    UdpGaze(const std::string& host, int port) : mWhere(host + ":" + std::to_string(port)) {
        try {
            mReceiver.emplace(eyetrack::UdpEndpoint{host, static_cast<uint16_t>(port)},
                              "gaze udp:" + mWhere,
                              [](const std::string& line) { log::warn(line); });
        } catch (const eyetrack::EyetrackError& e) {
            throw ArgumentError(std::string("--") + e.what()); // "--gaze udp:...: why"
        }
    }

    std::optional<GazeReading> read(double) override {
        while (const std::optional<eyetrack::GazeDatagram> d = mReceiver->next()) {
            fold(*d);
        }
        std::optional<GazeReading> out = mLast;
        if (mLast) {
            mLast->saccade = false; // reported once
        }
        return out;
    }
    std::string describe() const override { return "udp:" + mWhere; }

private:
    // A datagram updates what it gives: a per-eye one that eye's angles (and the screen point
    // it sent), a "both" one the viewer's gaze; the rest stays as the last datagrams left it.
    void fold(const eyetrack::GazeDatagram& d) {
        GazeReading r = mLast.value_or(GazeReading{});
        r.sampled = SteadyClock::now();
        r.sequence = ++mSequence;
        r.sourceMs = d.tMs;
        r.confidence = static_cast<float>(d.confidence);
        r.windowPixels = false;
        if (d.screenPx) r.screenPx = glm::vec2(glm::dvec2(d.screenPx->x, d.screenPx->y));
        if (d.anglesDeg) {
            const glm::vec2 a(glm::dvec2(d.anglesDeg->x, d.anglesDeg->y));
            switch (d.eye) {
            case eyetrack::DatagramEye::Left:
                r.eyeAnglesDeg[0] = a;
                break;
            case eyetrack::DatagramEye::Right:
                r.eyeAnglesDeg[1] = a;
                break;
            case eyetrack::DatagramEye::Both:
                r.anglesDeg = a;
                break;
            }
        }
        r.saccade = (mLast && mLast->saccade) || d.saccadeOnset;
        mLast = r;
    }

    std::string mWhere;
    std::optional<eyetrack::UdpGazeReceiver> mReceiver;
    std::optional<GazeReading> mLast;
    uint64_t mSequence = 0;
};

} // namespace

std::unique_ptr<GazeInput> openGazeInput(const std::string& spec, const GazeInputContext& c) {
    const auto colon = spec.find(':');
    const std::string kind = spec.substr(0, colon);
    const std::string rest = colon == std::string::npos ? "" : spec.substr(colon + 1);
    if (kind == "mouse" && rest.empty()) {
        if (!c.cursor) throw ArgumentError("--gaze mouse needs a window");
        return std::make_unique<MouseGaze>(c.cursor);
    }
    if (kind == "fixed") {
        float x = 0, y = 0;
        char extra = 0;
        if (std::sscanf(rest.c_str(), "%f,%f%c", &x, &y, &extra) != 2 || !std::isfinite(x) ||
            !std::isfinite(y)) {
            throw ArgumentError("--gaze fixed:X,Y: expected two numbers, got '" + rest + "'");
        }
        return std::make_unique<FixedGaze>(glm::vec2(x, y));
    }
    if (kind == "trace" && !rest.empty()) {
        return std::make_unique<TraceGaze>(foveation::GazeTrace::load(rest), rest);
    }
    if (kind == "track" && !rest.empty()) {
        return std::make_unique<TrackerGaze>(rest, c.calibration, c.screenPx);
    }
    if (kind == "udp" && !rest.empty()) {
        std::string host = "127.0.0.1", port = rest;
        if (const auto p = rest.rfind(':'); p != std::string::npos) {
            host = rest.substr(0, p);
            port = rest.substr(p + 1);
        }
        if (host == "localhost") host = "127.0.0.1";
        char* end = nullptr;
        const long n = std::strtol(port.c_str(), &end, 10);
        if (port.empty() || *end != '\0' || n <= 0 || n > 65535) {
            throw ArgumentError("--gaze udp:" + rest + ": the port must be 1-65535");
        }
        return std::make_unique<UdpGaze>(host, static_cast<int>(n));
    }
    throw ArgumentError("--gaze: unknown source '" + spec +
                        "' (known: mouse, fixed:X,Y, trace:FILE.csv, track:SOURCE, udp:PORT)");
}

} // namespace gt::app
