#include "reference/reference.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "reference_comp.h"
#include "reference_shared.h"
#include "trace/gpu_scene.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::reference;

namespace {

// Between two dispatches of one pixel's rays: the later adds to what the earlier stored.
void shareBarrier(VkCommandBuffer cmd) {
    VkMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    barrier.srcStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    barrier.srcAccessMask = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
    barrier.dstStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    barrier.dstAccessMask =
        VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.memoryBarrierCount = 1;
    dep.pMemoryBarriers = &barrier;
    vkCmdPipelineBarrier2(cmd, &dep);
}

} // namespace

ReferencePass::ReferencePass(vk::Context& ctx) : mCtx(ctx) {
    (void)pipeline(false, false); // the common case, so that a bad shader fails at construction
}

const vk::ComputePipeline& ReferencePass::pipeline(bool alphaMask, bool dynamic,
                                                   const trace::IntegratorSettings& i) const {
    const bool direct = i.integrator == trace::Integrator::Direct; // one pipeline, any bounces
    auto& slot = mPipelines[{alphaMask, dynamic, static_cast<uint32_t>(i.integrator),
                             direct ? 0u : i.bounces, direct ? 0.0f : i.fireflyClamp,
                             direct ? 0u : static_cast<uint32_t>(i.sequence)}];
    if (!slot) {
        const std::vector<VkDescriptorType> bindings =
            trace::tracingBindings({VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // sh::kBindingOutput
                                    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}); // kBindingMotionOutput
        slot = std::make_unique<vk::ComputePipeline>(
            mCtx, vk::ComputePipelineDesc{
                      "reference.trace", gt_spv_reference_comp, bindings, sizeof(sh::ReferencePush),
                      trace::tracingSpecialization({alphaMask ? 1u : 0u}, dynamic, i)});
    }
    return *slot;
}

ReferencePass::~ReferencePass() = default;

rg::TextureId ReferencePass::add(rg::RenderGraph& graph, const trace::GpuScene& scene,
                                 const shaders::trace::CameraPush& cam,
                                 const ReferenceSettings& settings) const {
    return addImage(graph, scene, cam, settings).radiance;
}

ReferenceImage ReferencePass::addImage(rg::RenderGraph& graph, const trace::GpuScene& scene,
                                       const shaders::trace::CameraPush& cam,
                                       const ReferenceSettings& settings) const {
    if (settings.raysPerPixel == 0) throw ArgumentError("rays per pixel must be at least 1");
    struct Data {
        rg::TextureId output;
        std::optional<rg::TextureId> motion;
    };
    const bool dynamic = scene.dynamic();
    const uint32_t w = graph.outputWidth(), h = graph.outputHeight();
    const sh::ReferencePush push{cam.origin,
                                 cam.forward,
                                 cam.right,
                                 cam.up,
                                 glm::uvec4(w, h, settings.raysPerPixel, settings.frameSeed),
                                 glm::uvec4(0u, settings.raysPerPixel, 0u, 0u)};
    const uint32_t perDispatch = settings.integrator.integrator == trace::Integrator::Direct
                                     ? settings.raysPerPixel
                                     : sh::kPathRaysPerDispatch;
    const auto& data = graph.addPass<Data>(
        "reference.trace",
        [&](rg::PassBuilder& b, Data& d) {
            d.output =
                b.write(b.createTexture("reference.radiance", {VK_FORMAT_R32G32B32A32_SFLOAT}),
                        rg::Access::StorageWrite);
            if (dynamic) {
                d.motion =
                    b.write(b.createTexture("reference.motion", {VK_FORMAT_R32G32B32A32_SFLOAT}),
                            rg::Access::StorageWrite);
            }
        },
        [ctx = &mCtx, pipeline = &pipeline(scene.alphaMasked(), dynamic, settings.integrator),
         scene = &scene, push,
         perDispatch](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            // A scene that does not move never writes the motion binding.
            const VkImageView output = r.texture(d.output).view;
            for (uint32_t first = 0; first < push.params.z; first += perDispatch) {
                if (first > 0) shareBarrier(cmd);
                sh::ReferencePush share = push;
                share.range =
                    glm::uvec4(first, std::min(perDispatch, push.params.z - first), 0u, 0u);
                trace::dispatchImageTrace(
                    *ctx, cmd, *pipeline, *scene,
                    {{sh::kBindingOutput, output},
                     {sh::kBindingMotionOutput, d.motion ? r.texture(*d.motion).view : output}},
                    std::as_bytes(std::span(&share, 1)), {push.params.x, push.params.y},
                    {sh::kGroupSizeX, sh::kGroupSizeY});
            }
        });
    return {data.output, data.motion};
}

} // namespace gt::passes
