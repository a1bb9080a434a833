#pragma once
// Pass `point_sample` (thesis, 4.2): traces R rays inside the disc of every point of the set
// that lands on screen (plus a 10-pixel margin) once shifted to the gaze point.
#include <cstdint>
#include <map>
#include <memory>
#include <tuple>

#include <glm/glm.hpp>

#include "display/hmd_profile.hpp"
#include "foveation/sample_canvas.hpp"
#include "render_graph/render_graph.hpp"
#include "trace/integrator.hpp"
#include "trace_shared.h"
#include "vk/resources.hpp"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk
namespace gt::trace {
class GpuScene;
}
namespace gt::foveation {
class GpuPointSet;
}

namespace gt::passes {

using foveation::gazeOffset;
using foveation::kSampleMargin;
using foveation::PanelWarp;

// How many threads trace the rays of one point side by side. On a GPU the largest power of two
// up to min(R, 32), so that a subgroup traces the rays of one disc: on an H100 at R = 32 the
// pass took 12.0 ms with one thread per point and 5.3 ms with 32 (8 or 16: 5.6 / 5.4 ms).
// On a CPU driver 1: lavapipe at R = 8 took 2.05 s with 1 and 2.1-2.4 s with 8.
[[nodiscard]] uint32_t pointSampleLanes(const vk::Context& ctx, uint32_t raysPerPoint);

// Which threads point_sample starts: one per point of the chunks that can land on screen
// (foveation::PointChunks), or one per point of the whole canvas set. Both trace the same
// points with the same rays; the chunks skip the off-screen ones (29 % of the fove set with the
// gaze centred, 73 % in a corner) and keep a workgroup's rays neighbours.
enum class PointDispatch : uint8_t { OnScreenChunks, WholeSet };

// What point_sample writes: per point the mean radiance and first-hit distance, in a scene
// that moves (trace::GpuScene::dynamic()) the first hit's motion (shaders/common/motion.glsl),
// and from the path integrator the point denoiser's guides (shaders/common/point_guide.glsl).
struct SampledPoints {
    rg::BufferId samples;
    std::optional<rg::BufferId> motion, guide;
};

// Paths per point by eccentricity: the points within `radiusPx` (canvas pixels) of the centre
// of interest trace `rays` each instead of the pass's rays per point. rays 0 or radiusPx 0: off.
struct FoveaRays {
    uint32_t rays = 0;
    float radiusPx = 0.0f;
    [[nodiscard]] bool on() const noexcept { return rays > 0 && radiusPx > 0.0f; }
};

class PointSamplePass {
public:
    explicit PointSamplePass(vk::Context& ctx);
    ~PointSamplePass();
    // Adds "point_sample" writing a new buffer "point_sample.samples" (one vec4 per point).
    // lanesPerPoint 0 picks pointSampleLanes(); otherwise a power of two from 1 to 32. With
    // `lod`, points whose spacing is large trace the scene's coarser geometric LOD levels.
    // `frame` rotates the rays' positions inside each disc (frame 0: the thesis's fixed ones);
    // with `siteJitter` > 0 the disc centres move too, by up to that share of their spacing
    // (site_jitter.glsl; below 1.9). `thesisDisc`: rays anywhere
    // in the point's disc of radius p, as the thesis; else within 0.6 px of the site. With
    // OnScreenChunks a pass "point_sample.chunks" first uploads this frame's chunk list.
    // `integrator`: what each ray computes (the direct integrator or the path tracer). `fovea`:
    // more rays for the points near the gaze. Throws for more than 65535 rays per point.
    rg::BufferId add(rg::RenderGraph& graph, const trace::GpuScene& scene,
                     const shaders::trace::CameraPush& camera, const foveation::GpuPointSet& points,
                     glm::vec2 gaze, uint32_t raysPerPoint, uint32_t lanesPerPoint = 0,
                     const PanelWarp* warp = nullptr, bool lod = false, uint32_t frame = 0,
                     float siteJitter = 0.0f, bool thesisDisc = false,
                     PointDispatch dispatch = PointDispatch::OnScreenChunks,
                     const trace::IntegratorSettings& integrator = {},
                     const FoveaRays& fovea = {}) const;
    // The same, and in a scene that moves also a new buffer "point_sample.motion" (one vec4
    // per point: its ray 0's first hit's motion).
    SampledPoints addSamples(rg::RenderGraph& graph, const trace::GpuScene& scene,
                             const shaders::trace::CameraPush& camera,
                             const foveation::GpuPointSet& points, glm::vec2 gaze,
                             uint32_t raysPerPoint, uint32_t lanesPerPoint = 0,
                             const PanelWarp* warp = nullptr, bool lod = false, uint32_t frame = 0,
                             float siteJitter = 0.0f, bool thesisDisc = false,
                             PointDispatch dispatch = PointDispatch::OnScreenChunks,
                             const trace::IntegratorSettings& integrator = {},
                             const FoveaRays& fovea = {}) const;

private:
    const vk::ComputePipeline& pipeline(uint32_t lanes, bool alphaMask, bool chunked, bool dynamic,
                                        const trace::IntegratorSettings& integrator,
                                        float foveaRadiusPx) const;

    vk::Context& mCtx;
    // One pipeline per lane count, alpha-mask setting, dispatch, scene kind (static or
    // moving) and integrator, built on first use (each compiles the whole tracer).
    mutable std::map<
        std::tuple<uint32_t, bool, bool, bool, uint32_t, uint32_t, float, uint32_t, float>,
        std::unique_ptr<vk::ComputePipeline>>
        mPipelines;
    vk::Buffer mNoChunks; // bound as the chunk list when the whole set is dispatched
};

} // namespace gt::passes
