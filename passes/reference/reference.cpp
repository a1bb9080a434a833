#include "reference/reference.hpp"

#include "core/error.hpp"
#include "reference_comp.h"
#include "reference_shared.h"
#include "trace/gpu_scene.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::reference;

ReferencePass::ReferencePass(vk::Context& ctx) : mCtx(ctx) {
    (void)pipeline(false, false); // the common case, so that a bad shader fails at construction
}

const vk::ComputePipeline& ReferencePass::pipeline(bool alphaMask, bool dynamic,
                                                   const trace::IntegratorSettings& i) const {
    const bool direct = i.integrator == trace::Integrator::Direct; // one pipeline, any bounces
    auto& slot = mPipelines[{alphaMask, dynamic, static_cast<uint32_t>(i.integrator),
                             direct ? 0u : i.bounces, direct ? 0.0f : i.fireflyClamp}];
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
    sh::ReferencePush push{cam.origin, cam.forward, cam.right, cam.up,
                           glm::uvec4(w, h, settings.raysPerPixel, settings.frameSeed)};
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
         scene = &scene, push](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            // A scene that does not move never writes the motion binding.
            const VkImageView output = r.texture(d.output).view;
            trace::dispatchImageTrace(
                *ctx, cmd, *pipeline, *scene,
                {{sh::kBindingOutput, output},
                 {sh::kBindingMotionOutput, d.motion ? r.texture(*d.motion).view : output}},
                std::as_bytes(std::span(&push, 1)), {push.params.x, push.params.y},
                {sh::kGroupSizeX, sh::kGroupSizeY});
        });
    return {data.output, data.motion};
}

} // namespace gt::passes
