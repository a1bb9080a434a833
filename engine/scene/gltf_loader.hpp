#pragma once
// glTF 2.0 (.gltf and .glb) through tinygltf: triangle meshes (indexed or not, strips and fans
// converted), node transforms, base-colour factor and texture (its UV set and
// KHR_texture_transform baked into the UVs), metallic/roughness factors, emissive (with
// KHR_materials_emissive_strength), KHR_materials_unlit, cameras, KHR_lights_punctual,
// KHR_mesh_quantization and sparse accessors. Every accessor is bounds-checked; a broken or
// unsupported file throws gt::LoadError with one line naming the file and the problem.
//
// A file with animations, skins or morph targets also gets Scene::rig (animation.hpp): every
// node (parents first), the skins, the animations (validated: keys increasing, finite, counts
// matching), and as instances in mesh space every mesh that an animation moves (its node or an
// ancestor is a translation, rotation or scale target), that is skinned or that has morph
// targets; those meshes are not in Scene::vertices. Every other mesh is flattened as it is in a
// file without animation, which loads exactly as it did before rigs existed.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "limits.hpp"
#include "scene/scene.hpp"

namespace gt::scene {

struct GltfLoadReport {
    std::vector<std::string> warnings; // e.g. skipped line primitives, undecodable textures
};

// What a file may ask of the loader. The limits are counted before anything is expanded: a node
// graph whose levels each reference the next twice expands to 2^24 instances from 25 nodes.
struct GltfLoadOptions {
    // 200 times the largest shared scene (the flight helmet, 95 k triangles).
    double maxTriangles = 20e6;
    // Node instances after expansion: a million is far beyond hand-made scenes (Sponza and the
    // shared scenes have under a thousand) and still visited in well under a second.
    double maxInstances = 1e6;
    // Decoded base-colour textures, all together (each image is also limited to
    // image::kMaxImageSide a side, checked from its header before decoding).
    std::uint64_t maxTextureBytes = io::limits::kGltfTextureBytes;
    // Buffers and images may lie anywhere, not only in the model's folder and below it.
    bool anyPath = false;
};

[[nodiscard]] Scene loadGltf(const std::filesystem::path& path, GltfLoadReport* report = nullptr,
                             const GltfLoadOptions& options = {});

// "builtin:NAME", "cubemap:FILE" (an environment image or cube faces, see environment.hpp)
// or a .gltf/.glb path.
[[nodiscard]] Scene loadScene(const std::string& spec, GltfLoadReport* report = nullptr,
                              const GltfLoadOptions& options = {});

} // namespace gt::scene
