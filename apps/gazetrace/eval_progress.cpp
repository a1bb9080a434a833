#include "eval_progress.hpp"

#include <algorithm>

#include "core/log.hpp"

namespace gt::app {

uint32_t evalFrameCount(const EvalOptions& o, bool referenceGiven, std::size_t pursuitSamples) {
    const uint32_t settled = std::max(1u, o.frames); // the foveated frame and its TAA history
    const uint32_t sequence = std::max(2u, o.sequenceFrames);
    const uint32_t baselines = o.baseline == "uniform" ? 2 : 0; // low resolution, full
    uint32_t n = referenceGiven ? 0 : 1;
    n += settled + baselines;
    if (o.temporal) n += settled - 1 + sequence;
    if (!o.cameraPath.empty()) n += 2 * sequence; // foveated and reference
    if (!o.pursuit.empty()) {
        n += settled - 1 + static_cast<uint32_t>(std::min<std::size_t>(pursuitSamples, sequence));
    }
    if (o.sweep) n += 4 * (settled + 2);    // four scales, each with its uniform baselines
    if (!o.match.empty()) n += 8 * settled; // at most 8 candidates, each settled
    return n;
}

std::string EvalProgress::frame(const std::string& stage) {
    ++mDone;
    const std::string line = "eval: frame " + std::to_string(mDone) + "/" +
                             std::to_string(std::max(mDone, mFrames)) + " (" + stage + ")";
    log::info(line);
    return line;
}

std::string EvalProgress::step(const std::string& what) {
    const std::string line = "eval: " + what;
    log::info(line);
    return line;
}

} // namespace gt::app
