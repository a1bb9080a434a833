#include "ui_overlay.hpp"

#include "overlay/overlay.hpp"

namespace gt::render {

UiOverlay::UiOverlay(vk::Context& ctx, VkFormat format)
    : mPass(std::make_unique<passes::OverlayPass>(ctx, format)) {}

UiOverlay::~UiOverlay() = default;

VkRenderPass UiOverlay::renderPass() const noexcept {
    return mPass->renderPass();
}

rg::TextureId UiOverlay::add(rg::RenderGraph& graph, rg::TextureId image, Draw draw) {
    return mPass->add(graph, image, std::move(draw));
}

void UiOverlay::releaseFramebuffers() noexcept {
    mPass->releaseFramebuffers();
}

} // namespace gt::render
