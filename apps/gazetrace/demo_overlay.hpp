#pragma once
// The demo's overlay (Dear ImGui, Debian's libimgui-dev with the GLFW and Vulkan backends that
// package ships as sources): the settings as switches, what the frame cost per pass from the
// graph's timestamps, the frame rate and the latency from the gaze sample to the frame's
// completion. Drawn by pass `overlay` into the swapchain image after the views, inside the
// frame's render graph; laid out by overlayLayout (overlay_layout.hpp) to keep off the fovea.
#include <cstdint>
#include <deque>
#include <map>
#include <optional>

#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "demo_settings.hpp"
#include "imgui_layer.hpp"
#include "overlay_layout.hpp"
#include "render_graph/render_graph.hpp"
#include "ui_overlay.hpp"

namespace gt::vk {
class Context;
}

namespace gt::app {

class Window;

class DemoOverlay {
public:
    DemoOverlay(Window& window, vk::Context& ctx, VkFormat format, uint32_t imageCount);
    ~DemoOverlay();
    DemoOverlay(const DemoOverlay&) = delete;
    DemoOverlay& operator=(const DemoOverlay&) = delete;

    // Builds this frame's UI; returns true when the user changed a setting.
    // `target`: a calibration target to draw (window pixels).
    bool build(DemoSettings& settings, const DemoStats& stats,
               std::optional<glm::vec2> target = std::nullopt);
    // Records a finished frame's GPU times for the graph.
    void addTimings(const rg::FrameTimings& t);
    // Adds pass `overlay` over `image`; returns its new version.
    rg::TextureId add(rg::RenderGraph& graph, rg::TextureId image);
    void swapchainRecreated(uint32_t imageCount);
    void toggle() noexcept { mVisible = !mVisible; }
    [[nodiscard]] bool visible() const noexcept { return mVisible; }

private:
    // The settings and timings panel; returns true when the user changed a setting.
    bool panel(DemoSettings& settings, const DemoStats& stats);

    ImGuiLayer mLayer;
    bool mVisible = true;
    OverlayLayout mLayout{.corner = -1}; // kept in its corner while it clears the gaze
    std::deque<float> mGpuHistory;
    std::map<std::string, std::deque<float>> mPassHistory;
};

} // namespace gt::app
