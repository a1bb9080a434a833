#pragma once
// A binary BVH over the scene's triangles, built on the CPU with binned SAH (64 bins per axis,
// Wald 2007 "On fast construction of SAH-based BVHs"), flattened so that the two children of
// an interior node are adjacent (left = leftFirst, right = leftFirst + 1). The same flat arrays
// are uploaded for the compute-shader tracer; the CPU traversal here is the reference the GPU
// is tested against.
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.hpp"

namespace gt::scene {

// An axis-aligned box, empty until grown.
struct Aabb {
    glm::vec3 lo{std::numeric_limits<float>::max()};
    glm::vec3 hi{-std::numeric_limits<float>::max()};
    void grow(glm::vec3 p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void grow(const Aabb& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    [[nodiscard]] float area() const {
        const glm::vec3 d = hi - lo;
        if (d.x < 0.0f) return 0.0f;
        return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
    [[nodiscard]] glm::vec3 centre() const { return 0.5f * (lo + hi); }
};

struct BvhNode {
    glm::vec3 boundsMin;
    uint32_t leftFirst; // interior: index of the left child; leaf: first triangle
    glm::vec3 boundsMax;
    uint32_t count; // 0 for interior nodes, triangle count for leaves
};
static_assert(sizeof(BvhNode) == 32);

struct Ray {
    glm::vec3 origin;
    glm::vec3 direction;
    float tMin = 0.0f;
    float tMax = std::numeric_limits<float>::infinity();
};

struct Hit {
    float t = std::numeric_limits<float>::infinity();
    uint32_t triangle = ~0u;  // index into the BVH's triangle order
    float u = 0.0f, v = 0.0f; // barycentrics of vertices 1 and 2
    [[nodiscard]] bool valid() const noexcept { return triangle != ~0u; }
};

// Precomputed triangle in intersection form: v0 and two edges.
struct BvhTriangle {
    glm::vec3 v0, e1, e2;
};

struct BvhBuildStats {
    uint32_t nodes = 0;
    uint32_t leaves = 0;
    uint32_t maxDepth = 0;
    uint32_t maxLeafSize = 0;
    // Expected cost of a random ray that hits the root box, in units of one box test (the SAH
    // with a triangle test costing as much as a box test): the figure of merit of the build.
    float sahCost = 0.0f;
    double seconds = 0.0;
};

class Bvh {
public:
    static constexpr uint32_t kMaxLeafSize = 8;
    static constexpr uint32_t kMaxDepth = 64; // the GPU traversal stack is sized from this

    explicit Bvh(const Scene& scene);
    // Over any triangle list, 3 vertices per triangle (a mesh in its own space: a bottom-level
    // tree of dynamic_geometry.hpp).
    explicit Bvh(std::span<const Vertex> vertices);

    // Moves the triangles to `vertices` (the same triangles in the same scene order, deformed)
    // and refits every node's bounds bottom-up, keeping the topology; returns the tree's SAH
    // cost afterwards (stats().sahCost keeps the cost at build).
    float refit(std::span<const Vertex> vertices);

    [[nodiscard]] const std::vector<BvhNode>& nodes() const noexcept { return mNodes; }
    // triangleOrder()[i] = the scene triangle stored at BVH position i.
    [[nodiscard]] const std::vector<uint32_t>& triangleOrder() const noexcept { return mOrder; }
    [[nodiscard]] const std::vector<BvhTriangle>& triangles() const noexcept { return mTriangles; }
    [[nodiscard]] const BvhBuildStats& stats() const noexcept { return mStats; }

    // Whether a candidate hit on BVH triangle `i` at barycentrics (u, v) counts: alpha masks
    // pass rays through. Empty: every hit counts.
    using HitFilter = std::function<bool(uint32_t i, float u, float v)>;

    // Closest hit in [tMin, tMax]; ties on t go to the lower BVH triangle index so the result
    // does not depend on traversal order.
    [[nodiscard]] Hit intersect(const Ray& ray, const HitFilter& accept = {}) const;
    [[nodiscard]] bool occluded(const Ray& ray, const HitFilter& accept = {}) const;
    // The same answer by testing every triangle (for tests).
    [[nodiscard]] Hit intersectBruteForce(const Ray& ray) const;

private:
    void placeTriangles(std::span<const Vertex> vertices); // mTriangles from mOrder

    std::vector<BvhNode> mNodes;
    std::vector<uint32_t> mOrder;
    std::vector<BvhTriangle> mTriangles;
    BvhBuildStats mStats;
};

// Möller–Trumbore; returns true and fills t/u/v when the ray hits within (tMin, tMax).
bool intersectTriangle(const BvhTriangle& tri, const Ray& ray, float& t, float& u, float& v);

} // namespace gt::scene
