#pragma once
// The two-level acceleration structure of a scene that moves: one bottom-level BVH per rig mesh
// (shared by the rigid instances of that mesh; one per instance for skinned or morphed ones,
// refitted every frame and rebuilt when refitting has let its SAH cost grow past a measured
// bound), and a top level over the instances' world bounds, rebuilt every frame. The static
// triangles (Scene::vertices) keep their own single tree (Bvh), exactly as in a scene where
// nothing moves; rays test both.
//
// Each frame's update keeps the previous frame's transforms and deformed triangles, which the
// tracer reads to give every hit its motion (where the surface point was one frame ago).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "scene/animation.hpp"
#include "scene/bvh.hpp"

namespace gt::scene {

struct DynamicHit {
    float t = std::numeric_limits<float>::infinity();
    uint32_t instance = ~0u; // into Rig::instances
    uint32_t triangle = ~0u; // in the instance's bottom-level tree's triangle order
    float u = 0.0f, v = 0.0f;
    [[nodiscard]] bool valid() const noexcept { return instance != ~0u; }
};

// Per-frame costs on the CPU, reported by bench apart from tracing.
struct DynamicUpdateTimings {
    double poseMs = 0.0;     // evaluatePose
    double deformMs = 0.0;   // morph targets and skinning
    double refitMs = 0.0;    // bottom-level refits
    double rebuildMs = 0.0;  // bottom-level rebuilds (refit quality past the bound)
    double topLevelMs = 0.0; // the top level over the instances
    uint32_t refits = 0;
    uint32_t rebuilds = 0;
};

class DynamicGeometry {
public:
    // A refitted tree is rebuilt once its SAH cost exceeds this multiple of its cost when last
    // built (bvh.hpp's BvhBuildStats::sahCost). The ratio to the build's cost overstates what
    // refitting loses: a skinned bar of 2,400 triangles bent about its middle refits to 0.54x
    // (1.5 rad) and 1.58x (3 rad, folded back) of its build's cost, yet stays within 1.04-1.12x
    // of a fresh build of the same pose at every angle. At 2, bends and folds keep their tree,
    // and a tree whose boxes have come apart (triangles scattered, a limb swept through the
    // mesh) is rebuilt.
    static constexpr float kRebuildSahRatio = 2.0f;

    // Builds every bottom-level tree at the pose of `seconds` (the previous frame is that pose
    // too: no motion on the first frame).
    DynamicGeometry(std::shared_ptr<const Rig> rig, AnimationChoice playing, double seconds);

    // The pose at `seconds`: the current frame becomes the previous one; deforming instances
    // are deformed and refitted (or rebuilt), and the top level is rebuilt.
    void update(double seconds);
    // Starts over at `seconds` with no motion (a jump in time: a seek, a loop the caller cuts).
    void reset(double seconds);

    [[nodiscard]] const Rig& rig() const noexcept { return *mRig; }
    [[nodiscard]] const Pose& pose() const noexcept { return mPose; }
    [[nodiscard]] const AnimationChoice& playing() const noexcept { return mPlaying; }

    // Bottom-level trees: rigid meshes' first, one per mesh that some rigid instance uses, then
    // one per deforming instance.
    [[nodiscard]] std::size_t bottomLevelCount() const noexcept { return mBottom.size(); }
    [[nodiscard]] const Bvh& bottomLevel(std::size_t i) const { return *mBottom[i]; }
    // Whether bottom level i changes every frame (a deforming instance's): its nodes and
    // triangles must be uploaded again after each update().
    [[nodiscard]] bool bottomLevelDeforms(std::size_t i) const { return mBottomDeforms[i]; }

    [[nodiscard]] std::size_t instanceCount() const noexcept { return mInstances.size(); }
    [[nodiscard]] uint32_t bottomLevelOf(std::size_t instance) const {
        return mInstances[instance].bottom;
    }
    [[nodiscard]] const glm::mat4& objectToWorld(std::size_t instance) const {
        return mInstances[instance].objectToWorld;
    }
    [[nodiscard]] const glm::mat4& previousObjectToWorld(std::size_t instance) const {
        return mInstances[instance].previousObjectToWorld;
    }
    // A deforming instance's triangles one frame ago, in its bottom-level tree's triangle order
    // (as Bvh::triangles()); empty for rigid instances, whose triangles do not change.
    [[nodiscard]] const std::vector<BvhTriangle>& previousTriangles(std::size_t instance) const {
        return mInstances[instance].previousTriangles;
    }
    // Shading data of bottom level i in its triangle order (normals and UVs of the deformed
    // vertices, materials): 3 vertices per triangle.
    [[nodiscard]] const std::vector<Vertex>& bottomLevelVertices(std::size_t i) const {
        return mBottomVertices[i];
    }
    [[nodiscard]] const std::vector<uint32_t>& bottomLevelMaterials(std::size_t i) const {
        return mBottomMaterials[i];
    }

    // The top level over the instances' world bounds: leaves index topLevelOrder().
    [[nodiscard]] const std::vector<BvhNode>& topLevel() const noexcept { return mTop; }
    [[nodiscard]] const std::vector<uint32_t>& topLevelOrder() const noexcept { return mTopOrder; }
    // Upper bound on topLevel().size() for this rig (a GPU table's fixed size).
    [[nodiscard]] std::size_t topLevelCapacity() const noexcept;

    [[nodiscard]] const DynamicUpdateTimings& lastTimings() const noexcept { return mTimings; }

    // CPU reference of the tracer's two-level traversal, over the instances only (the static
    // tree is Bvh::intersect): closest hit, ties on t to the lower instance then triangle.
    [[nodiscard]] DynamicHit intersect(const Ray& ray) const;
    [[nodiscard]] bool occluded(const Ray& ray) const;
    // The hit point's world position one frame ago (the motion a traced sample carries).
    [[nodiscard]] glm::vec3 previousPosition(const DynamicHit& hit) const;

private:
    struct Instance {
        uint32_t bottom = 0;
        glm::mat4 objectToWorld{1.0f}, previousObjectToWorld{1.0f};
        std::vector<BvhTriangle> previousTriangles;
    };
    void buildAll(double seconds);
    void rebuildTopLevel();

    std::shared_ptr<const Rig> mRig;
    AnimationChoice mPlaying;
    Pose mPose;
    std::vector<std::unique_ptr<Bvh>> mBottom;
    std::vector<bool> mBottomDeforms;
    std::vector<std::vector<Vertex>> mBottomVertices;
    std::vector<std::vector<uint32_t>> mBottomMaterials;
    std::vector<Instance> mInstances;
    std::vector<BvhNode> mTop;
    std::vector<uint32_t> mTopOrder;
    DynamicUpdateTimings mTimings;
    std::vector<Vertex> mScratch; // a deforming instance's vertices, reused frame to frame
};

} // namespace gt::scene
