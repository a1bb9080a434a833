#pragma once
// A user interface drawn over a front end's output image inside the frame's render graph (the
// demo's Dear ImGui panel). The renderer owns the pass that draws it, so a front end reaches it
// through here, never through passes/.
#include <functional>
#include <memory>

#include <vulkan/vulkan.h>

#include "render_graph/render_graph.hpp"

namespace gt::vk {
class Context;
}
namespace gt::passes {
class OverlayPass;
}

namespace gt::render {

class UiOverlay {
public:
    UiOverlay(vk::Context& ctx, VkFormat format);
    ~UiOverlay();
    UiOverlay(const UiOverlay&) = delete;
    UiOverlay& operator=(const UiOverlay&) = delete;

    // The render pass the UI library's draws are recorded in (Dear ImGui's Vulkan backend needs
    // one); the attachment stays in COLOR_ATTACHMENT_OPTIMAL, so the graph places every barrier.
    [[nodiscard]] VkRenderPass renderPass() const noexcept;
    // Adds the drawing into `image` (of the format given at construction) with `draw`, called
    // inside the render pass; returns the image's new version.
    using Draw = std::function<void(VkCommandBuffer)>;
    rg::TextureId add(rg::RenderGraph& graph, rg::TextureId image, Draw draw);
    // Framebuffers are kept per image view: forget them when the views go (a new swapchain).
    void releaseFramebuffers() noexcept;

private:
    std::unique_ptr<passes::OverlayPass> mPass;
};

} // namespace gt::render
