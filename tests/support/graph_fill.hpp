#pragma once
// Render-graph passes that give a pass under test an input of known value: a new texture cleared
// to one colour, or filled from a buffer of texels.
#include <string>

#include <glm/glm.hpp>

#include "render_graph/render_graph.hpp"

namespace gt::test {

inline rg::TextureId addFilledTexture(rg::RenderGraph& g, const char* name,
                                      const rg::TextureDesc& desc, glm::vec4 c) {
    struct Data {
        rg::TextureId t;
    };
    return g
        .addPass<Data>(
            name,
            [&](rg::PassBuilder& b, Data& d) {
                d.t = b.write(b.createTexture(name, desc), rg::Access::TransferDst);
            },
            [c](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
                const VkClearColorValue v{{c.r, c.g, c.b, c.a}};
                const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
                vkCmdClearColorImage(cmd, r.texture(d.t).image,
                                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &v, 1, &range);
            })
        .t;
}

// A new texture of the graph's size copied from `src` (tightly packed texels in `format`).
inline rg::TextureId addUploadedTexture(rg::RenderGraph& g, const std::string& name,
                                        rg::BufferId src, VkFormat format) {
    struct Data {
        rg::BufferId src;
        rg::TextureId image;
    };
    return g
        .addPass<Data>(
            name,
            [&](rg::PassBuilder& b, Data& d) {
                d.src = b.read(src, rg::Access::TransferSrc);
                d.image = b.write(b.createTexture(name, {format}), rg::Access::TransferDst);
            },
            [](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
                const rg::ResolvedTexture& t = r.texture(d.image);
                VkBufferImageCopy region{};
                region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                region.imageExtent = {t.width, t.height, 1};
                vkCmdCopyBufferToImage(cmd, r.buffer(d.src), t.image,
                                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
            })
        .image;
}

} // namespace gt::test
