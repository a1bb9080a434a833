#pragma once
// glTF 2.0 (.gltf and .glb) through tinygltf: triangle meshes (indexed or not, strips and fans
// converted), node transforms, base-colour factor and texture (its UV set and
// KHR_texture_transform baked into the UVs), metallic/roughness factors, emissive (with
// KHR_materials_emissive_strength), KHR_materials_unlit, cameras, KHR_lights_punctual,
// KHR_mesh_quantization and sparse accessors. Every accessor is bounds-checked; a broken or
// unsupported file throws gt::LoadError with one line naming the file and the problem.
#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace gt::scene {

struct GltfLoadReport {
    std::vector<std::string> warnings; // e.g. skipped line primitives, undecodable textures
};

[[nodiscard]] Scene loadGltf(const std::filesystem::path& path, GltfLoadReport* report = nullptr);

// "builtin:NAME", "cubemap:FILE" (an environment image or cube faces, see environment.hpp)
// or a .gltf/.glb path.
[[nodiscard]] Scene loadScene(const std::string& spec, GltfLoadReport* report = nullptr);

} // namespace gt::scene
