#pragma once
// A render-graph pass that clears a new texture to one colour: an input of known value for a
// pass under test.
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

} // namespace gt::test
