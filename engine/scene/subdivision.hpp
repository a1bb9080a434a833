#pragma once
// Catmull-Clark refinement of the scene's cages with OpenSubdiv (Far), for geometric LOD by
// eccentricity (Guenter et al. 2012, section 6: "the outer layer is rendered with roughly half as
// many triangles"). Every refined vertex is placed on the limit surface with its limit normal, so
// the levels differ only by how finely they approximate one smooth surface: shading barely changes
// between them and silhouettes move by the chord error, which falls about fourfold per level.
#include <array>
#include <cstdint>
#include <vector>

#include "scene/scene.hpp"

namespace gt::scene {

// The cage refined `level` times (0: the cage's own faces), as a triangle list (3 vertices per
// triangle, counter-clockwise). Throws gt::Error naming the cage when OpenSubdiv rejects its
// topology (a non-manifold cage, a bad index).
[[nodiscard]] std::vector<Vertex> refineCage(const SubdivisionCage& cage, uint32_t level);

// Faces of the cage after `level` uniform refinements (each face of n corners becomes n quads).
[[nodiscard]] std::size_t refinedFaceCount(const SubdivisionCage& cage, uint32_t level);

// Catmull-Clark refinements of the cages at each geometric LOD level, full detail first. Each
// level halves the edge length, so rays sampling twice as far apart can take one level coarser
// (lodForPitch).
inline constexpr std::array<uint32_t, 3> kLodRefinements{3, 2, 1};

// The LOD level for rays `pitch` display pixels apart, of `levels` held: full detail below 4 px,
// then one level coarser per doubling, floor(log2(pitch / 2)), clamped. One level sooner (from
// 2 px) showed in the middle layer on builtin:gallery's near, mirror-like bronze: 3.2/255 mean
// difference at 200-300 px from the gaze, where reflections magnify the facets; so, as in the
// paper (section 6), only the outer layer and the sparsest points take coarser geometry.
[[nodiscard]] uint32_t lodForPitch(float pitch, uint32_t levels);

// Every cage of `scene` refined `level` times and appended to its triangles; the cages are gone
// afterwards (the renderer's full-detail level, refined in place).
void refineCages(Scene& scene, uint32_t level);
// The scene's geometry alone (its triangles and its cages refined `level` times), all a coarser
// LOD level's BVH and tables need: materials, lights and textures stay with the full scene.
[[nodiscard]] Scene refinedGeometry(const Scene& scene, uint32_t level);

} // namespace gt::scene
