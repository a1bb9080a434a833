#include "point_denoise/point_denoise.hpp"

#include <algorithm>
#include <string>

#include "core/error.hpp"
#include "foveation/gpu_point_set.hpp"
#include "point_denoise_comp.h"
#include "point_denoise_shared.h"
#include "point_temporal_comp.h"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::point_denoise;

namespace {

struct StepData {
    rg::BufferId samples, guide, input, output;
};

struct TemporalData {
    rg::BufferId samples, guide, output, guideOut;
    rg::TextureId lightThen, hitThen, albedoThen, lightNext, hitNext, albedoNext;
};

constexpr const char* kLightHistory = "point_denoise.light";
constexpr const char* kHitHistory = "point_denoise.hit";
constexpr const char* kAlbedoHistory = "point_denoise.albedo";
constexpr VkFormat kLightFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kHitFormat = VK_FORMAT_R32G32B32A32_UINT;
constexpr VkFormat kAlbedoFormat = VK_FORMAT_R32_UINT;

bool sameFrustum(const shaders::trace::CameraPush& a, const shaders::trace::CameraPush& b) {
    return a.origin.w == b.origin.w && a.forward.w == b.forward.w && a.right.w == b.right.w &&
           a.up.w == b.up.w;
}

// The rows of the 3x4 transform from `now`'s camera frame (x right, y up, z forward) into
// `then`'s: each of then's axes in now's axes, and now's origin seen from then's.
void setToPrevious(sh::PointTemporalPush& push, const shaders::trace::CameraPush& now,
                   const shaders::trace::CameraPush& then) {
    const glm::vec3 r(now.right), u(now.up), f(now.forward);
    const glm::vec3 o = glm::vec3(now.origin) - glm::vec3(then.origin);
    auto row = [&](const glm::vec4& axis) {
        const glm::vec3 a(axis);
        return glm::vec4(glm::dot(r, a), glm::dot(u, a), glm::dot(f, a), glm::dot(o, a));
    };
    push.toPrevious0 = row(then.right);
    push.toPrevious1 = row(then.up);
    push.toPrevious2 = row(then.forward);
}

constexpr uint32_t kMaxSteps = 16;

sh::PointDenoisePush pushFor(const rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                             const PointDenoiseFrame& f, const PointDenoiseSettings& s) {
    const uint32_t w = graph.outputWidth(), h = graph.outputHeight();
    const glm::vec2 off =
        foveation::gazeOffset(f.gaze, points.displayWidth(), points.displayHeight());
    const shaders::trace::CameraPush& c = f.camera;
    sh::PointDenoisePush push{
        glm::vec4(off, foveation::kSampleMargin, foveation::siteFrameField(f.frame, f.siteJitter)),
        glm::uvec4(w, h, points.count(), points.storedNeighbours()),
        glm::vec4(c.origin.w, c.forward.w, c.right.w, c.up.w),
        glm::vec4(s.sigmaLuminance, s.sigmaDepth, s.foveaDeg, s.fullDeg), glm::vec4(0.0f),
        glm::vec4(0.0f),
        // The gaze as point_sample places it: the canvas centre, shifted by the whole-pixel
        // offset.
        glm::vec4(off + glm::vec2(points.displayWidth(), points.displayHeight()), s.normalPower,
                  s.spacingSigma),
        glm::uvec4(s.neighbours, sh::kStepDemodulate, 0u, 0u)};
    if (f.warp) {
        const foveation::PanelWarpPush p = foveation::panelWarpPush(*f.warp, w, h);
        push.lens = p.lens;
        push.lensCoeffs = p.coeffs;
    }
    return push;
}

} // namespace

PointDenoisePass::PointDenoisePass(vk::Context& ctx) : mCtx(ctx) {
    mPipeline = std::make_unique<vk::ComputePipeline>(
        ctx, vk::ComputePipelineDesc{
                 "point_denoise",
                 gt_spv_point_denoise_comp,
                 {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
                  VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                  VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                 sizeof(sh::PointDenoisePush)});
    mTemporal = std::make_unique<vk::ComputePipeline>(
        ctx, vk::ComputePipelineDesc{
                 "point_temporal",
                 gt_spv_point_temporal_comp,
                 {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
                  VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                  VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                  VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                  VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                  VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                  VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
                 sizeof(sh::PointTemporalPush)});
}

PointDenoisePass::~PointDenoisePass() = default;

rg::BufferId PointDenoisePass::add(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                                   const PointSamples& sampled, const PointDenoiseFrame& frame,
                                   const PointDenoiseSettings& settings,
                                   const std::optional<PointDenoiseHistory>& history) const {
    points.requireIndex("point_denoise");
    if (!sampled.guide) {
        throw ArgumentError("point_denoise: the samples carry no guides (the path integrator "
                            "writes them)");
    }
    if (settings.steps == 0 || settings.steps > kMaxSteps) {
        throw ArgumentError("point_denoise: steps must be 1 to " + std::to_string(kMaxSteps) +
                            ", got " + std::to_string(settings.steps));
    }
    if (settings.neighbours > points.storedNeighbours()) {
        throw ArgumentError("point_denoise: " + std::to_string(settings.neighbours) +
                            " neighbours asked, the set stores " +
                            std::to_string(points.storedNeighbours()));
    }
    if (!(settings.temporalAlpha >= 0.0f && settings.temporalAlpha <= 1.0f)) {
        throw ArgumentError("point_denoise: the temporal alpha must lie in [0, 1], got " +
                            std::to_string(settings.temporalAlpha));
    }
    sh::PointDenoisePush push = pushFor(graph, points, frame, settings);
    const VkDeviceSize bytes = static_cast<VkDeviceSize>(points.count()) * 16;
    rg::BufferId current = sampled.samples, guide = *sampled.guide;
    // A panel's sites would need the lens warp inverted to find last frame's: no history there.
    if (history && settings.temporalAlpha > 0.0f && frame.warp == nullptr) {
        const TemporalOutput temporal =
            addTemporal(graph, points, sampled, frame, settings, *history);
        current = temporal.light;
        guide = temporal.guide;
        push.step.z = sh::kInputTemporal;
    }
    for (uint32_t step = 0; step <= settings.steps; ++step) {
        const bool first = step == 0;
        push.step.y = first                    ? sh::kStepDemodulate
                      : step == settings.steps ? sh::kStepLast
                                               : sh::kStepFilter;
        const std::string name = first ? std::string("point_denoise.demodulate")
                                       : "point_denoise.step" + std::to_string(step - 1);
        const auto& data = graph.addPass<StepData>(
            name,
            [&](rg::PassBuilder& b, StepData& d) {
                d.samples = b.read(sampled.samples, rg::Access::StorageRead);
                d.guide = b.read(guide, rg::Access::StorageRead);
                d.input = current == sampled.samples ? d.samples
                                                     : b.read(current, rg::Access::StorageRead);
                d.output = b.write(b.createBuffer(name, {bytes}), rg::Access::StorageWrite);
            },
            [ctx = &mCtx, pipeline = mPipeline.get(), pts = &points,
             push](const rg::PassResources& r, const StepData& d, VkCommandBuffer cmd) {
                vk::DescriptorWriter writer;
                writer.texelBuffer(sh::kBindingPoints, pts->points())
                    .texelBuffer(sh::kBindingNeighbours, pts->neighbours())
                    .storageBuffer(sh::kBindingSamples, r.buffer(d.samples))
                    .storageBuffer(sh::kBindingGuide, r.buffer(d.guide))
                    .storageBuffer(sh::kBindingInput, r.buffer(d.input))
                    .storageBuffer(sh::kBindingOutput, r.buffer(d.output));
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline->handle());
                writer.push(*ctx, cmd, *pipeline);
                vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                             (push.params.z + sh::kGroupSize - 1) / sh::kGroupSize, 1);
            });
        current = data.output;
    }
    return current;
}

// point_temporal: each point's demodulated light and variance, accumulated with the history
// of its surface, into "point_denoise.temporal"; the histories for the next frame beside it.
PointDenoisePass::TemporalOutput
PointDenoisePass::addTemporal(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                              const PointSamples& sampled, const PointDenoiseFrame& frame,
                              const PointDenoiseSettings& settings,
                              const PointDenoiseHistory& history) const {
    const uint32_t rows = (points.count() + sh::kHistoryWidth - 1) / sh::kHistoryWidth;
    const rg::HistoryTextures light =
        graph.importHistory(history.pool, kLightHistory, kLightFormat, sh::kHistoryWidth, rows);
    const rg::HistoryTextures hit =
        graph.importHistory(history.pool, kHitHistory, kHitFormat, sh::kHistoryWidth, rows);
    const rg::HistoryTextures albedo =
        graph.importHistory(history.pool, kAlbedoHistory, kAlbedoFormat, sh::kHistoryWidth, rows);
    const sh::PointDenoisePush base = pushFor(graph, points, frame, settings);
    sh::PointTemporalPush push{};
    push.offset = base.offset;
    push.params = glm::uvec4(base.params.x, base.params.y, points.count(),
                             points.canvasWidth() | (points.canvasHeight() << 16u));
    push.frustum = base.frustum;
    push.gaze = glm::vec4(base.gaze.x, base.gaze.y, settings.foveaDeg, settings.fullDeg);
    const bool valid =
        light.valid && hit.valid && history.camera && sameFrustum(*history.camera, frame.camera);
    if (valid) {
        setToPrevious(push, frame.camera, *history.camera);
    }
    push.previous = glm::vec4(
        foveation::gazeOffset(history.gaze, points.displayWidth(), points.displayHeight()),
        settings.temporalAlpha, valid ? static_cast<float>(points.storedNeighbours() + 1) : 0.0f);
    const VkDeviceSize bytes = static_cast<VkDeviceSize>(points.count()) * 16;
    const auto& data = graph.addPass<TemporalData>(
        "point_denoise.temporal",
        [&](rg::PassBuilder& b, TemporalData& d) {
            d.samples = b.read(sampled.samples, rg::Access::StorageRead);
            d.guide = b.read(*sampled.guide, rg::Access::StorageRead);
            d.lightThen = b.read(light.previous, rg::Access::StorageRead);
            d.hitThen = b.read(hit.previous, rg::Access::StorageRead);
            d.albedoThen = b.read(albedo.previous, rg::Access::StorageRead);
            d.lightNext = b.write(light.next, rg::Access::StorageWrite);
            d.hitNext = b.write(hit.next, rg::Access::StorageWrite);
            d.albedoNext = b.write(albedo.next, rg::Access::StorageWrite);
            d.output = b.write(b.createBuffer("point_denoise.temporal", {bytes}),
                               rg::Access::StorageWrite);
            d.guideOut =
                b.write(b.createBuffer("point_denoise.guide", {bytes}), rg::Access::StorageWrite);
        },
        [ctx = &mCtx, pipeline = mTemporal.get(), pts = &points,
         push](const rg::PassResources& r, const TemporalData& d, VkCommandBuffer cmd) {
            vk::DescriptorWriter writer;
            writer.texelBuffer(sh::kBindingPoints, pts->points())
                .texelBuffer(sh::kBindingTemporalNearest, pts->nearest())
                .texelBuffer(sh::kBindingTemporalNeighbours, pts->neighbours())
                .storageBuffer(sh::kBindingSamples, r.buffer(d.samples))
                .storageBuffer(sh::kBindingGuide, r.buffer(d.guide))
                .storageBuffer(sh::kBindingTemporalOutput, r.buffer(d.output))
                .storageImage(sh::kBindingHistoryLight, r.texture(d.lightThen).view)
                .storageImage(sh::kBindingHistoryHit, r.texture(d.hitThen).view)
                .storageImage(sh::kBindingNextLight, r.texture(d.lightNext).view)
                .storageImage(sh::kBindingNextHit, r.texture(d.hitNext).view)
                .storageImage(sh::kBindingHistoryAlbedo, r.texture(d.albedoThen).view)
                .storageImage(sh::kBindingNextAlbedo, r.texture(d.albedoNext).view)
                .storageBuffer(sh::kBindingTemporalGuide, r.buffer(d.guideOut));
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline->handle());
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                         (push.params.z + sh::kGroupSize - 1) / sh::kGroupSize, 1);
        });
    return {data.output, data.guideOut};
}

} // namespace gt::passes
