#pragma once
// `gazetrace eval` renders for minutes on a CPU driver: it says on stderr what it is doing and
// how far it is, one line per frame rendered (which stage, frame i of the run's N) and one per
// measurement.
#include <cstdint>
#include <string>

#include "eval_command.hpp"

namespace gt::app {

// The frames a run with these options renders, all stages together. `referenceGiven`: --reference
// (no reference render); `pursuitSamples`: the --pursuit trace's samples (0 without one).
[[nodiscard]] uint32_t evalFrameCount(const EvalOptions& o, bool referenceGiven,
                                      std::size_t pursuitSamples);

class EvalProgress {
public:
    explicit EvalProgress(uint32_t frames) : mFrames(frames) {}
    // A frame of `stage` (the view's name) rendered; returns the line it wrote.
    std::string frame(const std::string& stage);
    // A step that renders nothing (scoring, depth maps); returns the line it wrote.
    std::string step(const std::string& what);
    [[nodiscard]] uint32_t framesDone() const noexcept { return mDone; }

private:
    uint32_t mFrames;
    uint32_t mDone = 0;
};

} // namespace gt::app
