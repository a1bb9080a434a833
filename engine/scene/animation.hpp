#pragma once
// Scenes that move: the glTF node hierarchy kept beside the flattened static triangles, with
// animations (glTF 2.0, 3.11: node translation, rotation, scale and morph weights; STEP, LINEAR
// and CUBICSPLINE samplers), skins (3.7.3: joints, inverse bind matrices, 4 weights a vertex)
// and morph targets (3.7.2.2: positions and normals). A Rig holds what a pose needs; a Pose is
// the rig at one instant; deformInstance() turns one mesh instance into the triangles the
// bottom-level BVH of that instance is built or refitted over.
//
// What the loader puts here: every mesh instance whose world transform an animation can change
// (the node or one of its ancestors is a channel's target), that is skinned, or that has morph
// targets. Everything else stays flattened in Scene::vertices, as for a scene without
// animation, so static scenes are unchanged.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "scene/scene.hpp"

namespace gt::scene {

enum class Interpolation : uint8_t { Step, Linear, CubicSpline };
enum class AnimatedPath : uint8_t { Translation, Rotation, Scale, Weights };

// One glTF animation sampler, validated by the loader (times finite and strictly increasing,
// values finite, counts matching).
struct AnimationSampler {
    std::vector<float> times; // seconds, strictly increasing, at least one key
    // Per key `components` floats (3 for translation and scale, 4 for rotation as x, y, z, w,
    // the morph target count for weights); CUBICSPLINE stores in-tangent, value, out-tangent
    // per key (3 * components floats), as glTF does.
    std::vector<float> values;
    uint32_t components = 0;
    Interpolation interpolation = Interpolation::Linear;
};

struct AnimationChannel {
    uint32_t sampler = 0; // into Animation::samplers
    uint32_t node = 0;    // into Rig::nodes
    AnimatedPath path = AnimatedPath::Translation;
};

struct Animation {
    std::string name;
    std::vector<AnimationSampler> samplers;
    std::vector<AnimationChannel> channels;
    float duration = 0.0f; // the last key time over its samplers; playback loops over it
};

struct NodeTrs {
    glm::vec3 translation{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f}; // w, x, y, z (glm's constructor order)
    glm::vec3 scale{1.0f};
};

struct RigNode {
    std::string name;
    int parent = -1; // parents come before their children in Rig::nodes
    // glTF's `matrix` (such a node is never an animation target) or its TRS.
    bool hasMatrix = false;
    glm::mat4 matrix{1.0f};
    NodeTrs rest;
    std::vector<float> weights; // default morph weights (the node's, else its mesh's)
};

// Per vertex of a RigMesh: displacements added with the target's weight (glTF 3.7.2.2).
struct MorphTarget {
    std::vector<glm::vec3> positions; // empty: the target moves no position
    std::vector<glm::vec3> normals;   // empty: the target turns no normal
};

// A glTF mesh (its triangle primitives together) in its own space: 3 vertices per triangle.
struct RigMesh {
    std::string name;
    std::vector<Vertex> vertices;
    std::vector<uint32_t> triangleMaterial; // into Scene::materials
    std::vector<glm::uvec4> joints;         // per vertex, into Skin::joints; empty: not skinned
    std::vector<glm::vec4> weights;         // per vertex, summing to 1
    std::vector<MorphTarget> targets;
};

struct Skin {
    std::string name;
    std::vector<uint32_t> joints;       // into Rig::nodes
    std::vector<glm::mat4> inverseBind; // one per joint (identity when the file gives none)
};

// A mesh placed by a node: one bottom-level BVH in the two-level structure.
struct MeshInstance {
    uint32_t node = 0;
    uint32_t mesh = 0;
    int skin = -1; // into Rig::skins
};

struct Rig {
    std::vector<RigNode> nodes;
    std::vector<RigMesh> meshes;
    std::vector<MeshInstance> instances;
    std::vector<Skin> skins;
    std::vector<Animation> animations;
    // The node of Scene::camera when it came from the file (-1: none, or it is not animated).
    int cameraNode = -1;
    // Per Scene::lights entry: its node (-1: a light that does not move).
    std::vector<int> lightNodes;

    [[nodiscard]] bool empty() const noexcept { return instances.empty() && animations.empty(); }
};

// Which animations play: "all", "none", a name or an index (the command line's --animation).
struct AnimationChoice {
    enum class Kind : uint8_t { All, None, One };
    Kind kind = Kind::All;
    uint32_t index = 0; // Kind::One
};
// Resolves a name or a decimal index against the rig; throws gt::Error naming the value when
// there is no such animation.
[[nodiscard]] AnimationChoice chooseAnimation(const Rig& rig, const std::string& nameOrIndex);

// The rig at one instant.
struct Pose {
    double seconds = 0.0;
    std::vector<glm::mat4> world;            // per node
    std::vector<std::vector<float>> weights; // per node: its morph weights
};

// Samples every playing animation at `seconds` (each looping over its own duration; before the
// first key a sampler holds its first value, glTF 3.11) over the nodes' rest transforms, then
// composes the world matrices down the hierarchy.
[[nodiscard]] Pose evaluatePose(const Rig& rig, const AnimationChoice& playing, double seconds);
// The same into an existing pose, reusing its storage (no allocation per frame once sized).
void evaluatePose(const Rig& rig, const AnimationChoice& playing, double seconds, Pose& pose);

// One sampler's value at time t (already looped): `out` receives `components` floats. LINEAR
// rotations are spherical (slerp, shortest path), CUBICSPLINE rotations normalised (glTF
// Appendix C).
void sampleAnimation(const AnimationSampler& sampler, AnimatedPath path, float t,
                     std::span<float> out);

// Whether the instance's vertices change with the pose (skinned or morphed): its bottom-level
// tree is refitted per frame, not only moved.
[[nodiscard]] bool deforms(const Rig& rig, const MeshInstance& instance) noexcept;

// The instance's object-to-world transform at `pose`: its node's world matrix, or identity for a
// skinned instance (skinning puts vertices in world space; glTF 3.7.3.3 ignores the mesh
// node's transform).
[[nodiscard]] glm::mat4 instanceTransform(const Rig& rig, const MeshInstance& instance,
                                          const Pose& pose);

// The instance's triangles at `pose`, in the space instanceTransform() maps to the world: morph
// targets applied with the node's weights, then linear blend skinning with the joints' world
// matrices times their inverse bind matrices, normals by the blended matrix's inverse transpose
// and renormalised. `out` is resized to the mesh's vertex count; no other allocation once `out`
// and the calling thread's scratch are sized, and calls on several threads are independent.
void deformInstance(const Rig& rig, const MeshInstance& instance, const Pose& pose,
                    std::vector<Vertex>& out);

} // namespace gt::scene
