#pragma once
// Pass `point_denoise`: SVGF's edge-avoiding filter (Schied et al. 2017) on the point set's
// neighbour graph, over the path tracer's samples before interpolation, guided by each point's
// first-hit normal, distance, albedo and the variance of its paths, applied more the farther a
// point lies from the gaze (none within the fovea). shaders/point_denoise/point_denoise.comp
// has the maths.
#include <cstdint>
#include <memory>
#include <optional>

#include <glm/glm.hpp>

#include "foveation/sample_canvas.hpp"
#include "render_graph/render_graph.hpp"
#include "trace_shared.h"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk
namespace gt::foveation {
class GpuPointSet;
}

namespace gt::passes {

struct PointDenoiseSettings {
    // Steps over the neighbour graph; each reaches a point's `neighbours` nearest.
    uint32_t steps = 3;
    uint32_t neighbours = 12;
    // The spatial Gaussian's standard deviation, in units of the point's spacing.
    float spacingSigma = 1.0f;
    float sigmaLuminance = 4.0f; // luminance difference, in standard deviations of the point
    float sigmaDepth = 0.05f;    // a neighbour's hit off the point's surface plane, relative
    float normalPower = 32.0f;   // (n_i . n_j)^power
    float foveaDeg = 5.0f;       // no filtering below this eccentricity (degrees)
    float fullDeg = 15.0f;       // full strength from here (a smooth ramp between)
    // The temporal step's weight of the current frame once a history holds 1 / alpha frames
    // (SVGF's 0.2); 0: no temporal step (each frame filtered on its own).
    float temporalAlpha = 0.2f;

    friend bool operator==(const PointDenoiseSettings&, const PointDenoiseSettings&) = default;
};

// What the filter reads of point_sample's output: the samples (one vec4 per point: mean
// radiance, first-hit distance) and the guides the path integrator writes beside them.
struct PointSamples {
    rg::BufferId samples;
    std::optional<rg::BufferId> guide;
};

// Where point_sample's points were traced this frame, as the filter must find them again.
struct PointDenoiseFrame {
    shaders::trace::CameraPush camera;
    glm::vec2 gaze{};        // screen pixels (on the panel when `warp` is set)
    uint32_t frame = 0;      // point_sample's frame
    float siteJitter = 0.0f; // and its sites' jitter scale
    const foveation::PanelWarp* warp = nullptr;
};

// What the temporal step keeps across frames: its histories (named in the graph's scope) and
// last frame's camera and gaze, which carry a point's hit to where it was seen.
struct PointDenoiseHistory {
    rg::HistoryPool& pool;
    std::optional<shaders::trace::CameraPush> camera; // none: the view's first frame
    glm::vec2 gaze{};
};

class PointDenoisePass {
public:
    explicit PointDenoisePass(vk::Context& ctx);
    ~PointDenoisePass();
    // Adds "point_denoise.temporal" (with a history, settings.temporalAlpha > 0 and no panel
    // warp), "point_denoise.demodulate" and "point_denoise.step0".. reading `sampled` (which
    // must hold the path integrator's guides) and returns a new buffer laid out as its samples.
    // Throws gt::ArgumentError without guides, for 0 steps, neighbours beyond those stored or
    // an alpha outside [0, 1].
    rg::BufferId add(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                     const PointSamples& sampled, const PointDenoiseFrame& frame,
                     const PointDenoiseSettings& settings,
                     const std::optional<PointDenoiseHistory>& history = std::nullopt) const;

private:
    // The accumulated light (and its variance) and the guides with the accumulated albedo.
    struct TemporalOutput {
        rg::BufferId light, guide;
    };
    TemporalOutput addTemporal(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                               const PointSamples& sampled, const PointDenoiseFrame& frame,
                               const PointDenoiseSettings& settings,
                               const PointDenoiseHistory& history) const;

    vk::Context& mCtx;
    std::unique_ptr<vk::ComputePipeline> mPipeline;
    std::unique_ptr<vk::ComputePipeline> mTemporal;
};

} // namespace gt::passes
