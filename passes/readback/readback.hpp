#pragma once
// Pass `readback`: copies a texture into a host-visible buffer the caller reads after the frame.
#include <string>

#include "render_graph/render_graph.hpp"

namespace gt::passes {

// Adds "readback.<name>" copying `texture` into `hostBuffer` (imported, tightly packed rows).
void addReadbackPass(rg::RenderGraph& graph, const std::string& name, rg::TextureId texture,
                     rg::BufferId hostBuffer);

} // namespace gt::passes
