#include "point_sample/point_sample.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "foveated_shared.h"
#include "foveation/gpu_point_set.hpp"
#include "point_sample_comp.h"
#include "trace/gpu_scene.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::foveated;

namespace {
constexpr uint32_t kMaxLanes = 32; // a GPU subgroup's width at most; kSampleGroupSize / 2
} // namespace

uint32_t pointSampleLanes(const vk::Context& ctx, uint32_t raysPerPoint) {
    if (ctx.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) {
        return 1;
    }
    uint32_t lanes = 1;
    while (lanes * 2 <= std::min(raysPerPoint, kMaxLanes)) {
        lanes *= 2;
    }
    return lanes;
}

PointSamplePass::PointSamplePass(vk::Context& ctx) : mCtx(ctx) {}

PointSamplePass::~PointSamplePass() = default;

const vk::ComputePipeline& PointSamplePass::pipeline(uint32_t lanes, bool alphaMask) const {
    auto& slot = mPipelines[{lanes, alphaMask}];
    if (!slot) {
        const std::vector<VkDescriptorType> bindings =
            trace::tracingBindings({VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, // kBindingPoints
                                    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});     // kBindingSamples
        slot = std::make_unique<vk::ComputePipeline>(
            mCtx, vk::ComputePipelineDesc{"point_sample",
                                          gt_spv_point_sample_comp,
                                          bindings,
                                          sizeof(sh::PointSamplePush),
                                          {alphaMask ? 1u : 0u, lanes}});
    }
    return *slot;
}

rg::BufferId PointSamplePass::add(rg::RenderGraph& graph, const trace::GpuScene& scene,
                                  const shaders::trace::CameraPush& cam,
                                  const foveation::GpuPointSet& points, glm::vec2 gaze,
                                  uint32_t raysPerPoint, uint32_t lanesPerPoint,
                                  const PanelWarp* warp, bool lod, uint32_t frame, float siteJitter,
                                  bool thesisDisc) const {
    if (raysPerPoint == 0) {
        throw ArgumentError("rays per point is 0: every point traces at least 1 ray");
    }
    const uint32_t lanes =
        lanesPerPoint == 0 ? pointSampleLanes(mCtx, raysPerPoint) : lanesPerPoint;
    if (lanes > kMaxLanes || (lanes & (lanes - 1)) != 0) {
        throw ArgumentError("point_sample: lanes per point must be a power of two up to 32");
    }
    const vk::ComputePipeline& pipe = pipeline(lanes, scene.alphaMasked());
    const uint32_t pointsPerGroup = sh::kSampleGroupSize / lanes;
    const uint32_t w = graph.outputWidth(), h = graph.outputHeight();
    const glm::vec2 off = gazeOffset(gaze, points.displayWidth(), points.displayHeight());
    sh::PointSamplePush push{
        cam.origin,
        cam.forward,
        cam.right,
        cam.up,
        glm::vec4(off, kSampleMargin,
                  // Never 0, so that the sign always tells the disc.
                  (thesisDisc ? -1.0f : 1.0f) *
                      std::max(lod ? static_cast<float>(scene.lodLevels()) : 0.0f, 0.5f)),
        glm::uvec4(w, h, raysPerPoint, points.count()),
        glm::vec4(0.0f),
        glm::vec4(0.0f, 0.0f, 0.0f,
                  static_cast<float>(frame % (1u << 16)) +
                      0.5f * std::clamp(siteJitter, 0.0f, 1.9f))};
    if (warp) {
        const float aspect = static_cast<float>(w) / static_cast<float>(h);
        const glm::vec2 c = warp->centre;
        const float dx = std::max(c.x, 1.0f - c.x) * aspect, dy = std::max(c.y, 1.0f - c.y);
        push.lens = glm::vec4(c, aspect, std::sqrt(dx * dx + dy * dy));
        push.lensCoeffs =
            glm::vec4(warp->lens.k1, warp->lens.k2, 1.0f / (1.0f + warp->lens.k1 + warp->lens.k2),
                      push.lensCoeffs.w);
    }
    struct Data {
        rg::BufferId samples;
    };
    const auto& data = graph.addPass<Data>(
        "point_sample",
        [&](rg::PassBuilder& b, Data& d) {
            d.samples = b.write(b.createBuffer("point_sample.samples",
                                               {static_cast<VkDeviceSize>(points.count()) * 16}),
                                rg::Access::StorageWrite);
        },
        [ctx = &mCtx, pipeline = &pipe, scene = &scene, pts = &points, push,
         pointsPerGroup](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            vk::DescriptorWriter writer;
            scene->bind(writer);
            writer.texelBuffer(sh::kBindingPoints, pts->points())
                .storageBuffer(sh::kBindingSamples, r.buffer(d.samples));
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                         (push.params.w + pointsPerGroup - 1) / pointsPerGroup, 1);
        });
    return data.samples;
}

} // namespace gt::passes
