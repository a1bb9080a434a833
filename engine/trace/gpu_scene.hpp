#pragma once
// The scene packed for the compute-shader tracer: BVH nodes, triangles, shading data,
// materials, lights and textures in uniform texel buffers (texel buffers beat storage buffers
// by 1.6x for BVH nodes on lavapipe, docs/lavapipe.md), plus a small uniform block.
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "scene/bvh.hpp"
#include "scene/dynamic_geometry.hpp"
#include "scene/scene.hpp"
#include "trace/integrator.hpp"
#include "trace_shared.h"
#include "vk/resources.hpp"

namespace gt::vk {
class Context;
class DescriptorWriter;
class ComputePipeline;
} // namespace gt::vk

namespace gt::trace {

// CPU-side packing (plain data, unit-testable).
struct PackedScene {
    std::vector<glm::vec4> nodes;
    std::vector<glm::vec4> triangles;
    std::vector<glm::vec4> shading;
    std::vector<glm::vec4> materials;
    // The emissive triangles' alias table (SceneUniforms::emitters), uploaded after the
    // materials in their table.
    std::vector<glm::vec4> emitters;
    std::vector<glm::vec4> lights;
    std::vector<uint32_t> texels;
    std::vector<glm::uvec4> textureInfo;
    std::vector<glm::vec4> environment;
    shaders::trace::SceneUniforms uniforms{};
    bool alphaMasked = false; // a material has alphaMode MASK
};

// The texels and texture info a device holds: `p`'s, or where they exceed `maxTexels` (the
// device's maxTexelBufferElements) each texture's level 0 alone; an Error naming both counts
// when even that does not fit.
struct FittedTextures {
    std::vector<uint32_t> texels;
    std::vector<glm::uvec4> info;
};
[[nodiscard]] FittedTextures fitTextures(const PackedScene& p, uint64_t maxTexels);

[[nodiscard]] PackedScene packScene(const scene::Scene& scene, const scene::Bvh& bvh);

// One geometric LOD level: the scene with its cages refined for it, and its BVH.
struct LodGeometry {
    const scene::Scene* scene;
    const scene::Bvh* bvh;
};
// Every level in one set of tables: materials, lights and textures from the first (levels share
// them), then each level's nodes, triangles and shading appended, its node and triangle indices
// offset, its root in uniforms.lodRoots. At most shaders::trace::kLodLevels levels.
[[nodiscard]] PackedScene packScene(std::span<const LodGeometry> levels);

// Where the two-level part of a scene that moves lies in its tables (after the static levels):
// in the nodes table the bottom levels' nodes (rigid meshes' first, then each deforming
// instance's, with room for a rebuild: 2n - 1 nodes for n triangles), the top level (room for
// DynamicGeometry::topLevelCapacity() nodes) and the instance records (trace_shared.h); in the
// triangles and shading tables the bottom levels' triangles, then in the triangles table each
// deforming instance's previous triangles. Everything from the first deforming bottom level on
// (nodes, triangles, shading), and the lights, changes with the pose.
struct DynamicLayout {
    std::vector<uint32_t> bottomRoot;       // per bottom level: its root node
    std::vector<uint32_t> bottomTriangle;   // per bottom level: its first triangle
    std::vector<uint32_t> previousTriangle; // per instance: first previous one, or kNoPrevious
    uint32_t topRoot = 0;
    uint32_t instanceTexel = 0; // first texel of the instance records in the nodes table
    // First texel of each table that changes with the pose (the end of each table is dynamic).
    uint32_t dynamicNodeTexel = 0, dynamicTriangleTexel = 0, dynamicShadingTexel = 0;
};

// The static levels as packScene(levels), then the two-level part at its pose (DynamicLayout).
[[nodiscard]] PackedScene packScene(std::span<const LodGeometry> levels,
                                    const scene::DynamicGeometry& dynamic, DynamicLayout& layout);
// Rewrites what changes with the pose in `p` (packed by the overload above with `layout`):
// deforming bottom levels, the top level, the instance records, the previous triangles, and the
// lights that have a node (Rig::lightNodes, glTF lights shine down their node's -Z).
void repackDynamic(const scene::Scene& scene, const scene::DynamicGeometry& dynamic,
                   const DynamicLayout& layout, PackedScene& p);

class GpuScene {
public:
    GpuScene(vk::Context& ctx, const scene::Scene& scene, const scene::Bvh& bvh);
    GpuScene(vk::Context& ctx, std::span<const LodGeometry> levels);
    // A scene that moves: the tables that change with the pose (nodes, triangles, shading,
    // lights) are host-visible, one copy per frame in flight (`copies`), written by update()
    // and prepare(); the rest as for a static scene. `levels[0].scene` must outlive this.
    GpuScene(vk::Context& ctx, std::span<const LodGeometry> levels,
             const scene::DynamicGeometry& dynamic, uint32_t copies);
    ~GpuScene();
    GpuScene(const GpuScene&) = delete;
    GpuScene& operator=(const GpuScene&) = delete;
    // Adds the nine scene bindings (trace::kBinding*) to a descriptor update.
    void bind(vk::DescriptorWriter& writer) const;
    [[nodiscard]] std::size_t bytes() const noexcept { return mBytes; }
    // Tracing passes build their pipelines with kAlphaMask (trace.glsl) set to this.
    [[nodiscard]] bool alphaMasked() const noexcept { return mAlphaMasked; }
    // Geometric LOD levels held (1 for a scene without subdivision cages).
    [[nodiscard]] uint32_t lodLevels() const noexcept { return mLodLevels; }
    // Whether the scene has a two-level part: tracing passes set kSpecDynamic (trace.glsl's
    // kDynamic) to this.
    [[nodiscard]] bool dynamic() const noexcept { return mDynamic != nullptr; }
    // The tables' contents at `dynamic`'s current pose (call after DynamicGeometry::update);
    // no copy is written until prepare().
    void update(const scene::DynamicGeometry& dynamic);
    // Makes copy `copy` (the frame ring's slot of the frame about to be recorded: the GPU no
    // longer reads it) hold the latest update() and binds it from now on.
    void prepare(uint32_t copy);
    [[nodiscard]] uint32_t boundCopy() const noexcept { return mBound; }

private:
    struct Table {
        vk::Buffer buffer;
        vk::BufferView view;
    };
    Table upload(vk::Context& ctx, const void* data, std::size_t bytes, VkFormat format,
                 const char* name);
    struct DynamicTables; // the host-visible copies of a scene that moves
    void uploadShared(vk::Context& ctx, const PackedScene& p);
    Table mNodes, mTriangles, mShading, mMaterials, mLights, mTexels, mTextureInfo, mEnvironment;
    std::unique_ptr<DynamicTables> mDynamic;
    uint32_t mBound = 0;
    vk::Buffer mUniforms;
    std::size_t mBytes = 0;
    bool mAlphaMasked = false;
    uint32_t mLodLevels = 1;
};

// The descriptor types of a tracing pass's pipeline: the scene's nine bindings (GpuScene::bind,
// set 0, bindings 0-8), then the pass's own from binding 9 on.
[[nodiscard]] std::vector<VkDescriptorType>
tracingBindings(std::initializer_list<VkDescriptorType> passBindings);

// A tracing pipeline's specialisation constants: the pass's own (constant_id 0 = kAlphaMask
// and on, as before) padded to kSpecDynamic, which takes `dynamic` (GpuScene::dynamic()), and
// for an integrator other than the direct one its constants (kSpecIntegrator and on); the
// direct integrator's pipelines leave those at their defaults, as they were built before.
[[nodiscard]] std::vector<uint32_t>
tracingSpecialization(std::vector<uint32_t> passConstants, bool dynamic,
                      const IntegratorSettings& integrator = {});

// A storage image a tracing shader writes, at its binding.
struct TracedImage {
    uint32_t binding;
    VkImageView view;
};
// Records a tracing shader that writes images (its radiance, and the motion of a scene that
// moves): the scene's bindings and `outputs`, `push`, and one thread per pixel of `extent` in
// groups of `group`.
void dispatchImageTrace(vk::Context& ctx, VkCommandBuffer cmd, const vk::ComputePipeline& pipeline,
                        const GpuScene& scene, std::initializer_list<TracedImage> outputs,
                        std::span<const std::byte> push, VkExtent2D extent, VkExtent2D group);

// The camera as push-constant vectors, for an image of the given aspect ratio.
[[nodiscard]] shaders::trace::CameraPush cameraPush(const scene::Camera& camera, float aspect);

// An off-axis frustum as the tangents of the angles from the view axis to its four edges, as
// OpenXR's XrFovf gives them (left and down negative when the axis lies inside the frustum).
struct FrustumTangents {
    float left = -1.0f, right = 1.0f, up = 1.0f, down = -1.0f;
    // The symmetric frustum of a vertical field of view and an aspect ratio (width / height).
    [[nodiscard]] static FrustumTangents symmetric(float yfov, float aspect);
    [[nodiscard]] bool valid() const noexcept; // finite, left < right, down < up
};

// The pose of `camera` (its yfov is not used) with the frustum `t`: the push holds the half
// extents as tan(half height) and aspect, and the frustum's centre in right.w and up.w. (Views
// with a symmetric frustum keep using cameraPush(camera, aspect), whose rounding the stored
// reference images were made with.)
[[nodiscard]] shaders::trace::CameraPush cameraPush(const scene::Camera& camera,
                                                    const FrustumTangents& t);

} // namespace gt::trace
