#pragma once
// Dear ImGui on a window's swapchain (Debian's libimgui-dev with the GLFW and Vulkan backends
// that package ships as sources): the library's context, its backends and their descriptor pool
// for one window, and the pass that draws a frame's UI over the swapchain image inside the
// frame's render graph. The demo's overlay and the study's prompts draw through it.
#include <cstdint>

#include <vulkan/vulkan.h>

#include "render_graph/render_graph.hpp"
#include "ui_overlay.hpp"

namespace gt::vk {
class Context;
}

namespace gt::app {

class Window;

class ImGuiLayer {
public:
    ImGuiLayer(Window& window, vk::Context& ctx, VkFormat format, uint32_t imageCount);
    ~ImGuiLayer();
    ImGuiLayer(const ImGuiLayer&) = delete;
    ImGuiLayer& operator=(const ImGuiLayer&) = delete;

    // The backends' part of a new frame; ImGui::NewFrame() follows (after any font scale).
    void newFrame();
    // Adds the pass that draws the last ImGui::Render()'s data over `image`; returns its new
    // version.
    rg::TextureId add(rg::RenderGraph& graph, rg::TextureId image);
    void swapchainRecreated(uint32_t imageCount);

private:
    vk::Context& mCtx;
    render::UiOverlay mPass;
    VkDescriptorPool mPool = VK_NULL_HANDLE;
};

} // namespace gt::app
