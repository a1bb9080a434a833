#pragma once
// Frames in flight. Each slot owns what one frame needs while the GPU works on it: a command
// buffer, a fence, its own transient images and buffers, and its timestamp queries. The CPU
// records frame n + 1 while the GPU renders frame n; begin() waits only for the frame that last
// used the slot, reads its GPU times, and releases what was retired while it could still be in
// use (DeferredRelease). With one slot every frame is recorded, submitted and waited for in turn.
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include <vulkan/vulkan.h>

#include "render_graph/render_graph.hpp"

namespace gt::vk {
class Context;
class TimestampPool;
} // namespace gt::vk

namespace gt::rg {

// Semaphores a submit waits for and signals (a swapchain's acquire and present, an XR runtime's).
struct SubmitSync {
    std::vector<VkSemaphoreSubmitInfo> wait;
    std::vector<VkSemaphoreSubmitInfo> signal;
};

struct FrameSlot; // one frame's command buffer, fence, transients and timestamps

// The GPU times of a finished frame.
struct CompletedFrame {
    uint64_t number = 0;
    FrameTimings timings;
};

class FrameRing {
public:
    FrameRing(vk::Context& ctx, uint32_t framesInFlight);
    ~FrameRing(); // waits for every frame still in flight
    FrameRing(const FrameRing&) = delete;
    FrameRing& operator=(const FrameRing&) = delete;

    struct Frame {
        uint64_t number = 0;
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        TransientPool* pool = nullptr;
        RecordedFrame recorded; // set by the caller after RenderGraph::record
        // A timestamp pool of at least `queries` queries for this frame (grown when needed).
        vk::TimestampPool& timestamps(uint32_t queries);

    private:
        friend class FrameRing;
        struct FrameSlot* mSlot = nullptr;
    };

    // Starts the next frame in its slot: waits for the slot's previous frame, collects its GPU
    // times and begins the command buffer. A frame begun and never submitted (recording
    // failed) is simply begun again by the next call.
    Frame& begin();
    // Ends and submits the frame begun last. Throws (and nothing is in flight) when it fails.
    void submit(const SubmitSync& sync = {});
    // Waits for every submitted frame and collects their times.
    void waitIdle();

    [[nodiscard]] uint32_t framesInFlight() const noexcept;
    // The number of the frame begun last (frames count from 1; 0 before the first).
    [[nodiscard]] uint64_t frameNumber() const noexcept { return mFrame; }
    // Every frame up to this number has finished on the GPU.
    [[nodiscard]] uint64_t completedFrame() const noexcept { return mCompleted; }
    [[nodiscard]] DeferredRelease& deferredRelease() noexcept { return mRelease; }
    // Device memory of the transient images every slot holds (of `extent` only, where given).
    [[nodiscard]] VkDeviceSize
    transientImageBytes(std::optional<VkExtent2D> extent = {}) const noexcept;
    // GPU times of the frames finished since the last call, oldest first.
    [[nodiscard]] std::vector<CompletedFrame> takeCompleted();

private:
    void finish(FrameSlot& slot);

    vk::Context& mCtx;
    std::vector<std::unique_ptr<FrameSlot>> mSlots;
    uint64_t mFrame = 0;
    uint64_t mCompleted = 0;
    bool mRecording = false;
    DeferredRelease mRelease;
    std::deque<CompletedFrame> mDone;
};

} // namespace gt::rg
