#include "layers/layers.hpp"

#include <string>
#include <vector>

#include "core/error.hpp"
#include "layers_compose_comp.h"
#include "layers_shared.h"
#include "layers_trace_comp.h"
#include "trace/gpu_scene.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::layers;

LayersPass::LayersPass(vk::Context& ctx) : mCtx(ctx) {
    (void)tracePipeline(false, false); // bad shaders fail at construction
    (void)composePipeline(3);
}

const vk::ComputePipeline& LayersPass::composePipeline(std::size_t layers) const {
    auto& slot = mCompose.at(layers - 1);
    if (!slot) {
        std::vector<VkDescriptorType> bindings(sh::kMaxLayers + 1,
                                               VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
        slot = std::make_unique<vk::ComputePipeline>(
            mCtx, vk::ComputePipelineDesc{"layers.compose",
                                          gt_spv_layers_compose_comp,
                                          bindings,
                                          sizeof(sh::LayerComposePush),
                                          {static_cast<uint32_t>(layers)}});
    }
    return *slot;
}

LayersPass::~LayersPass() = default;

const vk::ComputePipeline& LayersPass::tracePipeline(bool alphaMask, bool dynamic) const {
    auto& slot = mTrace[(alphaMask ? 1 : 0) + (dynamic ? 2 : 0)];
    if (!slot) {
        const std::vector<VkDescriptorType> bindings =
            trace::tracingBindings({VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // kBindingTraceOutput
                                    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}); // kBindingTraceMotion
        slot = std::make_unique<vk::ComputePipeline>(
            mCtx,
            vk::ComputePipelineDesc{"layers.trace", gt_spv_layers_trace_comp, bindings,
                                    sizeof(sh::LayerTracePush),
                                    trace::tracingSpecialization({alphaMask ? 1u : 0u}, dynamic)});
    }
    return *slot;
}

rg::TextureId LayersPass::addTrace(rg::RenderGraph& graph, const trace::GpuScene& scene,
                                   const shaders::trace::CameraPush& cam, uint32_t width,
                                   uint32_t height, uint32_t raysPerPixel, uint32_t lod) const {
    return addTraceImage(graph, scene, cam, width, height, raysPerPixel, lod).radiance;
}

TracedLayer LayersPass::addTraceImage(rg::RenderGraph& graph, const trace::GpuScene& scene,
                                      const shaders::trace::CameraPush& cam, uint32_t width,
                                      uint32_t height, uint32_t raysPerPixel, uint32_t lod) const {
    if (raysPerPixel == 0) {
        throw ArgumentError("rays per layer pixel must be at least 1");
    }
    if (width == 0 || height == 0) {
        throw ArgumentError("an eccentricity layer of zero size");
    }
    struct Data {
        rg::TextureId output;
        std::optional<rg::TextureId> motion;
    };
    const bool dynamic = scene.dynamic();
    const sh::LayerTracePush push{cam.origin, cam.forward, cam.right, cam.up,
                                  glm::uvec4(width, height, raysPerPixel, lod)};
    const auto& data = graph.addPass<Data>(
        "layers.trace",
        [&](rg::PassBuilder& b, Data& d) {
            d.output =
                b.write(b.createTexture("layers.radiance",
                                        {VK_FORMAT_R32G32B32A32_SFLOAT, rg::SizeMode::Absolute,
                                         static_cast<float>(width), static_cast<float>(height)}),
                        rg::Access::StorageWrite);
            if (dynamic) {
                d.motion = b.write(
                    b.createTexture("layers.motion",
                                    {VK_FORMAT_R32G32B32A32_SFLOAT, rg::SizeMode::Absolute,
                                     static_cast<float>(width), static_cast<float>(height)}),
                    rg::Access::StorageWrite);
            }
        },
        [ctx = &mCtx, pipeline = &tracePipeline(scene.alphaMasked(), dynamic), scene = &scene,
         push](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            // A scene that does not move never writes the motion binding.
            const VkImageView output = r.texture(d.output).view;
            trace::dispatchImageTrace(
                *ctx, cmd, *pipeline, *scene,
                {{sh::kBindingTraceOutput, output},
                 {sh::kBindingTraceMotion, d.motion ? r.texture(*d.motion).view : output}},
                std::as_bytes(std::span(&push, 1)), {push.params.x, push.params.y},
                {sh::kGroupSizeX, sh::kGroupSizeY});
        });
    return {data.output, data.motion};
}

rg::TextureId LayersPass::addCompose(rg::RenderGraph& graph, std::span<const ComposedLayer> layers,
                                     glm::vec2 gaze, float transition) const {
    if (layers.empty() || layers.size() > sh::kMaxLayers) {
        throw ArgumentError("layers.compose: " + std::to_string(layers.size()) +
                            " layers (1 to 4)");
    }
    sh::LayerComposePush push{};
    push.gaze = glm::vec4(gaze, 0.0f, transition);
    for (std::size_t i = 0; i < layers.size(); ++i) {
        push.layer[i] = glm::vec4(layers[i].origin, layers[i].pitch, layers[i].radiusPx);
    }
    struct Data {
        std::array<rg::TextureId, sh::kMaxLayers> layers;
        std::size_t count = 0;
        rg::TextureId output;
    };
    const auto& data = graph.addPass<Data>(
        "layers.compose",
        [&](rg::PassBuilder& b, Data& d) {
            d.count = layers.size();
            for (std::size_t i = 0; i < layers.size(); ++i) {
                d.layers[i] = b.read(layers[i].image, rg::Access::StorageRead);
            }
            d.output = b.write(b.createTexture("layers.composed", {VK_FORMAT_R32G32B32A32_SFLOAT}),
                               rg::Access::StorageWrite);
        },
        [ctx = &mCtx, pipeline = &composePipeline(layers.size()),
         push](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            const rg::ResolvedTexture& out = r.texture(d.output);
            vk::DescriptorWriter writer;
            for (uint32_t i = 0; i < sh::kMaxLayers; ++i) {
                // Slots past the count repeat the outer layer (never read by the shader).
                const std::size_t src = i < d.count ? i : d.count - 1;
                writer.storageImage(sh::kBindingLayer0 + i, r.texture(d.layers[src]).view);
            }
            writer.storageImage(sh::kBindingComposeOutput, out.view);
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push), (out.width + 7) / 8,
                         (out.height + 7) / 8);
        });
    return data.output;
}

} // namespace gt::passes
