#pragma once
// Pass `blit`: copies a texture into a rectangle of another, scaled with a linear filter (a view
// into its place on a window or a side-by-side panel). Formats may differ in channel order
// (RGBA into a BGRA swapchain image).
#include <string>

#include <vulkan/vulkan.h>

#include "render_graph/render_graph.hpp"

namespace gt::passes {

// Adds "NAME" (e.g. "present.blit"); returns the destination's new version.
rg::TextureId addBlitPass(rg::RenderGraph& graph, const std::string& name, rg::TextureId source,
                          rg::TextureId destination, VkRect2D rect);

} // namespace gt::passes
