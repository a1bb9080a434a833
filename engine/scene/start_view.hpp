#pragma once
// Where a viewer starts in a scene whose file places no camera. Framing the bounds from outside
// (the loader's default) shows the outer walls of an interior; if the scene encloses its own
// centre (most rays from there hit something), the start is inside: above the floor under the
// centre at eye height (1.6 scene units, or 60 % of a lower room's height), looking along the
// horizontal direction with the most free space.
#include <optional>

#include "scene/bvh.hpp"
#include "scene/scene.hpp"

namespace gt::scene {

[[nodiscard]] std::optional<Camera> insideStartView(const Scene& scene, const Bvh& bvh);

} // namespace gt::scene
