#include "output_target.hpp"

#include <span>

#include "blit/blit.hpp"
#include "readback/readback.hpp"
#include "view.hpp"

namespace gt::render {

void HostImageCopy::add(rg::RenderGraph& graph, const std::string& name, rg::TextureId image,
                        uint32_t width, uint32_t height) {
    const VkDeviceSize bytes = static_cast<VkDeviceSize>(width) * height * 4;
    if (!mHost || mHost->size() != bytes) {
        mHost.reset(); // a frame never reads another frame's copy: its target waits for it
        mHost.emplace(mCtx, vk::BufferDesc{bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           vk::MemoryUsage::Readback, "readback." + name});
    }
    const rg::BufferId host = graph.importBuffer(
        name + ".host", {mHost->handle(), mHost->size(), std::nullopt, rg::Access::HostRead});
    passes::addReadbackPass(graph, name, image, host);
}

std::vector<uint8_t> HostImageCopy::download() const {
    std::vector<uint8_t> px(mHost ? mHost->size() : 0);
    if (mHost) mHost->download(std::as_writable_bytes(std::span(px)));
    return px;
}

void ReadbackTarget::addOutput(rg::RenderGraph& graph, rg::TextureId image, const View& view) {
    mCopy.add(graph, "frame", image, view.width, view.height);
}

void ReadbackTarget::frameFinished() {
    if (mCopy.recorded()) mPixels = mCopy.download();
}

void CompositeReadbackTarget::beginFrame(rg::RenderGraph& graph) {
    struct Data {
        rg::TextureId image;
    };
    // Cleared first: a part no view covers is black, not undefined.
    const auto& data = graph.addPass<Data>(
        "composite.clear",
        [&](rg::PassBuilder& b, Data& d) {
            d.image =
                b.write(b.createTexture("composite",
                                        {VK_FORMAT_R8G8B8A8_UNORM, rg::SizeMode::Absolute,
                                         static_cast<float>(mWidth), static_cast<float>(mHeight)}),
                        rg::Access::TransferDst);
        },
        [](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            const VkClearColorValue black{};
            const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            vkCmdClearColorImage(cmd, r.texture(d.image).image,
                                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &black, 1, &range);
        });
    mImage = data.image;
}

void CompositeReadbackTarget::addOutput(rg::RenderGraph& graph, rg::TextureId image,
                                        const View& view) {
    const auto it = mPlaces.find(view.name);
    const VkRect2D rect = it != mPlaces.end() ? it->second : VkRect2D{{0, 0}, {mWidth, mHeight}};
    mImage = passes::addBlitPass(graph, "composite.blit", image, mImage, rect);
}

void CompositeReadbackTarget::endFrame(rg::RenderGraph& graph) {
    const VkDeviceSize bytes = static_cast<VkDeviceSize>(mWidth) * mHeight * 4;
    if (!mHost) {
        mHost.emplace(mCtx, vk::BufferDesc{bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           vk::MemoryUsage::Readback, "composite.host"});
    }
    const rg::BufferId host = graph.importBuffer(
        "composite.host", {mHost->handle(), bytes, std::nullopt, rg::Access::HostRead});
    passes::addReadbackPass(graph, "composite", mImage, host);
}

void CompositeReadbackTarget::frameFinished() {
    mPixels.resize(mHost->size());
    mHost->download(std::as_writable_bytes(std::span(mPixels)));
}

void DiscardTarget::addOutput(rg::RenderGraph& graph, rg::TextureId image, const View& view) {
    (void)view;
    graph.sink(image, rg::Access::StorageRead);
}

} // namespace gt::render
