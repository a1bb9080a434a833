#pragma once
// The latest-gaze mailbox: the tracker thread publishes, the renderer reads the newest sample
// each frame without waiting (older samples are simply overwritten).
#include <cstdint>
#include <mutex>
#include <optional>

#include "gaze/gaze_sample.hpp"

namespace gt::eyetrack {

class GazeMailbox {
public:
    void publish(const GazeSample& s) {
        const std::lock_guard lock(mMutex);
        mSample = s;
        ++mVersion;
    }
    [[nodiscard]] std::optional<GazeSample> latest() const {
        const std::lock_guard lock(mMutex);
        return mSample;
    }
    // Increases with every publish: a reader can tell whether anything new arrived.
    [[nodiscard]] std::uint64_t version() const {
        const std::lock_guard lock(mMutex);
        return mVersion;
    }

private:
    mutable std::mutex mMutex;
    std::optional<GazeSample> mSample;
    std::uint64_t mVersion = 0;
};

} // namespace gt::eyetrack
