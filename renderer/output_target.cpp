#include "output_target.hpp"

#include <span>

#include "readback/readback.hpp"
#include "view.hpp"

namespace gt::render {

void ReadbackTarget::addOutput(rg::RenderGraph& graph, rg::TextureId image, const View& view) {
    const VkDeviceSize bytes = static_cast<VkDeviceSize>(view.width) * view.height * 4;
    if (!mHost || mHost->size() != bytes) {
        mHost.reset(); // a frame never reads another frame's readback: waitsForFrame()
        mHost.emplace(mCtx, vk::BufferDesc{bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           vk::MemoryUsage::Readback, "readback.frame"});
    }
    const rg::BufferId host = graph.importBuffer(
        "frame.host", {mHost->handle(), mHost->size(), std::nullopt, rg::Access::HostRead});
    passes::addReadbackPass(graph, "frame", image, host);
}

void ReadbackTarget::frameFinished() {
    if (!mHost) {
        return;
    }
    mPixels.resize(mHost->size());
    mHost->download(std::as_writable_bytes(std::span(mPixels)));
}

void DiscardTarget::addOutput(rg::RenderGraph& graph, rg::TextureId image, const View& view) {
    (void)view;
    graph.sink(image, rg::Access::StorageRead);
}

} // namespace gt::render
