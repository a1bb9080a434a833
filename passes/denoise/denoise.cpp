#include "denoise/denoise.hpp"

#include <bit>
#include <string>

#include "core/error.hpp"
#include "denoise_comp.h"
#include "denoise_shared.h"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::denoise;

namespace {

struct StepData {
    rg::TextureId radiance, input, output, guide;
};

constexpr uint32_t kMaxLevels = 16;

} // namespace

DenoisePass::DenoisePass(vk::Context& ctx) : mCtx(ctx) {
    mPipeline = std::make_unique<vk::ComputePipeline>(
        ctx, vk::ComputePipelineDesc{
                 "denoise",
                 gt_spv_denoise_comp,
                 {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                  VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                 sizeof(sh::DenoisePush)});
}

DenoisePass::~DenoisePass() = default;

rg::TextureId DenoisePass::add(rg::RenderGraph& graph, rg::TextureId radiance,
                               const shaders::trace::CameraPush& camera, glm::vec2 gaze,
                               const DenoiseSettings& settings) const {
    if (settings.levels == 0 || settings.levels > kMaxLevels) {
        throw ArgumentError("denoise: levels must be 1 to " + std::to_string(kMaxLevels) +
                            ", got " + std::to_string(settings.levels));
    }
    const float w = static_cast<float>(graph.outputWidth());
    const float h = static_cast<float>(graph.outputHeight());
    sh::DenoisePush push{glm::vec4(w, h, gaze.x, gaze.y),
                         glm::vec4(camera.origin.w, camera.forward.w, camera.right.w, camera.up.w),
                         glm::vec4(settings.sigmaLuminance, settings.sigmaDepth, settings.foveaDeg,
                                   settings.fullDeg),
                         glm::uvec4(1u, sh::kStepVariance, 0u, 0u)};
    rg::TextureId current = radiance, guide = radiance;
    for (uint32_t level = 0; level <= settings.levels; ++level) {
        const bool first = level == 0;
        push.step = glm::uvec4(first ? 1u : 1u << (level - 1),
                               first                      ? sh::kStepVariance
                               : level == settings.levels ? sh::kStepLast
                                                          : sh::kStepFilter,
                               std::bit_cast<uint32_t>(settings.normalPower), 0u);
        const std::string name =
            first ? std::string("denoise.variance") : "denoise.level" + std::to_string(level - 1);
        const auto& data = graph.addPass<StepData>(
            name,
            [&](rg::PassBuilder& b, StepData& d) {
                d.radiance =
                    b.read(radiance, rg::Access::StorageRead, VK_FORMAT_R32G32B32A32_SFLOAT);
                d.input =
                    first ? d.radiance
                          : b.read(current, rg::Access::StorageRead, VK_FORMAT_R32G32B32A32_SFLOAT);
                d.output = b.write(b.createTexture(name, {VK_FORMAT_R32G32B32A32_SFLOAT}),
                                   rg::Access::StorageWrite);
                d.guide =
                    first
                        ? b.write(b.createTexture("denoise.guide", {VK_FORMAT_R32G32B32A32_SFLOAT}),
                                  rg::Access::StorageWrite)
                        : b.read(guide, rg::Access::StorageRead, VK_FORMAT_R32G32B32A32_SFLOAT);
            },
            [ctx = &mCtx, pipeline = mPipeline.get(),
             push](const rg::PassResources& r, const StepData& d, VkCommandBuffer cmd) {
                const rg::ResolvedTexture& out = r.texture(d.output);
                vk::DescriptorWriter writer;
                writer.storageImage(sh::kBindingRadiance, r.texture(d.radiance).view)
                    .storageImage(sh::kBindingInput, r.texture(d.input).view)
                    .storageImage(sh::kBindingOutput, out.view)
                    .storageImage(sh::kBindingGuide, r.texture(d.guide).view);
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline->handle());
                writer.push(*ctx, cmd, *pipeline);
                vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                             (out.width + sh::kGroupSizeX - 1) / sh::kGroupSizeX,
                             (out.height + sh::kGroupSizeY - 1) / sh::kGroupSizeY);
            });
        current = data.output;
        if (first) guide = data.guide;
    }
    return current;
}

} // namespace gt::passes
