#include "blit/blit.hpp"

#include <algorithm>
#include <functional>

namespace gt::passes {

namespace {

using RecordTransfer =
    std::function<void(const rg::ResolvedTexture& source, const rg::ResolvedTexture& destination,
                       VkCommandBuffer cmd)>;

// A pass that reads `source` as a transfer source and writes what `destination` gives as a
// transfer destination; `record` writes the one transfer command.
rg::TextureId addTransferPass(rg::RenderGraph& graph, const std::string& name, rg::TextureId source,
                              const std::function<rg::TextureId(rg::PassBuilder&)>& destination,
                              RecordTransfer record) {
    struct Data {
        rg::TextureId src, dst;
    };
    const auto& data = graph.addPass<Data>(
        name,
        [&](rg::PassBuilder& b, Data& d) {
            d.src = b.read(source, rg::Access::TransferSrc);
            d.dst = b.write(destination(b), rg::Access::TransferDst);
        },
        [record = std::move(record)](const rg::PassResources& r, const Data& d,
                                     VkCommandBuffer cmd) {
            record(r.texture(d.src), r.texture(d.dst), cmd);
        });
    return data.dst;
}

// The fields VkBlitImageInfo2 and VkCopyImageInfo2 share, for one region between the two.
template <typename Info, typename Region>
Info transferInfo(VkStructureType type, const rg::ResolvedTexture& s, const rg::ResolvedTexture& t,
                  const Region& region) {
    Info info{type};
    info.srcImage = s.image;
    info.srcImageLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    info.dstImage = t.image;
    info.dstImageLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    info.regionCount = 1;
    info.pRegions = &region;
    return info;
}

} // namespace

rg::TextureId addBlitPass(rg::RenderGraph& graph, const std::string& name, rg::TextureId source,
                          rg::TextureId destination, VkRect2D rect) {
    return addTransferPass(
        graph, name, source, [destination](rg::PassBuilder&) { return destination; },
        [rect](const rg::ResolvedTexture& s, const rg::ResolvedTexture& t, VkCommandBuffer cmd) {
            VkImageBlit2 region{VK_STRUCTURE_TYPE_IMAGE_BLIT_2};
            region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, s.layer, 1};
            region.srcOffsets[1] = {static_cast<int32_t>(s.width), static_cast<int32_t>(s.height),
                                    1};
            region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, t.layer, 1};
            region.dstOffsets[0] = {rect.offset.x, rect.offset.y, 0};
            region.dstOffsets[1] = {rect.offset.x + static_cast<int32_t>(rect.extent.width),
                                    rect.offset.y + static_cast<int32_t>(rect.extent.height), 1};
            auto info =
                transferInfo<VkBlitImageInfo2>(VK_STRUCTURE_TYPE_BLIT_IMAGE_INFO_2, s, t, region);
            info.filter = VK_FILTER_LINEAR;
            vkCmdBlitImage2(cmd, &info);
        });
}

rg::TextureId addCopyPass(rg::RenderGraph& graph, const std::string& name, rg::TextureId source,
                          VkFormat format, uint32_t width, uint32_t height) {
    const rg::TextureDesc desc{format, rg::SizeMode::Absolute, static_cast<float>(width),
                               static_cast<float>(height)};
    return addTransferPass(
        graph, name, source,
        [&](rg::PassBuilder& b) { return b.createTexture(name + ".image", desc); },
        [](const rg::ResolvedTexture& s, const rg::ResolvedTexture& t, VkCommandBuffer cmd) {
            VkImageCopy2 region{VK_STRUCTURE_TYPE_IMAGE_COPY_2};
            region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, s.layer, 1};
            region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, t.layer, 1};
            region.extent = {std::min(s.width, t.width), std::min(s.height, t.height), 1};
            const auto info =
                transferInfo<VkCopyImageInfo2>(VK_STRUCTURE_TYPE_COPY_IMAGE_INFO_2, s, t, region);
            vkCmdCopyImage2(cmd, &info);
        });
}

} // namespace gt::passes
