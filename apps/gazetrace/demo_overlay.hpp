#pragma once
// The demo's overlay (Dear ImGui, Debian's libimgui-dev with the GLFW and Vulkan backends that
// package ships as sources): the settings as switches, what the frame cost per pass from the
// graph's timestamps, the frame rate and the gaze-to-photon latency. Drawn by pass `overlay`
// into the swapchain image after the views, inside the frame's render graph.
#include <cstdint>
#include <deque>
#include <map>
#include <optional>

#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "overlay/overlay.hpp"
#include "render_graph/render_graph.hpp"

namespace gt::vk {
class Context;
}

namespace gt::app {

class Window;

// What the overlay shows and may change; the demo applies the changes before the next frame.
struct DemoSettings {
    std::string method = "foveated"; // foveated | layers | reference
    std::string interp = "nn";       // nn | msm | rbf
    uint32_t k = 5;
    uint32_t raysPerPoint = 1;
    double scale = 2.0;
    bool taa = true;
    std::string view; // "" | points | cells | eccentricity
};

struct DemoStats {
    double frameMs = 0.0;
    double latencyMs = 0.0;
    uint64_t pointsSampled = 0;
    uint64_t rays = 0;
    std::string gazeSource;
    std::string device;
};

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
    vk::Context& mCtx;
    passes::OverlayPass mPass;
    VkDescriptorPool mPool = VK_NULL_HANDLE;
    bool mVisible = true;
    std::deque<float> mGpuHistory;
    std::map<std::string, std::deque<float>> mPassHistory;
};

} // namespace gt::app
