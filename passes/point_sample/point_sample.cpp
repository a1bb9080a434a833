#include "point_sample/point_sample.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

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
constexpr uint32_t kMaxLanes = 32;    // a GPU subgroup's width at most; kSampleGroupSize / 2
constexpr uint32_t kMaxRays = 0xffff; // params.z holds two counts of 16 bits

// The tracing constants with the fovea's radius (kSpecFoveaRadius) when it is on: off, the
// pipelines are built exactly as without it.
std::vector<uint32_t> fovealSpecialization(std::vector<uint32_t> constants, float radiusPx) {
    if (radiusPx <= 0.0f) return constants;
    constants.resize(std::max<std::size_t>(constants.size(), sh::kSpecFoveaRadius + 1));
    constants[sh::kSpecFoveaRadius] = std::bit_cast<uint32_t>(radiusPx);
    return constants;
}
static_assert(foveation::PointChunks::kPoints == sh::kSampleGroupSize,
              "a chunk is one workgroup's points at one lane per point");

// Adds "point_sample.chunks": this frame's list of chunks to trace, written into a new buffer
// (vkCmdUpdateBuffer takes at most 64 KiB at a time).
rg::BufferId addChunkList(rg::RenderGraph& graph, const foveation::PointChunks& all,
                          std::shared_ptr<const std::vector<uint32_t>> chunks) {
    struct Data {
        rg::BufferId list;
    };
    const auto& data = graph.addPass<Data>(
        "point_sample.chunks",
        [&](rg::PassBuilder& b, Data& d) {
            const VkDeviceSize bytes = 4 * static_cast<VkDeviceSize>(std::max(all.count(), 1u));
            d.list =
                b.write(b.createBuffer("point_sample.chunks", {bytes}), rg::Access::TransferDst);
        },
        [chunks = std::move(chunks)](const rg::PassResources& r, const Data& d,
                                     VkCommandBuffer cmd) {
            constexpr std::size_t kMaxUpdate = 65536 / 4;
            for (std::size_t first = 0; first < chunks->size(); first += kMaxUpdate) {
                const std::size_t n = std::min(kMaxUpdate, chunks->size() - first);
                vkCmdUpdateBuffer(cmd, r.buffer(d.list), first * 4, n * 4, &(*chunks)[first]);
            }
        });
    return data.list;
}
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

PointSamplePass::PointSamplePass(vk::Context& ctx)
    : mCtx(ctx), mNoChunks(ctx, {16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUsage::GpuOnly,
                                 "point_sample.no_chunks"}) {}

PointSamplePass::~PointSamplePass() = default;

const vk::ComputePipeline& PointSamplePass::pipeline(uint32_t lanes, bool alphaMask, bool chunked,
                                                     bool dynamic,
                                                     const trace::IntegratorSettings& i,
                                                     float foveaRadiusPx) const {
    const bool direct = i.integrator == trace::Integrator::Direct; // one pipeline, any bounces
    auto& slot =
        mPipelines[{lanes, alphaMask, chunked, dynamic, static_cast<uint32_t>(i.integrator),
                    direct ? 0u : i.bounces, direct ? 0.0f : i.fireflyClamp,
                    direct ? 0u : static_cast<uint32_t>(i.sequence), foveaRadiusPx}];
    if (!slot) {
        const std::vector<VkDescriptorType> bindings =
            trace::tracingBindings({VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, // kBindingPoints
                                    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,       // kBindingSamples
                                    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,       // kBindingChunks
                                    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,       // kBindingSampleMotion
                                    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});     // kBindingSampleGuide
        slot = std::make_unique<vk::ComputePipeline>(
            mCtx,
            vk::ComputePipelineDesc{
                "point_sample", gt_spv_point_sample_comp, bindings, sizeof(sh::PointSamplePush),
                fovealSpecialization(
                    trace::tracingSpecialization({alphaMask ? 1u : 0u, lanes, chunked ? 1u : 0u},
                                                 dynamic, i),
                    foveaRadiusPx)});
    }
    return *slot;
}

rg::BufferId PointSamplePass::add(rg::RenderGraph& graph, const trace::GpuScene& scene,
                                  const shaders::trace::CameraPush& cam,
                                  const foveation::GpuPointSet& points, glm::vec2 gaze,
                                  uint32_t raysPerPoint, uint32_t lanesPerPoint,
                                  const PanelWarp* warp, bool lod, uint32_t frame, float siteJitter,
                                  bool thesisDisc, PointDispatch dispatch,
                                  const trace::IntegratorSettings& integrator,
                                  const FoveaRays& fovea) const {
    return addSamples(graph, scene, cam, points, gaze, raysPerPoint, lanesPerPoint, warp, lod,
                      frame, siteJitter, thesisDisc, dispatch, integrator, fovea)
        .samples;
}

SampledPoints PointSamplePass::addSamples(rg::RenderGraph& graph, const trace::GpuScene& scene,
                                          const shaders::trace::CameraPush& cam,
                                          const foveation::GpuPointSet& points, glm::vec2 gaze,
                                          uint32_t raysPerPoint, uint32_t lanesPerPoint,
                                          const PanelWarp* warp, bool lod, uint32_t frame,
                                          float siteJitter, bool thesisDisc, PointDispatch dispatch,
                                          const trace::IntegratorSettings& integrator,
                                          const FoveaRays& fovea) const {
    if (raysPerPoint == 0) {
        throw ArgumentError("rays per point is 0: every point traces at least 1 ray");
    }
    if (raysPerPoint > kMaxRays || fovea.rays > kMaxRays) {
        throw ArgumentError("point_sample: at most 65535 rays per point");
    }
    const uint32_t lanes =
        lanesPerPoint == 0 ? pointSampleLanes(mCtx, raysPerPoint) : lanesPerPoint;
    if (lanes > kMaxLanes || (lanes & (lanes - 1)) != 0) {
        throw ArgumentError("point_sample: lanes per point must be a power of two up to 32");
    }
    const bool chunked = dispatch == PointDispatch::OnScreenChunks;
    const bool dynamic = scene.dynamic();
    const vk::ComputePipeline& pipe = pipeline(lanes, scene.alphaMasked(), chunked, dynamic,
                                               integrator, fovea.on() ? fovea.radiusPx : 0.0f);
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
        glm::uvec4(w, h, raysPerPoint | (fovea.on() ? fovea.rays << 16 : 0u), points.count()),
        glm::vec4(0.0f),
        glm::vec4(0.0f, 0.0f, 0.0f, foveation::siteFrameField(frame, siteJitter))};
    if (warp) {
        const foveation::PanelWarpPush p = foveation::panelWarpPush(*warp, w, h);
        push.lens = p.lens;
        push.lensCoeffs = glm::vec4(glm::vec3(p.coeffs), push.lensCoeffs.w);
    }
    // Whole workgroups: the set's points, or `lanes` per chunk that can land on screen. The
    // chunks allow for the sites' moves exactly as the shader reads their scale back.
    uint32_t groups = (push.params.w + pointsPerGroup - 1) / pointsPerGroup;
    std::optional<rg::BufferId> chunkList;
    if (chunked) {
        const float field = push.lensCoeffs.w;
        const float siteMove = 2.0f * (field - std::floor(field));
        auto chunks = std::make_shared<const std::vector<uint32_t>>(
            points.chunks().onScreen(off, w, h, kSampleMargin, siteMove));
        groups = static_cast<uint32_t>(chunks->size()) * lanes;
        chunkList = addChunkList(graph, points.chunks(), std::move(chunks));
    }
    const bool guided = integrator.integrator == trace::Integrator::Path;
    struct Data {
        rg::BufferId samples;
        std::optional<rg::BufferId> chunks, motion, guide;
    };
    const auto& data = graph.addPass<Data>(
        "point_sample",
        [&](rg::PassBuilder& b, Data& d) {
            d.samples = b.write(b.createBuffer("point_sample.samples",
                                               {static_cast<VkDeviceSize>(points.count()) * 16}),
                                rg::Access::StorageWrite);
            if (dynamic) {
                d.motion = b.write(b.createBuffer("point_sample.motion",
                                                  {static_cast<VkDeviceSize>(points.count()) * 16}),
                                   rg::Access::StorageWrite);
            }
            if (guided) {
                d.guide = b.write(b.createBuffer("point_sample.guide",
                                                 {static_cast<VkDeviceSize>(points.count()) * 16}),
                                  rg::Access::StorageWrite);
            }
            if (chunkList) {
                d.chunks = b.read(*chunkList, rg::Access::StorageRead);
            }
        },
        [ctx = &mCtx, pipeline = &pipe, scene = &scene, pts = &points, push, groups,
         noChunks = mNoChunks.handle()](const rg::PassResources& r, const Data& d,
                                        VkCommandBuffer cmd) {
            vk::DescriptorWriter writer;
            scene->bind(writer);
            writer.texelBuffer(sh::kBindingPoints, pts->points())
                .storageBuffer(sh::kBindingSamples, r.buffer(d.samples))
                .storageBuffer(sh::kBindingChunks, d.chunks ? r.buffer(*d.chunks) : noChunks)
                // A scene that does not move never writes it.
                .storageBuffer(sh::kBindingSampleMotion,
                               d.motion ? r.buffer(*d.motion) : r.buffer(d.samples))
                // Only the path integrator writes it.
                .storageBuffer(sh::kBindingSampleGuide,
                               d.guide ? r.buffer(*d.guide) : r.buffer(d.samples));
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push), groups, 1);
        });
    return {data.samples, data.motion, data.guide};
}

} // namespace gt::passes
