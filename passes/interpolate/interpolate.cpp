#include "interpolate/interpolate.hpp"

#include "core/error.hpp"
#include "foveated_shared.h"
#include "foveation/gpu_point_set.hpp"
#include "interpolate_comp.h"
#include "point_sample/point_sample.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::foveated;

Interpolation parseInterpolation(const std::string& name) {
    if (name == "nn") return Interpolation::Nearest;
    if (name == "msm") return Interpolation::Shepard;
    throw ArgumentError("--interp: '" + name + "' is not available (known: nn, msm)");
}

Interpolation parseView(const std::string& name) {
    if (name == "points") return Interpolation::ViewPoints;
    if (name == "cells") return Interpolation::ViewCells;
    if (name == "eccentricity") return Interpolation::ViewSpacing;
    throw ArgumentError("--view: '" + name +
                        "' is not available (known: points, cells, eccentricity)");
}

InterpolatePass::InterpolatePass(vk::Context& ctx) : mCtx(ctx) {
    mPipeline = std::make_unique<vk::ComputePipeline>(
        ctx, vk::ComputePipelineDesc{
                 "interpolate",
                 gt_spv_interpolate_comp,
                 {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                  VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
                  VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                 sizeof(sh::InterpolatePush)});
}

InterpolatePass::~InterpolatePass() = default;

rg::TextureId InterpolatePass::add(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                                   rg::BufferId samples, glm::vec2 gaze,
                                   const InterpolateSettings& s) const {
    if (s.k == 0 || s.k > points.storedNeighbours() + 1 || s.k > sh::kMaxK) {
        throw ArgumentError("--k must be 1.." +
                            std::to_string(std::min(sh::kMaxK, points.storedNeighbours() + 1)));
    }
    const glm::vec2 off = gazeOffset(gaze, points.displayWidth(), points.displayHeight());
    uint32_t method = sh::kMethodNearest;
    switch (s.method) {
    case Interpolation::Nearest:
        method = sh::kMethodNearest;
        break;
    case Interpolation::Shepard:
        method = sh::kMethodShepard;
        break;
    case Interpolation::ViewPoints:
        method = sh::kViewPoints;
        break;
    case Interpolation::ViewCells:
        method = sh::kViewCells;
        break;
    case Interpolation::ViewSpacing:
        method = sh::kViewSpacing;
        break;
    }
    const uint32_t k = s.method == Interpolation::Shepard ? s.k : 1u;
    const sh::InterpolatePush push{
        glm::vec4(off, kSampleMargin, s.shepardPower),
        glm::uvec4(graph.outputWidth(), graph.outputHeight(), k, method),
        glm::uvec4(points.canvasWidth(), points.canvasHeight(), points.storedNeighbours(), 0)};
    struct Data {
        rg::BufferId samples;
        rg::TextureId output;
    };
    const auto& data = graph.addPass<Data>(
        "interpolate",
        [&](rg::PassBuilder& b, Data& d) {
            d.samples = b.read(samples, rg::Access::StorageRead);
            d.output =
                b.write(b.createTexture("interpolate.radiance", {VK_FORMAT_R32G32B32A32_SFLOAT}),
                        rg::Access::StorageWrite);
        },
        [ctx = &mCtx, pipeline = mPipeline.get(), pts = &points,
         push](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            vk::DescriptorWriter writer;
            writer.texelBuffer(sh::kBindingInterpPoints, pts->points())
                .storageBuffer(sh::kBindingInterpSamples, r.buffer(d.samples))
                .texelBuffer(sh::kBindingNearest, pts->nearest())
                .texelBuffer(sh::kBindingNeighbours, pts->neighbours())
                .storageImage(sh::kBindingInterpOutput, r.texture(d.output).view);
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                         (push.params.x + sh::kInterpGroupX - 1) / sh::kInterpGroupX,
                         (push.params.y + sh::kInterpGroupY - 1) / sh::kInterpGroupY);
        });
    return data.output;
}

} // namespace gt::passes
