#include "overlay/overlay.hpp"

#include "core/error.hpp"
#include "vk/context.hpp"

namespace gt::passes {

OverlayPass::OverlayPass(vk::Context& ctx, VkFormat format) : mCtx(ctx), mFormat(format) {
    VkAttachmentDescription a{};
    a.format = format;
    a.samples = VK_SAMPLE_COUNT_1_BIT;
    a.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    a.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    a.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &ref;
    VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    info.attachmentCount = 1;
    info.pAttachments = &a;
    info.subpassCount = 1;
    info.pSubpasses = &sub;
    GT_VK_CHECK(vkCreateRenderPass(ctx.device(), &info, nullptr, &mRenderPass));
}

OverlayPass::~OverlayPass() {
    releaseFramebuffers();
    vkDestroyRenderPass(mCtx.device(), mRenderPass, nullptr);
}

void OverlayPass::releaseFramebuffers() noexcept {
    for (auto& [view, fb] : mFramebuffers) {
        vkDestroyFramebuffer(mCtx.device(), fb.handle, nullptr);
    }
    mFramebuffers.clear();
}

VkFramebuffer OverlayPass::framebuffer(VkImageView view, uint32_t width, uint32_t height) {
    const auto it = mFramebuffers.find(view);
    if (it != mFramebuffers.end() && it->second.width == width && it->second.height == height) {
        return it->second.handle;
    }
    if (it != mFramebuffers.end()) {
        throw Error("overlay: an image view changed size without releaseFramebuffers()");
    }
    VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    info.renderPass = mRenderPass;
    info.attachmentCount = 1;
    info.pAttachments = &view;
    info.width = width;
    info.height = height;
    info.layers = 1;
    VkFramebuffer fb = VK_NULL_HANDLE;
    GT_VK_CHECK(vkCreateFramebuffer(mCtx.device(), &info, nullptr, &fb));
    mFramebuffers[view] = {fb, width, height};
    return fb;
}

rg::TextureId OverlayPass::add(rg::RenderGraph& graph, rg::TextureId image, Draw draw) {
    struct Data {
        rg::TextureId target;
    };
    const auto& data = graph.addPass<Data>(
        "overlay",
        [&](rg::PassBuilder& b, Data& d) {
            d.target = b.write(image, rg::Access::ColorAttachment, mFormat);
        },
        [this, draw = std::move(draw)](const rg::PassResources& r, const Data& d,
                                       VkCommandBuffer cmd) {
            const rg::ResolvedTexture& t = r.texture(d.target);
            VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
            begin.renderPass = mRenderPass;
            begin.framebuffer = framebuffer(t.view, t.width, t.height);
            begin.renderArea = {{0, 0}, {t.width, t.height}};
            vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
            draw(cmd);
            vkCmdEndRenderPass(cmd);
        });
    return data.target;
}

} // namespace gt::passes
