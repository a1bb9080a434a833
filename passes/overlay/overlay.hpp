#pragma once
// Pass `overlay`: draws over a colour image inside a render pass whose draws someone else records
// (Dear ImGui's Vulkan backend needs a VkRenderPass). The attachment is loaded and stored and
// stays in COLOR_ATTACHMENT_OPTIMAL throughout, so the render pass makes no transitions of its
// own: the graph places every barrier around it, and what the backend records stays inside.
#include <functional>
#include <map>

#include <vulkan/vulkan.h>

#include "render_graph/render_graph.hpp"

namespace gt::vk {
class Context;
}

namespace gt::passes {

class OverlayPass {
public:
    OverlayPass(vk::Context& ctx, VkFormat format);
    ~OverlayPass();
    OverlayPass(const OverlayPass&) = delete;
    OverlayPass& operator=(const OverlayPass&) = delete;

    [[nodiscard]] VkRenderPass renderPass() const noexcept { return mRenderPass; }
    // Adds "overlay" drawing into `image` (of the format given at construction) with `draw`,
    // called inside the render pass; returns the image's new version.
    using Draw = std::function<void(VkCommandBuffer)>;
    rg::TextureId add(rg::RenderGraph& graph, rg::TextureId image, Draw draw);
    // Framebuffers are kept per image view: forget them when the views go (a new swapchain).
    void releaseFramebuffers() noexcept;

private:
    VkFramebuffer framebuffer(VkImageView view, uint32_t width, uint32_t height);

    vk::Context& mCtx;
    VkFormat mFormat;
    VkRenderPass mRenderPass = VK_NULL_HANDLE;
    struct Fb {
        VkFramebuffer handle;
        uint32_t width, height;
    };
    std::map<VkImageView, Fb> mFramebuffers;
};

} // namespace gt::passes
