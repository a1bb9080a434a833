#include "demo_overlay.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <imgui.h>

#include "core/error.hpp"
#include "core/log.hpp"
#include "gaze_mapping.hpp"
#include "overlay_layout.hpp"
#include "vk/context.hpp"
#include "window.hpp"

namespace gt::app {

namespace {
constexpr std::size_t kHistory = 120;

template <typename T> void push(std::deque<T>& d, T v) {
    d.push_back(v);
    if (d.size() > kHistory) d.pop_front();
}

bool combo(const char* label, std::string& value, const std::vector<const char*>& items) {
    int current = 0;
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (value == items[i]) current = static_cast<int>(i);
    }
    if (ImGui::Combo(label, &current, items.data(), static_cast<int>(items.size()))) {
        value = items[static_cast<std::size_t>(current)];
        return true;
    }
    return false;
}

// The desktop screen's pixels per degree at its centre, where the demo's window sits.
float desktopPixelsPerDegree() {
    const render::ScreenGeometry screen;
    return static_cast<float>(screen.distanceCm * std::tan(M_PI / 180.0) * screen.widthPx /
                              screen.widthCm);
}
} // namespace

DemoOverlay::DemoOverlay(Window& window, vk::Context& ctx, VkFormat format, uint32_t imageCount)
    : mLayer(window, ctx, format, imageCount) {}

DemoOverlay::~DemoOverlay() = default;

void DemoOverlay::swapchainRecreated(uint32_t imageCount) {
    mLayer.swapchainRecreated(imageCount);
}

void DemoOverlay::addTimings(const rg::FrameTimings& t) {
    push(mGpuHistory, static_cast<float>(t.gpuMs));
    for (const auto& p : t.passes)
        push(mPassHistory[p.name], static_cast<float>(p.gpuMs));
}

bool DemoOverlay::build(DemoSettings& s, const DemoStats& stats, std::optional<glm::vec2> target) {
    mLayer.newFrame();
    // The panel's place and the font's scale before the frame (NewFrame takes the scale).
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const glm::vec2 window(display.x, display.y);
    mLayout = overlayLayout(window, stats.gaze.value_or(0.5f * window), desktopPixelsPerDegree(),
                            mLayout.corner);
    ImGui::GetIO().FontGlobalScale = mLayout.fontScale;
    ImGui::NewFrame();
    bool changed = false;
    if (target) {
        // A calibration target: a ring with a dot, drawn over everything.
        ImDrawList* d = ImGui::GetForegroundDrawList();
        const ImVec2 c(target->x, target->y);
        d->AddCircleFilled(c, 12.0f, IM_COL32(255, 255, 255, 255));
        d->AddCircleFilled(c, 4.0f, IM_COL32(220, 0, 0, 255));
    }
    if (mVisible) {
        changed = panel(s, stats);
    }
    ImGui::Render();
    return changed;
}

bool DemoOverlay::panel(DemoSettings& s, const DemoStats& stats) {
    const OverlayLayout& layout = mLayout;
    // Anchored at its corner: a panel smaller than its largest size hugs the corner too.
    const glm::vec2 pivot(layout.corner % 2 == 1 ? 1.0f : 0.0f, layout.corner >= 2 ? 1.0f : 0.0f);
    const glm::vec2 anchor = layout.position + pivot * layout.maxSize;
    ImGui::SetNextWindowPos(ImVec2(anchor.x, anchor.y), ImGuiCond_Always, ImVec2(pivot.x, pivot.y));
    ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(layout.maxSize.x, layout.maxSize.y));
    ImGui::SetNextWindowBgAlpha(0.75f);
    ImGui::Begin("gazetrace (Tab hides)", nullptr,
                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove);
    ImGui::TextUnformatted(frameRateText(stats.frameMs).c_str());
    ImGui::TextUnformatted(latencyText(stats.latencyMs).c_str());
    if (ImGui::IsItemHovered()) {
        ImGui::SetTooltip("From the gaze sample a frame used to the moment the frame was known\n"
                          "finished on the device. No present timing is offered: not\n"
                          "gaze-to-photon, which adds the display's scan-out.");
    }
    if (!stats.defaults.empty()) ImGui::Text("defaults: %s", stats.defaults.c_str());
    bool changed = false;
    if (ImGui::CollapsingHeader("settings")) {
        ImGui::TextUnformatted(stats.device.c_str());
        ImGui::Text("gaze %s", stats.gazeSource.c_str());
        changed |= combo("method (M)", s.method, {"foveated", "layers", "reference"});
        if (s.method == "foveated") {
            changed |= combo("interpolation (I)", s.interp, {"nn", "msm", "rbf"});
            int k = static_cast<int>(s.k);
            if (s.interp != "nn" && ImGui::SliderInt("k", &k, 1, 20)) {
                s.k = static_cast<uint32_t>(k);
                changed = true;
            }
            int rays = static_cast<int>(s.raysPerPoint);
            if (ImGui::SliderInt("rays per point ([ ])", &rays, 1, 64)) {
                s.raysPerPoint = static_cast<uint32_t>(rays);
                changed = true;
            }
            float scale = static_cast<float>(s.scale);
            if (ImGui::SliderFloat("scale", &scale, 1.0f, 4.0f, "%.1f")) {
                s.scale = scale;
                changed = true;
            }
            std::string view = s.view.empty() ? "image" : s.view;
            if (combo("debug view (V)", view,
                      {"image", "points", "cells", "eccentricity", "motion"})) {
                s.view = view == "image" ? "" : view;
                changed = true;
            }
            ImGui::Text("points sampled %llu",
                        static_cast<unsigned long long>(stats.pointsSampled));
        }
        if (s.method != "layers") { // layers trace direct light
            changed |= combo("integrator", s.integrator, {"direct", "path"});
            int bounces = static_cast<int>(s.bounces);
            if (s.integrator == "path" && ImGui::SliderInt("bounces", &bounces, 1, 16)) {
                s.bounces = static_cast<uint32_t>(bounces);
                changed = true;
            }
            changed |= ImGui::Checkbox("denoise", &s.denoise);
        }
        changed |= ImGui::Checkbox("TAA (T)", &s.taa);
        ImGui::Text("rays %llu", static_cast<unsigned long long>(stats.rays));
        ImGui::TextWrapped("WASD/QE move, right button looks, P screenshot, R records path");
    }
    if (!mGpuHistory.empty() && ImGui::CollapsingHeader("GPU time per pass")) {
        // On lavapipe, once a render pass (this overlay's) has run, llvmpipe bins later
        // timestamp queries with its rasteriser and the compute passes' times collapse;
        // the frame time above is wall clock and stays right. GPUs report true times.
        const std::vector<float> gpu(mGpuHistory.begin(), mGpuHistory.end());
        char label[64];
        std::snprintf(label, sizeof(label), "GPU %.1f ms", gpu.back());
        ImGui::PlotLines("##gpu", gpu.data(), static_cast<int>(gpu.size()), 0, label, 0.0f, FLT_MAX,
                         ImVec2(0, 50 * layout.fontScale));
        for (const auto& [name, h] : mPassHistory) {
            ImGui::Text("%-22s %7.2f ms", name.c_str(), h.back());
        }
    }
    ImGui::End();
    return changed;
}

rg::TextureId DemoOverlay::add(rg::RenderGraph& graph, rg::TextureId image) {
    return mLayer.add(graph, image);
}

} // namespace gt::app
