#include "blit/blit.hpp"

namespace gt::passes {

rg::TextureId addBlitPass(rg::RenderGraph& graph, const std::string& name, rg::TextureId source,
                          rg::TextureId destination, VkRect2D rect) {
    struct Data {
        rg::TextureId src, dst;
    };
    const auto& data = graph.addPass<Data>(
        name,
        [&](rg::PassBuilder& b, Data& d) {
            d.src = b.read(source, rg::Access::TransferSrc);
            d.dst = b.write(destination, rg::Access::TransferDst);
        },
        [rect](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            const rg::ResolvedTexture& s = r.texture(d.src);
            const rg::ResolvedTexture& t = r.texture(d.dst);
            VkImageBlit2 region{VK_STRUCTURE_TYPE_IMAGE_BLIT_2};
            region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, s.layer, 1};
            region.srcOffsets[1] = {static_cast<int32_t>(s.width), static_cast<int32_t>(s.height),
                                    1};
            region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, t.layer, 1};
            region.dstOffsets[0] = {rect.offset.x, rect.offset.y, 0};
            region.dstOffsets[1] = {rect.offset.x + static_cast<int32_t>(rect.extent.width),
                                    rect.offset.y + static_cast<int32_t>(rect.extent.height), 1};
            VkBlitImageInfo2 info{VK_STRUCTURE_TYPE_BLIT_IMAGE_INFO_2};
            info.srcImage = s.image;
            info.srcImageLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
            info.dstImage = t.image;
            info.dstImageLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
            info.regionCount = 1;
            info.pRegions = &region;
            info.filter = VK_FILTER_LINEAR;
            vkCmdBlitImage2(cmd, &info);
        });
    return data.dst;
}

} // namespace gt::passes
