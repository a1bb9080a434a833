#include "scene/dynamic_geometry.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <map>
#include <numeric>

#include "core/error.hpp"

namespace gt::scene {

namespace {

using SteadyClock = std::chrono::steady_clock;

double msSince(SteadyClock::time_point start) {
    return std::chrono::duration<double, std::milli>(SteadyClock::now() - start).count();
}

// The world box of a bottom-level tree placed by `m`: its root box's eight corners moved.
Aabb worldBox(const Bvh& bvh, const glm::mat4& m) {
    Aabb b;
    if (bvh.triangles().empty()) return b;
    const BvhNode& root = bvh.nodes().front();
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner{(c & 1) ? root.boundsMax.x : root.boundsMin.x,
                               (c & 2) ? root.boundsMax.y : root.boundsMin.y,
                               (c & 4) ? root.boundsMax.z : root.boundsMin.z};
        b.grow(glm::vec3(m * glm::vec4(corner, 1.0f)));
    }
    return b;
}

// A vertex list in a tree's triangle order (what the tracer's shading table holds).
void inTreeOrder(const Bvh& bvh, const std::vector<Vertex>& sceneOrder,
                 const std::vector<uint32_t>& sceneMaterials, std::vector<Vertex>& vertices,
                 std::vector<uint32_t>& materials) {
    const std::vector<uint32_t>& order = bvh.triangleOrder();
    vertices.resize(3 * order.size());
    materials.resize(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        for (int k = 0; k < 3; ++k)
            vertices[3 * i + k] = sceneOrder[3 * order[i] + k];
        materials[i] = sceneMaterials[order[i]];
    }
}

Ray intoObjectSpace(const Ray& ray, const glm::mat4& worldToObject) {
    // The direction is not normalised: t along the moved ray is t along the world ray.
    Ray r = ray;
    r.origin = glm::vec3(worldToObject * glm::vec4(ray.origin, 1.0f));
    r.direction = glm::vec3(worldToObject * glm::vec4(ray.direction, 0.0f));
    return r;
}

bool slabHit(const BvhNode& n, const Ray& ray, const glm::vec3& invDir, float tMax) {
    const glm::vec3 t0 = (n.boundsMin - ray.origin) * invDir;
    const glm::vec3 t1 = (n.boundsMax - ray.origin) * invDir;
    const glm::vec3 lo = glm::min(t0, t1), hi = glm::max(t0, t1);
    const float enter = std::max(std::max(lo.x, lo.y), std::max(lo.z, ray.tMin));
    const float exit = std::min(std::min(hi.x, hi.y), std::min(hi.z, tMax));
    return enter <= exit;
}

} // namespace

DynamicGeometry::DynamicGeometry(std::shared_ptr<const Rig> rig, AnimationChoice playing,
                                 double seconds)
    : mRig(std::move(rig)), mPlaying(playing) {
    if (!mRig) throw Error("dynamic geometry: a scene without a rig");
    buildAll(seconds);
}

void DynamicGeometry::buildAll(double seconds) {
    const Rig& rig = *mRig;
    evaluatePose(rig, mPlaying, seconds, mPose);
    mBottom.clear();
    mBottomDeforms.clear();
    mBottomVertices.clear();
    mBottomMaterials.clear();
    mInstances.assign(rig.instances.size(), {});
    const auto addBottom = [&](const std::vector<Vertex>& vertices,
                               const std::vector<uint32_t>& materials, bool deforming) {
        mBottom.push_back(std::make_unique<Bvh>(std::span<const Vertex>(vertices)));
        mBottomDeforms.push_back(deforming);
        mBottomVertices.emplace_back();
        mBottomMaterials.emplace_back();
        inTreeOrder(*mBottom.back(), vertices, materials, mBottomVertices.back(),
                    mBottomMaterials.back());
        return static_cast<uint32_t>(mBottom.size() - 1);
    };
    // Rigid meshes first, one tree per mesh, shared by its instances.
    std::map<uint32_t, uint32_t> meshBottom;
    for (std::size_t i = 0; i < rig.instances.size(); ++i) {
        const MeshInstance& inst = rig.instances[i];
        if (deforms(rig, inst)) continue;
        auto [it, added] = meshBottom.try_emplace(inst.mesh, 0u);
        if (added) {
            const RigMesh& mesh = rig.meshes[inst.mesh];
            it->second = addBottom(mesh.vertices, mesh.triangleMaterial, false);
        }
        mInstances[i].bottom = it->second;
    }
    std::vector<Vertex> deformed;
    for (std::size_t i = 0; i < rig.instances.size(); ++i) {
        const MeshInstance& inst = rig.instances[i];
        if (!deforms(rig, inst)) continue;
        deformInstance(rig, inst, mPose, deformed);
        mInstances[i].bottom = addBottom(deformed, rig.meshes[inst.mesh].triangleMaterial, true);
    }
    for (std::size_t i = 0; i < rig.instances.size(); ++i) {
        Instance& inst = mInstances[i];
        inst.objectToWorld = instanceTransform(rig, rig.instances[i], mPose);
        inst.previousObjectToWorld = inst.objectToWorld;
        if (mBottomDeforms[inst.bottom]) inst.previousTriangles = mBottom[inst.bottom]->triangles();
    }
    const auto start = SteadyClock::now();
    rebuildTopLevel();
    mTimings = {};
    mTimings.topLevelMs = msSince(start);
}

void DynamicGeometry::reset(double seconds) {
    buildAll(seconds);
}

void DynamicGeometry::update(double seconds) {
    const Rig& rig = *mRig;
    mTimings = {};
    auto start = SteadyClock::now();
    evaluatePose(rig, mPlaying, seconds, mPose);
    mTimings.poseMs = msSince(start);
    std::vector<Vertex>& deformed = mScratch;
    for (std::size_t i = 0; i < rig.instances.size(); ++i) {
        Instance& inst = mInstances[i];
        inst.previousObjectToWorld = inst.objectToWorld;
        inst.objectToWorld = instanceTransform(rig, rig.instances[i], mPose);
        if (!mBottomDeforms[inst.bottom]) continue;
        Bvh& bvh = *mBottom[inst.bottom];
        inst.previousTriangles = bvh.triangles();
        start = SteadyClock::now();
        deformInstance(rig, rig.instances[i], mPose, deformed);
        mTimings.deformMs += msSince(start);
        start = SteadyClock::now();
        const float cost = bvh.refit(deformed);
        ++mTimings.refits;
        mTimings.refitMs += msSince(start);
        const std::vector<uint32_t>& materials = rig.meshes[rig.instances[i].mesh].triangleMaterial;
        if (cost > kRebuildSahRatio * bvh.stats().sahCost) {
            // Refitting has stretched the boxes (a limb swung far from the bind pose): a fresh
            // build over the same triangles. Previous triangles follow the new order.
            start = SteadyClock::now();
            const std::vector<uint32_t> oldOrder = bvh.triangleOrder();
            mBottom[inst.bottom] = std::make_unique<Bvh>(std::span<const Vertex>(deformed));
            std::vector<BvhTriangle> bySceneIndex(oldOrder.size());
            for (std::size_t k = 0; k < oldOrder.size(); ++k)
                bySceneIndex[oldOrder[k]] = inst.previousTriangles[k];
            const std::vector<uint32_t>& newOrder = mBottom[inst.bottom]->triangleOrder();
            for (std::size_t k = 0; k < newOrder.size(); ++k)
                inst.previousTriangles[k] = bySceneIndex[newOrder[k]];
            ++mTimings.rebuilds;
            mTimings.rebuildMs += msSince(start);
        }
        inTreeOrder(*mBottom[inst.bottom], deformed, materials, mBottomVertices[inst.bottom],
                    mBottomMaterials[inst.bottom]);
    }
    start = SteadyClock::now();
    rebuildTopLevel();
    mTimings.topLevelMs = msSince(start);
}

std::size_t DynamicGeometry::topLevelCapacity() const noexcept {
    return mInstances.empty() ? 1 : 2 * mInstances.size() - 1;
}

// Top-down over the instances' world boxes: each node splits its instances at the median
// centroid along the box's longest axis (a few hundred instances at most; the SAH buys little
// over so few and this costs microseconds). Leaves hold one instance.
void DynamicGeometry::rebuildTopLevel() {
    const std::size_t n = mInstances.size();
    mTop.clear();
    mTopOrder.resize(n);
    std::iota(mTopOrder.begin(), mTopOrder.end(), 0u);
    if (n == 0) {
        mTop.push_back({glm::vec3(0.0f), 0u, glm::vec3(0.0f), 0u});
        return;
    }
    std::vector<Aabb> boxes(n);
    for (std::size_t i = 0; i < n; ++i)
        boxes[i] = worldBox(*mBottom[mInstances[i].bottom], mInstances[i].objectToWorld);
    mTop.reserve(2 * n - 1);
    mTop.push_back({});
    struct Task {
        uint32_t node, first, count;
    };
    std::vector<Task> stack{{0, 0, static_cast<uint32_t>(n)}};
    while (!stack.empty()) {
        const Task t = stack.back();
        stack.pop_back();
        Aabb b;
        for (uint32_t i = t.first; i < t.first + t.count; ++i)
            b.grow(boxes[mTopOrder[i]]);
        mTop[t.node].boundsMin = b.lo;
        mTop[t.node].boundsMax = b.hi;
        if (t.count == 1) {
            mTop[t.node].leftFirst = t.first;
            mTop[t.node].count = 1;
            continue;
        }
        const glm::vec3 extent = b.hi - b.lo;
        const int axis =
            extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        const uint32_t mid = t.first + t.count / 2;
        std::nth_element(mTopOrder.begin() + t.first, mTopOrder.begin() + mid,
                         mTopOrder.begin() + t.first + t.count, [&](uint32_t a, uint32_t c) {
                             return boxes[a].centre()[axis] < boxes[c].centre()[axis];
                         });
        const auto left = static_cast<uint32_t>(mTop.size());
        mTop.push_back({});
        mTop.push_back({});
        mTop[t.node].leftFirst = left;
        mTop[t.node].count = 0;
        stack.push_back({left + 1, mid, t.first + t.count - mid});
        stack.push_back({left, t.first, mid - t.first});
    }
}

DynamicHit DynamicGeometry::intersect(const Ray& ray) const {
    DynamicHit best;
    best.t = ray.tMax;
    const glm::vec3 invDir = 1.0f / ray.direction;
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
        const BvhNode& node = mTop[stack.back()];
        stack.pop_back();
        if (mInstances.empty() || !slabHit(node, ray, invDir, best.t)) continue;
        if (node.count == 0) {
            stack.push_back(node.leftFirst);
            stack.push_back(node.leftFirst + 1);
            continue;
        }
        const uint32_t instance = mTopOrder[node.leftFirst];
        const Instance& inst = mInstances[instance];
        Ray local = intoObjectSpace(ray, glm::inverse(inst.objectToWorld));
        local.tMax = best.t;
        const Hit h = mBottom[inst.bottom]->intersect(local);
        if (!h.valid() || h.t > best.t) continue;
        const bool tie = h.t == best.t;
        if (tie && best.valid() &&
            (instance > best.instance || (instance == best.instance && h.triangle > best.triangle)))
            continue;
        best = {h.t, instance, h.triangle, h.u, h.v};
    }
    if (!best.valid()) best.t = std::numeric_limits<float>::infinity();
    return best;
}

bool DynamicGeometry::occluded(const Ray& ray) const {
    for (std::size_t i = 0; i < mInstances.size(); ++i) {
        const Instance& inst = mInstances[i];
        if (mBottom[inst.bottom]->occluded(intoObjectSpace(ray, glm::inverse(inst.objectToWorld))))
            return true;
    }
    return false;
}

glm::vec3 DynamicGeometry::previousPosition(const DynamicHit& hit) const {
    const Instance& inst = mInstances.at(hit.instance);
    const std::vector<BvhTriangle>& tris =
        mBottomDeforms[inst.bottom] ? inst.previousTriangles : mBottom[inst.bottom]->triangles();
    const BvhTriangle& t = tris.at(hit.triangle);
    const glm::vec3 local = t.v0 + hit.u * t.e1 + hit.v * t.e2;
    return glm::vec3(inst.previousObjectToWorld * glm::vec4(local, 1.0f));
}

} // namespace gt::scene
