#include "readback/readback.hpp"

namespace gt::passes {

void addReadbackPass(rg::RenderGraph& graph, const std::string& name, rg::TextureId texture,
                     rg::BufferId hostBuffer) {
    struct Data {
        rg::TextureId source;
        rg::BufferId destination;
    };
    graph.addPass<Data>(
        "readback." + name,
        [&](rg::PassBuilder& b, Data& d) {
            d.source = b.read(texture, rg::Access::TransferSrc);
            d.destination = b.write(hostBuffer, rg::Access::TransferDst);
        },
        [](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            const rg::ResolvedTexture& t = r.texture(d.source);
            VkBufferImageCopy region{};
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            region.imageExtent = {t.width, t.height, 1};
            vkCmdCopyImageToBuffer(cmd, t.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                   r.buffer(d.destination), 1, &region);
        });
}

} // namespace gt::passes
