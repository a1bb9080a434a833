#pragma once
// Render-graph passes that give a pass under test an input of known value: a new texture cleared
// to one colour, or filled from a buffer of texels; and the run that reads its output back.
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "readback/readback.hpp"
#include "render_graph/render_graph.hpp"
#include "vk/resources.hpp"

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

// Runs `g` with `out` (RGBA32F, the graph's size) read back, commits `history` if given (the
// frame's histories become the next run's), and returns the texels row by row.
inline std::vector<glm::vec4> executeAndRead(vk::Context& ctx, rg::RenderGraph& g,
                                             rg::TextureId out, rg::HistoryPool* history) {
    const std::size_t n = static_cast<std::size_t>(g.outputWidth()) * g.outputHeight();
    vk::Buffer host(ctx, {n * sizeof(glm::vec4), 0, vk::MemoryUsage::Readback, "out"});
    const auto hostId =
        g.importBuffer("out", {host.handle(), host.size(), std::nullopt, rg::Access::HostRead});
    passes::addReadbackPass(g, "out", out, hostId);
    rg::TransientPool pool(ctx);
    g.executeAndWait(g.compile(), pool);
    if (history != nullptr) history->commit(g);
    std::vector<glm::vec4> px(n);
    host.download(std::as_writable_bytes(std::span(px)));
    return px;
}

} // namespace gt::test
