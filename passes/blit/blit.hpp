#pragma once
// Pass `blit`: copies a texture into a rectangle of another, scaled with a linear filter (a view
// into its place on a window or a side-by-side panel). Formats may differ in channel order
// (RGBA into a BGRA swapchain image).
// Pass `copy` (same file: the same transfer, without conversion): copies a texture bit for bit
// into a new texture of the same size and a size-compatible format. Its use: the tonemapped
// image holds sRGB-encoded bytes in an UNORM image (storage images cannot be sRGB); copied into
// an R8G8B8A8_SRGB texture the same bytes are read as what they are, so a blit from it into any
// 8-bit target (an sRGB or a linear OpenXR swapchain image, RGBA or BGRA) converts correctly.
#include <string>

#include <vulkan/vulkan.h>

#include "render_graph/render_graph.hpp"

namespace gt::passes {

// Adds "NAME" (e.g. "present.blit"); returns the destination's new version.
rg::TextureId addBlitPass(rg::RenderGraph& graph, const std::string& name, rg::TextureId source,
                          rg::TextureId destination, VkRect2D rect);

// Adds "NAME" and returns the new texture ("NAME.image", `format`, width x height).
rg::TextureId addCopyPass(rg::RenderGraph& graph, const std::string& name, rg::TextureId source,
                          VkFormat format, uint32_t width, uint32_t height);

} // namespace gt::passes
