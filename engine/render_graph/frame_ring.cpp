#include "render_graph/frame_ring.hpp"

#include "core/error.hpp"
#include "vk/context.hpp"
#include "vk/query_pool.hpp"

namespace gt::rg {

struct FrameSlot {
    vk::Context* ctx = nullptr;
    VkCommandPool pool = VK_NULL_HANDLE;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    std::unique_ptr<TransientPool> transients;
    std::unique_ptr<vk::TimestampPool> timestamps;
    bool inFlight = false; // submitted and not yet waited for
    FrameRing::Frame frame;

    explicit FrameSlot(vk::Context& c) : ctx(&c), transients(std::make_unique<TransientPool>(c)) {
        VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pi.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
        pi.queueFamilyIndex = c.queueFamily();
        GT_VK_CHECK(vkCreateCommandPool(c.device(), &pi, nullptr, &pool));
        VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        ai.commandPool = pool;
        ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        ai.commandBufferCount = 1;
        VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        try {
            GT_VK_CHECK(vkAllocateCommandBuffers(c.device(), &ai, &cmd));
            GT_VK_CHECK(vkCreateFence(c.device(), &fi, nullptr, &fence));
        } catch (...) {
            vkDestroyCommandPool(c.device(), pool, nullptr);
            throw;
        }
    }
    ~FrameSlot() {
        vkDestroyFence(ctx->device(), fence, nullptr);
        vkDestroyCommandPool(ctx->device(), pool, nullptr); // frees the command buffer
    }
    FrameSlot(const FrameSlot&) = delete;
    FrameSlot& operator=(const FrameSlot&) = delete;
};

vk::TimestampPool& FrameRing::Frame::timestamps(uint32_t queries) {
    FrameSlot& s = *mSlot;
    if (!s.timestamps || s.timestamps->capacity() < queries) {
        // This slot's earlier frame has finished (begin() waited), so the old pool is free.
        s.timestamps = std::make_unique<vk::TimestampPool>(*s.ctx, std::max(queries, 64u));
    }
    return *s.timestamps;
}

FrameRing::FrameRing(vk::Context& ctx, uint32_t framesInFlight) : mCtx(ctx) {
    if (framesInFlight == 0 || framesInFlight > 8) {
        throw Error("frames in flight must be 1..8, got " + std::to_string(framesInFlight));
    }
    for (uint32_t i = 0; i < framesInFlight; ++i) {
        mSlots.push_back(std::make_unique<FrameSlot>(ctx));
        mSlots.back()->frame.mSlot = mSlots.back().get();
        mSlots.back()->frame.pool = mSlots.back()->transients.get();
    }
}

FrameRing::~FrameRing() {
    for (auto& s : mSlots) {
        if (s->inFlight) {
            // Best effort: a lost device must not turn a destructor into a throw.
            (void)vkWaitForFences(mCtx.device(), 1, &s->fence, VK_TRUE, UINT64_MAX);
        }
    }
    mRelease.clear();
}

uint32_t FrameRing::framesInFlight() const noexcept {
    return static_cast<uint32_t>(mSlots.size());
}

VkDeviceSize FrameRing::transientImageBytes(std::optional<VkExtent2D> extent) const noexcept {
    VkDeviceSize sum = 0;
    for (const std::unique_ptr<FrameSlot>& s : mSlots) {
        sum += s->transients->imageBytes(extent);
    }
    return sum;
}

void FrameRing::finish(FrameSlot& s) {
    if (!s.inFlight) return;
    GT_VK_CHECK(vkWaitForFences(mCtx.device(), 1, &s.fence, VK_TRUE, UINT64_MAX));
    s.inFlight = false;
    mDone.push_back({s.frame.number, s.frame.recorded.timings()});
    // Slots are used in turn, so every frame before this one has been waited for already.
    mCompleted = std::max(mCompleted, s.frame.number);
    mRelease.collect(mCompleted);
}

FrameRing::Frame& FrameRing::begin() {
    if (mRecording) {
        // The last frame was begun but never submitted: record it again from the start.
        --mFrame;
    }
    ++mFrame;
    FrameSlot& s = *mSlots[mFrame % mSlots.size()];
    finish(s);
    GT_VK_CHECK(vkResetCommandPool(mCtx.device(), s.pool, 0));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    GT_VK_CHECK(vkBeginCommandBuffer(s.cmd, &bi));
    mRecording = true;
    s.frame.number = mFrame;
    s.frame.cmd = s.cmd;
    s.frame.recorded = {};
    return s.frame;
}

void FrameRing::submit(const SubmitSync& sync) {
    if (!mRecording) throw Error("FrameRing::submit without a frame begun");
    FrameSlot& s = *mSlots[mFrame % mSlots.size()];
    mRecording = false;
    GT_VK_CHECK(vkEndCommandBuffer(s.cmd));
    VkCommandBufferSubmitInfo cb{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cb.commandBuffer = s.cmd;
    VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    si.waitSemaphoreInfoCount = static_cast<uint32_t>(sync.wait.size());
    si.pWaitSemaphoreInfos = sync.wait.data();
    si.commandBufferInfoCount = 1;
    si.pCommandBufferInfos = &cb;
    si.signalSemaphoreInfoCount = static_cast<uint32_t>(sync.signal.size());
    si.pSignalSemaphoreInfos = sync.signal.data();
    GT_VK_CHECK(vkResetFences(mCtx.device(), 1, &s.fence));
    const VkResult r = vkQueueSubmit2(mCtx.queue(), 1, &si, s.fence);
    if (r != VK_SUCCESS) {
        // Nothing was queued: leave the fence signalled so the slot can be begun again.
        VkSubmitInfo2 empty{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
        (void)vkQueueSubmit2(mCtx.queue(), 1, &empty, s.fence);
        GT_VK_CHECK(r);
    }
    s.inFlight = true;
}

void FrameRing::waitIdle() {
    // Oldest first, so that completedFrame() rises in order.
    for (std::size_t i = 1; i <= mSlots.size(); ++i) {
        finish(*mSlots[(mFrame + i) % mSlots.size()]);
    }
}

std::vector<CompletedFrame> FrameRing::takeCompleted() {
    std::vector<CompletedFrame> out(mDone.begin(), mDone.end());
    mDone.clear();
    return out;
}

} // namespace gt::rg
