#include "swapchain_target.hpp"

#include <span>

#include "blit/blit.hpp"
#include "core/error.hpp"
#include "view.hpp"

namespace gt::render {

namespace {
// Stages the frame waits in for the acquire: the first use of the image is a blit.
constexpr VkPipelineStageFlags2 kAcquireStage = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
} // namespace

void SwapchainTarget::setImage(const vk::Swapchain::Image& image, VkFormat format,
                               VkExtent2D extent) {
    mImage = image;
    mFormat = format;
    mExtent = extent;
}

void SwapchainTarget::place(const std::string& view, VkRect2D rect) {
    mPlaces[view] = rect;
}

void SwapchainTarget::beginFrame(rg::RenderGraph& graph) {
    if (!mImage) {
        throw Error("window target: no swapchain image acquired for this frame");
    }
    rg::ImportedTexture t;
    t.image = mImage->image;
    t.view = mImage->view;
    t.format = mFormat;
    t.width = mExtent.width;
    t.height = mExtent.height;
    t.acquireStage = kAcquireStage; // contents undefined: every view's blit overwrites its part
    mTarget = graph.importTexture("swapchain", t);
}

void SwapchainTarget::addOutput(rg::RenderGraph& graph, rg::TextureId image, const View& view) {
    const auto it = mPlaces.find(view.name);
    const VkRect2D dst = it != mPlaces.end() ? it->second : VkRect2D{{0, 0}, mExtent};
    mTarget = passes::addBlitPass(graph, "present.blit", image, mTarget, dst);
}

void SwapchainTarget::endFrame(rg::RenderGraph& graph) {
    if (mOverlay) {
        mTarget = mOverlay(graph, mTarget);
    }
    if (mScreenshotWanted) {
        mScreenshotCopy.add(graph, "screenshot", mTarget, mExtent.width, mExtent.height);
    }
    graph.sink(mTarget, rg::Access::Present);
}

void SwapchainTarget::addSync(rg::SubmitSync& sync) {
    VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    wait.semaphore = mImage->acquired;
    wait.stageMask = kAcquireStage;
    sync.wait.push_back(wait);
    VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    signal.semaphore = mImage->rendered;
    signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    sync.signal.push_back(signal);
}

void SwapchainTarget::frameFinished() {
    if (!mScreenshotWanted || !mScreenshotCopy.recorded()) {
        return;
    }
    std::vector<uint8_t> px = mScreenshotCopy.download();
    if (mFormat == VK_FORMAT_B8G8R8A8_UNORM) {
        for (std::size_t i = 0; i + 3 < px.size(); i += 4) {
            std::swap(px[i], px[i + 2]);
        }
    }
    mScreenshot = std::move(px);
    mScreenshotWanted = false;
}

} // namespace gt::render
