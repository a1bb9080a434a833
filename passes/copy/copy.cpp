#include "copy/copy.hpp"

#include <algorithm>

namespace gt::passes {

rg::TextureId addCopyPass(rg::RenderGraph& graph, const std::string& name, rg::TextureId source,
                          VkFormat format, uint32_t width, uint32_t height) {
    struct Data {
        rg::TextureId src, dst;
    };
    const auto& data = graph.addPass<Data>(
        name,
        [&](rg::PassBuilder& b, Data& d) {
            d.src = b.read(source, rg::Access::TransferSrc);
            d.dst = b.write(b.createTexture(name + ".image", {format, rg::SizeMode::Absolute,
                                                              static_cast<float>(width),
                                                              static_cast<float>(height)}),
                            rg::Access::TransferDst);
        },
        [](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            const rg::ResolvedTexture& s = r.texture(d.src);
            const rg::ResolvedTexture& t = r.texture(d.dst);
            VkImageCopy2 region{VK_STRUCTURE_TYPE_IMAGE_COPY_2};
            region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, s.layer, 1};
            region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, t.layer, 1};
            region.extent = {std::min(s.width, t.width), std::min(s.height, t.height), 1};
            VkCopyImageInfo2 info{VK_STRUCTURE_TYPE_COPY_IMAGE_INFO_2};
            info.srcImage = s.image;
            info.srcImageLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
            info.dstImage = t.image;
            info.dstImageLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
            info.regionCount = 1;
            info.pRegions = &region;
            vkCmdCopyImage2(cmd, &info);
        });
    return data.dst;
}

} // namespace gt::passes
