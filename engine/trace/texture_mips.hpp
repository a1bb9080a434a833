#pragma once
// Mip chains for the path integrator's texture filtering by ray footprint (ray cones): each
// level halves the one above (at least 1 texel on a side), every texel the mean of the 2x2
// texels it covers (at an odd side's end 3, so that none is left out). Colour textures average in
// linear light, data textures (metallic-roughness, normal, transmission) as stored.
#include <cstdint>
#include <vector>

#include "scene/scene.hpp"

namespace gt::trace {

// Levels of a w x h texture's full chain, level 0 included: 1 + floor(log2(max(w, h))).
[[nodiscard]] uint32_t mipLevelCount(uint32_t width, uint32_t height) noexcept;

// Levels 1 to the last of `texture`'s chain, one after another, packed as scene::Texture's
// texels are.
[[nodiscard]] std::vector<uint32_t> mipChain(const scene::Texture& texture, bool srgb);

} // namespace gt::trace
