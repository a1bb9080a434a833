#include "scene/bvh.hpp"

#include <algorithm>
#include <array>
#include <chrono>

#include "core/error.hpp"

namespace gt::scene {

namespace {

// 64 bins: with 16 (Wald's figure) the top splits of enclosed scenes (the market hall, the
// classroom) landed badly and traversal cost up to 2.3x more (GPU ms per frame, bench and
// README); from 32 bins up the cost was flat within noise on every scene we ship or test.
constexpr int kBins = 64;

// The bin of a centroid at `x` bins from the low end; NaN or negative (never for finite,
// in-range centroids) goes to bin 0 rather than to an undefined integer.
int binOf(float x) {
    return x >= 0.0f ? std::min(kBins - 1, static_cast<int>(std::min(x, 1e6f))) : 0;
}
constexpr float kTraversalCost = 1.0f;
constexpr float kIntersectCost = 1.0f;

bool slab(const BvhNode& n, const glm::vec3& origin, const glm::vec3& invDir, float tMin,
          float tMax, float& tEnter) {
    const glm::vec3 t0 = (n.boundsMin - origin) * invDir;
    const glm::vec3 t1 = (n.boundsMax - origin) * invDir;
    const glm::vec3 lo = glm::min(t0, t1), hi = glm::max(t0, t1);
    const float enter = std::max(std::max(lo.x, lo.y), std::max(lo.z, tMin));
    const float exit = std::min(std::min(hi.x, hi.y), std::min(hi.z, tMax));
    tEnter = enter;
    return enter <= exit;
}

float nodeArea(const BvhNode& node) {
    Aabb b;
    b.grow(node.boundsMin);
    b.grow(node.boundsMax);
    return b.area();
}

// The build's figure of merit (BvhBuildStats::sahCost): each node's work weighted by the chance
// a ray through the root meets its box.
float sahCostOf(const std::vector<BvhNode>& nodes) {
    const float rootArea = std::max(nodeArea(nodes[0]), 1e-20f);
    float cost = 0.0f;
    for (const BvhNode& node : nodes) {
        const float work = node.count > 0 ? kIntersectCost * static_cast<float>(node.count)
                                          : 2.0f * kTraversalCost;
        cost += nodeArea(node) / rootArea * work;
    }
    return cost;
}

// The slab test must never reject a hit Möller–Trumbore accepts: boxes are padded by a few
// ULPs of their coordinates (flat boxes around axis-aligned triangles, grazing rays).
void storePadded(BvhNode& node, const Aabb& bounds) {
    const glm::vec3 pad = 4e-6f * (glm::abs(bounds.lo) + glm::abs(bounds.hi)) + 1e-30f;
    node.boundsMin = bounds.lo - pad;
    node.boundsMax = bounds.hi + pad;
}

} // namespace

void Bvh::placeTriangles(std::span<const Vertex> vertices) {
    const auto n = static_cast<uint32_t>(mOrder.size());
    mTriangles.resize(n);
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t t = mOrder[i];
        const glm::vec3 v0 = vertices[3 * t].position;
        mTriangles[i] = {v0, vertices[3 * t + 1].position - v0, vertices[3 * t + 2].position - v0};
    }
}

float Bvh::refit(std::span<const Vertex> vertices) {
    if (vertices.size() / 3 != mOrder.size()) {
        throw Error("BVH refit: " + std::to_string(vertices.size() / 3) +
                    " triangles for a tree over " + std::to_string(mOrder.size()));
    }
    if (mOrder.empty()) return mStats.sahCost;
    placeTriangles(vertices);
    // Children always follow their parent in mNodes (the build appends them after it), so one
    // pass from the back sees every node's children before the node.
    std::vector<Aabb> boxes(mNodes.size());
    for (std::size_t i = mNodes.size(); i-- > 0;) {
        BvhNode& node = mNodes[i];
        Aabb b;
        if (node.count > 0) {
            for (uint32_t k = node.leftFirst; k < node.leftFirst + node.count; ++k) {
                const BvhTriangle& t = mTriangles[k];
                b.grow(t.v0);
                b.grow(t.v0 + t.e1);
                b.grow(t.v0 + t.e2);
            }
        } else {
            b = boxes[node.leftFirst];
            b.grow(boxes[node.leftFirst + 1]);
        }
        boxes[i] = b;
        storePadded(node, b);
    }
    return sahCostOf(mNodes);
}

bool intersectTriangle(const BvhTriangle& tri, const Ray& ray, float& t, float& u, float& v) {
    const glm::vec3 p = glm::cross(ray.direction, tri.e2);
    const float det = glm::dot(tri.e1, p);
    if (std::abs(det) < 1e-12f) return false;
    const float inv = 1.0f / det;
    const glm::vec3 s = ray.origin - tri.v0;
    u = glm::dot(s, p) * inv;
    if (u < 0.0f || u > 1.0f) return false;
    const glm::vec3 q = glm::cross(s, tri.e1);
    v = glm::dot(ray.direction, q) * inv;
    if (v < 0.0f || u + v > 1.0f) return false;
    t = glm::dot(tri.e2, q) * inv;
    return t > ray.tMin && t < ray.tMax;
}

Bvh::Bvh(const Scene& scene) : Bvh(std::span<const Vertex>(scene.vertices)) {}

Bvh::Bvh(std::span<const Vertex> vertices) {
    const auto start = std::chrono::steady_clock::now();
    const auto n = static_cast<uint32_t>(vertices.size() / 3);
    if (n == 0) {
        // Environment-only scenes: an empty leaf; traversal returns at once (see intersect()).
        mNodes.push_back({glm::vec3(0.0f), 0u, glm::vec3(0.0f), 0u});
        mStats.nodes = 1;
        return;
    }
    std::vector<Aabb> boxes(n);
    std::vector<glm::vec3> centroids(n);
    for (uint32_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k)
            boxes[i].grow(vertices[3 * i + k].position);
        centroids[i] = 0.5f * (boxes[i].lo + boxes[i].hi);
    }
    mOrder.resize(n);
    for (uint32_t i = 0; i < n; ++i)
        mOrder[i] = i;
    mNodes.reserve(2 * n);
    mNodes.push_back({});

    struct Task {
        uint32_t node, first, count, depth;
    };
    std::vector<Task> stack{{0, 0, n, 1}};
    auto makeLeaf = [&](const Task& t) {
        mNodes[t.node].leftFirst = t.first;
        mNodes[t.node].count = t.count;
        ++mStats.leaves;
        mStats.maxLeafSize = std::max(mStats.maxLeafSize, t.count);
    };
    while (!stack.empty()) {
        const Task task = stack.back();
        stack.pop_back();
        Aabb bounds, centroidBounds;
        for (uint32_t i = task.first; i < task.first + task.count; ++i) {
            bounds.grow(boxes[mOrder[i]]);
            centroidBounds.grow(centroids[mOrder[i]]);
        }
        storePadded(mNodes[task.node], bounds);
        mStats.maxDepth = std::max(mStats.maxDepth, task.depth);
        if (task.count <= 2) {
            makeLeaf(task);
            continue;
        }
        // Binned SAH over the centroid bounds, all three axes.
        float bestCost = std::numeric_limits<float>::max();
        int bestAxis = -1, bestSplit = 0;
        for (int axis = 0; axis < 3; ++axis) {
            const float lo = centroidBounds.lo[axis], hi = centroidBounds.hi[axis];
            // Also skips extents that overflow (infinite): their scale would be 0 and a bin
            // index from inf * 0 undefined.
            if (!(hi - lo >= 1e-9f) || !std::isfinite(hi - lo)) continue;
            std::array<Aabb, kBins> binBox{};
            std::array<uint32_t, kBins> binCount{};
            const float scale = static_cast<float>(kBins) / (hi - lo);
            for (uint32_t i = task.first; i < task.first + task.count; ++i) {
                const uint32_t t = mOrder[i];
                const int b = binOf((centroids[t][axis] - lo) * scale);
                binBox[b].grow(boxes[t]);
                ++binCount[b];
            }
            std::array<float, kBins - 1> leftArea{}, rightArea{};
            std::array<uint32_t, kBins - 1> leftCount{}, rightCount{};
            Aabb l, r;
            uint32_t lc = 0, rc = 0;
            for (int i = 0; i < kBins - 1; ++i) {
                l.grow(binBox[i]);
                lc += binCount[i];
                leftArea[i] = l.area();
                leftCount[i] = lc;
                r.grow(binBox[kBins - 1 - i]);
                rc += binCount[kBins - 1 - i];
                rightArea[kBins - 2 - i] = r.area();
                rightCount[kBins - 2 - i] = rc;
            }
            for (int i = 0; i < kBins - 1; ++i) {
                if (leftCount[i] == 0 || rightCount[i] == 0) continue;
                const float cost = leftArea[i] * static_cast<float>(leftCount[i]) +
                                   rightArea[i] * static_cast<float>(rightCount[i]);
                if (cost < bestCost) {
                    bestCost = cost;
                    bestAxis = axis;
                    bestSplit = i;
                }
            }
        }
        const float leafCost = kIntersectCost * static_cast<float>(task.count);
        const float splitCost =
            kTraversalCost + kIntersectCost * bestCost / std::max(bounds.area(), 1e-20f);
        const bool mustSplit = task.count > kMaxLeafSize;
        if (bestAxis < 0 || (!mustSplit && splitCost >= leafCost) || task.depth >= kMaxDepth) {
            if (bestAxis < 0 && mustSplit && task.depth < kMaxDepth) {
                // All centroids coincide: split the range in the middle.
                bestAxis = -2;
            } else {
                if (task.count > kMaxLeafSize && task.depth >= kMaxDepth) {
                    throw Error("BVH build exceeded depth " + std::to_string(kMaxDepth));
                }
                makeLeaf(task);
                continue;
            }
        }
        uint32_t mid;
        if (bestAxis == -2) {
            mid = task.first + task.count / 2;
        } else {
            const float lo = centroidBounds.lo[bestAxis];
            const float scale = static_cast<float>(kBins) / (centroidBounds.hi[bestAxis] - lo);
            auto it =
                std::partition(mOrder.begin() + task.first,
                               mOrder.begin() + task.first + task.count, [&](uint32_t t) {
                                   return binOf((centroids[t][bestAxis] - lo) * scale) <= bestSplit;
                               });
            mid = static_cast<uint32_t>(it - mOrder.begin());
        }
        const auto left = static_cast<uint32_t>(mNodes.size());
        mNodes.push_back({});
        mNodes.push_back({});
        mNodes[task.node].leftFirst = left;
        mNodes[task.node].count = 0;
        stack.push_back({left + 1, mid, task.first + task.count - mid, task.depth + 1});
        stack.push_back({left, task.first, mid - task.first, task.depth + 1});
    }
    placeTriangles(vertices);
    mStats.nodes = static_cast<uint32_t>(mNodes.size());
    mStats.sahCost = sahCostOf(mNodes);
    mStats.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Hit Bvh::intersect(const Ray& ray, const HitFilter& accept) const {
    Hit best;
    if (mTriangles.empty()) return best;
    best.t = ray.tMax;
    const glm::vec3 invDir = 1.0f / ray.direction;
    std::array<uint32_t, kMaxDepth * 2> stack{};
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        const BvhNode& node = mNodes[stack[--sp]];
        float tEnter;
        if (!slab(node, ray.origin, invDir, ray.tMin, best.t, tEnter)) continue;
        if (node.count > 0) {
            for (uint32_t i = node.leftFirst; i < node.leftFirst + node.count; ++i) {
                float t, u, v;
                Ray r = ray;
                r.tMax = std::numeric_limits<float>::infinity();
                if (intersectTriangle(mTriangles[i], r, t, u, v) && t <= best.t &&
                    (t < best.t || i < best.triangle)) {
                    if (t > ray.tMax || (accept && !accept(i, u, v))) {
                        continue;
                    }
                    best = {t, i, u, v};
                }
            }
            continue;
        }
        // Visit the nearer child first.
        float tl, tr;
        const bool hl = slab(mNodes[node.leftFirst], ray.origin, invDir, ray.tMin, best.t, tl);
        const bool hr = slab(mNodes[node.leftFirst + 1], ray.origin, invDir, ray.tMin, best.t, tr);
        if (hl && hr) {
            const bool leftFirst = tl <= tr;
            stack[sp++] = leftFirst ? node.leftFirst + 1 : node.leftFirst;
            stack[sp++] = leftFirst ? node.leftFirst : node.leftFirst + 1;
        } else if (hl) {
            stack[sp++] = node.leftFirst;
        } else if (hr) {
            stack[sp++] = node.leftFirst + 1;
        }
    }
    if (!best.valid()) best.t = std::numeric_limits<float>::infinity();
    return best;
}

bool Bvh::occluded(const Ray& ray, const HitFilter& accept) const {
    if (mTriangles.empty()) return false;
    const glm::vec3 invDir = 1.0f / ray.direction;
    std::array<uint32_t, kMaxDepth * 2> stack{};
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        const BvhNode& node = mNodes[stack[--sp]];
        float tEnter;
        if (!slab(node, ray.origin, invDir, ray.tMin, ray.tMax, tEnter)) continue;
        if (node.count > 0) {
            for (uint32_t i = node.leftFirst; i < node.leftFirst + node.count; ++i) {
                float t, u, v;
                if (intersectTriangle(mTriangles[i], ray, t, u, v) &&
                    (!accept || accept(i, u, v))) {
                    return true;
                }
            }
            continue;
        }
        stack[sp++] = node.leftFirst + 1;
        stack[sp++] = node.leftFirst;
    }
    return false;
}

Hit Bvh::intersectBruteForce(const Ray& ray) const {
    Hit best;
    best.t = ray.tMax;
    for (uint32_t i = 0; i < mTriangles.size(); ++i) {
        float t, u, v;
        Ray r = ray;
        r.tMax = std::numeric_limits<float>::infinity();
        if (intersectTriangle(mTriangles[i], r, t, u, v) && t <= best.t &&
            (t < best.t || i < best.triangle) && t <= ray.tMax) {
            best = {t, i, u, v};
        }
    }
    if (!best.valid()) best.t = std::numeric_limits<float>::infinity();
    return best;
}

} // namespace gt::scene
