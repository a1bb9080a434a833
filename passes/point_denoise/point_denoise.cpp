#include "point_denoise/point_denoise.hpp"

#include <algorithm>
#include <string>

#include "core/error.hpp"
#include "foveation/gpu_point_set.hpp"
#include "point_denoise_comp.h"
#include "point_denoise_shared.h"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::point_denoise;

namespace {

struct StepData {
    rg::BufferId samples, guide, input, output;
};

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
}

PointDenoisePass::~PointDenoisePass() = default;

rg::BufferId PointDenoisePass::add(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                                   const PointSamples& sampled, const PointDenoiseFrame& frame,
                                   const PointDenoiseSettings& settings) const {
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
    sh::PointDenoisePush push = pushFor(graph, points, frame, settings);
    const VkDeviceSize bytes = static_cast<VkDeviceSize>(points.count()) * 16;
    rg::BufferId current = sampled.samples;
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
                d.guide = b.read(*sampled.guide, rg::Access::StorageRead);
                d.input = first ? d.samples : b.read(current, rg::Access::StorageRead);
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

} // namespace gt::passes
