#pragma once
// Pass `copy`: copies a texture bit for bit into a new texture of the same size and a
// size-compatible format. Its use: the tonemapped image holds sRGB-encoded bytes in an UNORM
// image (storage images cannot be sRGB); copied into an R8G8B8A8_SRGB texture the same bytes
// are read as what they are, so a blit from it into any 8-bit target (an sRGB or a linear
// OpenXR swapchain image, RGBA or BGRA) converts the colours correctly.
#include <string>

#include <vulkan/vulkan.h>

#include "render_graph/render_graph.hpp"

namespace gt::passes {

// Adds "NAME" and returns the new texture ("NAME.image", `format`, the source's size).
rg::TextureId addCopyPass(rg::RenderGraph& graph, const std::string& name, rg::TextureId source,
                          VkFormat format, uint32_t width, uint32_t height);

} // namespace gt::passes
