// The two-level structure of a scene that moves (dynamic_geometry.hpp) against brute force over
// the same triangles placed in the world, its refits against fresh builds, and the motion a hit
// carries.
#include <cmath>
#include <memory>
#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "scene/dynamic_geometry.hpp"

namespace gt::scene {
namespace {

// A unit cube [-0.5, 0.5]^3 as 12 triangles (material 0).
RigMesh cubeMesh() {
    Scene s;
    SceneBuilder b(s);
    b.box(glm::mat4(1.0f), b.material({}));
    RigMesh m;
    m.vertices = s.vertices;
    m.triangleMaterial.assign(s.triangleCount(), 0);
    return m;
}

// A bar along +y from 0 to 2 of `segments` boxes, skinned to two joints: below y = 1 to joint 0,
// above to joint 1 (which sits at y = 1).
RigMesh skinnedBar(int segments) {
    Scene s;
    SceneBuilder b(s);
    const uint32_t mat = b.material({});
    for (int i = 0; i < segments; ++i) {
        const float y = 2.0f * (static_cast<float>(i) + 0.5f) / static_cast<float>(segments);
        b.box(glm::scale(glm::translate(glm::mat4(1.0f), {0, y, 0}),
                         {0.2f, 2.0f / static_cast<float>(segments), 0.2f}),
              mat);
    }
    RigMesh m;
    m.vertices = s.vertices;
    m.triangleMaterial.assign(s.triangleCount(), 0);
    for (const Vertex& v : m.vertices) {
        const bool upper = v.position.y > 1.0f;
        m.joints.emplace_back(upper ? 1u : 0u, 0u, 0u, 0u);
        m.weights.emplace_back(1.0f, 0.0f, 0.0f, 0.0f);
    }
    return m;
}

AnimationSampler linear(std::vector<float> times, std::vector<float> values, uint32_t c) {
    AnimationSampler s;
    s.times = std::move(times);
    s.values = std::move(values);
    s.components = c;
    return s;
}

// Nodes: 0 and 1 rigid cubes (1 rotated and scaled unevenly, 0 sliding along x at 10 units/s),
// 2 another instance of the cube under node 0, 3 and 4 the bar's joints (4 swinging about z),
// 5 the bar's mesh node.
std::shared_ptr<Rig> testRig() {
    auto rig = std::make_shared<Rig>();
    rig->meshes = {cubeMesh(), skinnedBar(8)};
    RigNode n0, n1, n2, j0, j1, bar;
    n1.rest.translation = {0.0f, 0.0f, -4.0f};
    n1.rest.rotation = glm::angleAxis(0.6f, glm::normalize(glm::vec3(1, 2, 0.5f)));
    n1.rest.scale = {2.0f, 0.5f, 1.0f};
    n2.parent = 0;
    n2.rest.translation = {0.0f, 2.0f, 0.0f};
    j0.rest.translation = {3.0f, 0.0f, 0.0f};
    j1.parent = 3;
    j1.rest.translation = {0.0f, 1.0f, 0.0f};
    rig->nodes = {n0, n1, n2, j0, j1, bar};
    rig->instances = {{0, 0, -1}, {1, 0, -1}, {2, 0, -1}, {5, 1, 0}};
    Skin skin;
    skin.joints = {3, 4};
    skin.inverseBind = {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), {0.0f, -1.0f, 0.0f})};
    rig->skins = {skin};
    Animation a;
    a.samplers.push_back(linear({0.0f, 1.0f}, {0, 0, 0, 10, 0, 0}, 3));
    const glm::quat q0(1, 0, 0, 0), q1 = glm::angleAxis(1.5f, glm::vec3(0, 0, 1));
    a.samplers.push_back(linear({0.0f, 1.0f}, {q0.x, q0.y, q0.z, q0.w, q1.x, q1.y, q1.z, q1.w}, 4));
    a.channels = {{0, 0, AnimatedPath::Translation}, {1, 4, AnimatedPath::Rotation}};
    a.duration = 1.0f;
    rig->animations = {a};
    return rig;
}

// Every instance's triangles in the world at `seconds`, as one list.
std::vector<BvhTriangle> worldTriangles(const Rig& rig, double seconds) {
    const Pose pose = evaluatePose(rig, {}, seconds);
    std::vector<BvhTriangle> out;
    std::vector<Vertex> v;
    for (const MeshInstance& inst : rig.instances) {
        deformInstance(rig, inst, pose, v);
        const glm::mat4 m = instanceTransform(rig, inst, pose);
        for (std::size_t i = 0; i < v.size(); i += 3) {
            glm::vec3 p[3];
            for (int k = 0; k < 3; ++k)
                p[k] = glm::vec3(m * glm::vec4(v[i + k].position, 1.0f));
            out.push_back({p[0], p[1] - p[0], p[2] - p[0]});
        }
    }
    return out;
}

float bruteForce(const std::vector<BvhTriangle>& tris, const Ray& ray) {
    float best = std::numeric_limits<float>::infinity();
    for (const BvhTriangle& t : tris) {
        float d, u, v;
        if (intersectTriangle(t, ray, d, u, v)) best = std::min(best, d);
    }
    return best;
}

std::vector<Ray> raysAtTheScene(uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Ray> rays;
    for (uint32_t i = 0; i < count; ++i) {
        Ray r;
        r.origin = {u(rng) * 2.0f + 2.0f, u(rng) * 2.0f + 1.0f, 8.0f};
        const glm::vec3 target{u(rng) * 6.0f + 3.0f, u(rng) * 3.0f + 1.0f, u(rng) * 3.0f - 2.0f};
        r.direction = glm::normalize(target - r.origin);
        rays.push_back(r);
    }
    return rays;
}

void expectSameHits(const DynamicGeometry& g, const Rig& rig, double seconds, uint32_t seed,
                    int minHits = 50) {
    const std::vector<BvhTriangle> world = worldTriangles(rig, seconds);
    int hits = 0;
    for (const Ray& r : raysAtTheScene(2000, seed)) {
        const float expected = bruteForce(world, r);
        const DynamicHit h = g.intersect(r);
        if (std::isinf(expected)) {
            EXPECT_FALSE(h.valid());
        } else {
            ++hits;
            ASSERT_TRUE(h.valid());
            EXPECT_NEAR(h.t, expected, 1e-4f * expected);
        }
        EXPECT_EQ(g.occluded(r), !std::isinf(expected));
    }
    EXPECT_GT(hits, minHits) << "the rays mostly miss: the test would prove little";
}

TEST(DynamicGeometry, TwoLevelHitsEqualBruteForceOverTheWorldTriangles) {
    const auto rig = testRig();
    DynamicGeometry g(rig, {}, 0.25);
    expectSameHits(g, *rig, 0.25, 1);
    g.update(0.8); // the bar swung, the cubes slid: refits and a new top level
    expectSameHits(g, *rig, 0.8, 2);
}

TEST(DynamicGeometry, RigidInstancesOfOneMeshShareABottomLevel) {
    const auto rig = testRig();
    const DynamicGeometry g(rig, {}, 0.0);
    EXPECT_EQ(g.bottomLevelCount(), 2u); // the cube's, and the skinned bar's own
    EXPECT_EQ(g.bottomLevelOf(0), g.bottomLevelOf(1));
    EXPECT_EQ(g.bottomLevelOf(0), g.bottomLevelOf(2));
    EXPECT_FALSE(g.bottomLevelDeforms(g.bottomLevelOf(0)));
    EXPECT_TRUE(g.bottomLevelDeforms(g.bottomLevelOf(3)));
    EXPECT_LE(g.topLevel().size(), g.topLevelCapacity());
}

TEST(DynamicGeometry, AHitKnowsWhereItsPointWasOneFrameAgo) {
    const auto rig = testRig();
    DynamicGeometry g(rig, {}, 0.5);
    g.update(0.6); // node 0 (and node 2 under it) moved +1 in x
    Ray r;
    r.origin = {1.0f, 2.0f, 5.0f}; // straight at the cube of node 2, centred at (6, 2, 0)
    r.direction = {0.0f, 0.0f, -1.0f};
    r.origin.x = 6.0f;
    const DynamicHit h = g.intersect(r);
    ASSERT_TRUE(h.valid());
    EXPECT_EQ(h.instance, 2u);
    const glm::vec3 now = r.origin + h.t * r.direction;
    const glm::vec3 before = g.previousPosition(h);
    EXPECT_NEAR(before.x, now.x - 1.0f, 1e-4f);
    EXPECT_NEAR(before.y, now.y, 1e-4f);
    EXPECT_NEAR(before.z, now.z, 1e-4f);
}

TEST(DynamicGeometry, ADeformedHitMovesWithItsJoint) {
    const auto rig = testRig();
    DynamicGeometry g(rig, {}, 0.0);
    g.update(0.5); // joint 1 from 0 to 0.75 rad about z at (3, 1, 0)
    // A ray down onto the top of the bar's upper half, now leaning towards -x.
    const Pose pose = evaluatePose(*rig, {}, 0.5);
    const glm::vec3 tip = glm::vec3(pose.world[4] * glm::vec4(0.0f, 0.9f, 0.0f, 1.0f));
    Ray r;
    r.origin = tip + glm::vec3(0.0f, 0.0f, 5.0f);
    r.direction = {0.0f, 0.0f, -1.0f};
    const DynamicHit h = g.intersect(r);
    ASSERT_TRUE(h.valid());
    EXPECT_EQ(h.instance, 3u);
    const glm::vec3 before = g.previousPosition(h);
    // One frame ago (t = 0) the bar stood straight: the same surface point, rotated back.
    const glm::vec3 now = r.origin + h.t * r.direction;
    const glm::vec3 rel = now - glm::vec3(3.0f, 1.0f, 0.0f);
    const glm::vec3 back =
        glm::vec3(3.0f, 1.0f, 0.0f) + glm::angleAxis(-0.75f, glm::vec3(0, 0, 1)) * rel;
    EXPECT_NEAR(before.x, back.x, 1e-3f);
    EXPECT_NEAR(before.y, back.y, 1e-3f);
    EXPECT_NEAR(before.z, back.z, 1e-3f);
}

TEST(Bvh, RefitFindsWhatAFreshBuildFinds) {
    const RigMesh bar = skinnedBar(16);
    Bvh refitted{std::span<const Vertex>(bar.vertices)};
    std::vector<Vertex> moved = bar.vertices;
    for (Vertex& v : moved) // a shear that grows with height
        v.position.x += 0.7f * v.position.y * v.position.y;
    const float cost = refitted.refit(moved);
    const Bvh fresh{std::span<const Vertex>(moved)};
    EXPECT_GT(cost, 0.0f);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
        Ray r;
        r.origin = {u(rng) * 2.0f + 1.0f, u(rng) * 1.2f + 1.0f, 4.0f};
        r.direction = glm::normalize(glm::vec3(u(rng) * 0.2f, u(rng) * 0.2f, -1.0f));
        const Hit a = refitted.intersect(r), b = fresh.intersect(r);
        EXPECT_EQ(a.valid(), b.valid());
        if (a.valid() && b.valid()) {
            ++hits;
            EXPECT_NEAR(a.t, b.t, 1e-5f);
        }
    }
    EXPECT_GT(hits, 50);
}

TEST(Bvh, RefitOfTheSameVerticesKeepsTheBuildsCost) {
    const RigMesh bar = skinnedBar(16);
    Bvh bvh{std::span<const Vertex>(bar.vertices)};
    EXPECT_NEAR(bvh.refit(bar.vertices), bvh.stats().sahCost, 1e-3f * bvh.stats().sahCost);
    EXPECT_THROW((void)bvh.refit(std::span<const Vertex>(bar.vertices).first(3)), gt::Error);
}

// A bar whose triangles a morph target scatters (each triangle moved as a whole by up to 5
// units): refitted boxes then overlap everywhere, and the tree must be rebuilt.
std::shared_ptr<Rig> scatteringRig() {
    auto rig = std::make_shared<Rig>();
    RigMesh bar = skinnedBar(16);
    bar.joints.clear();
    bar.weights.clear();
    MorphTarget scatter;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-5.0f, 5.0f);
    for (std::size_t i = 0; i < bar.vertices.size(); i += 3) {
        const glm::vec3 d{u(rng), u(rng), u(rng)};
        scatter.positions.insert(scatter.positions.end(), {d, d, d});
    }
    bar.targets = {scatter};
    rig->meshes = {bar};
    RigNode node;
    node.weights = {0.0f};
    rig->nodes = {node};
    rig->instances = {{0, 0, -1}};
    Animation a;
    a.samplers.push_back(linear({0.0f, 1.0f}, {0.0f, 1.0f}, 1));
    a.channels = {{0, 0, AnimatedPath::Weights}};
    a.duration = 1.0f;
    rig->animations = {a};
    return rig;
}

TEST(DynamicGeometry, ARefitStretchedPastTheBoundIsRebuilt) {
    const auto rig = scatteringRig();
    DynamicGeometry g(rig, {}, 0.0);
    g.update(0.01); // triangles moved by at most 0.05: refitted
    EXPECT_EQ(g.lastTimings().refits, 1u);
    EXPECT_EQ(g.lastTimings().rebuilds, 0u);
    g.update(0.9); // scattered: past the bound
    EXPECT_EQ(g.lastTimings().rebuilds, 1u) << "the SAH after refit did not pass the bound";
    expectSameHits(g, *rig, 0.9, 4, 10);
    // The previous triangles follow the rebuilt order: a hit's point one frame ago lies on the
    // same triangle as it was at 0.01.
    const std::vector<BvhTriangle> before = worldTriangles(*rig, 0.01);
    int checked = 0;
    for (const Ray& r : raysAtTheScene(4000, 6)) {
        const DynamicHit h = g.intersect(r);
        if (!h.valid()) continue;
        const glm::vec3 p = g.previousPosition(h);
        const uint32_t sceneTriangle =
            g.bottomLevel(g.bottomLevelOf(0)).triangleOrder()[h.triangle];
        const BvhTriangle& t = before[sceneTriangle];
        const glm::vec3 expected = t.v0 + h.u * t.e1 + h.v * t.e2;
        EXPECT_NEAR(glm::distance(p, expected), 0.0f, 1e-4f);
        ++checked;
    }
    EXPECT_GT(checked, 10);
}

} // namespace
} // namespace gt::scene
