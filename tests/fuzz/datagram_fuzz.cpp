// Fuzz target: the gaze datagram reader (net/gaze_datagram.hpp), which reads bytes anyone on the
// network can send to `--gaze udp:PORT`. Contract: it returns either a datagram or a one-line
// reason, never both and never neither, and throws nothing (std::bad_alloc aside, which these
// sizes never reach); a datagram it returns holds finite values inside the documented ranges
// and says where the gaze is.
#include <cmath>
#include <string>
#include <string_view>

#include "fuzz_input.hpp"

#include "net/gaze_datagram.hpp"

namespace {

bool within(double v, double limit) {
    return std::isfinite(v) && std::abs(v) <= limit;
}

void check(const gt::eyetrack::GazeDatagram& d) {
    using gt::fuzz::finding;
    using namespace gt::eyetrack;
    if (!d.anglesDeg && !d.screenPx) finding("a datagram without a gaze position was read");
    if (d.anglesDeg &&
        !(within(d.anglesDeg->x, kMaxGazeAngleDeg) && within(d.anglesDeg->y, kMaxGazeAngleDeg) &&
          std::abs(d.anglesDeg->x) < kMaxGazeAngleDeg &&
          std::abs(d.anglesDeg->y) < kMaxGazeAngleDeg)) {
        finding("gaze angles outside (-90, 90) degrees were read");
    }
    if (d.screenPx &&
        !(within(d.screenPx->x, kMaxGazeScreenPx) && within(d.screenPx->y, kMaxGazeScreenPx))) {
        finding("a gaze pixel beyond the limit was read");
    }
    if (!within(d.tMs, kMaxGazeTimeMs)) finding("a time stamp beyond the limit was read");
    if (!(d.confidence >= 0.0 && d.confidence <= 1.0)) finding("a confidence outside [0, 1]");
    if (d.screen &&
        (d.screen->width < 1 || d.screen->height < 1 || d.screen->width > kMaxGazeScreenSidePx ||
         d.screen->height > kMaxGazeScreenSidePx)) {
        finding("a screen size outside the limit was read");
    }
    if (d.vergenceDeg && !(*d.vergenceDeg >= 0.0 && *d.vergenceDeg <= 180.0)) {
        finding("a vergence outside [0, 180] degrees was read");
    }
    if (d.fixationCm && !(std::isfinite(*d.fixationCm) && *d.fixationCm > 0.0)) {
        finding("a fixation distance that is not positive and finite was read");
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using gt::fuzz::finding;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    try {
        const gt::eyetrack::DatagramReading r = gt::eyetrack::parseGazeDatagram(bytes);
        if (r.datagram.has_value() == !r.refusal.empty()) {
            finding("the reader gave both a datagram and a reason, or neither");
        }
        if (r.datagram) {
            check(*r.datagram);
        } else if (r.refusal.find('\n') != std::string::npos || r.refusal.size() > 300) {
            finding("the reason is not one short line: " + r.refusal);
        }
    } catch (const std::exception& e) {
        finding(std::string("the reader threw: ") + e.what());
    }
    return 0;
}
