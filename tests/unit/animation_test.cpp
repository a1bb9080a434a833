// glTF 2.0 animation, skins and morph targets (animation.hpp) on rigs built here, against values
// worked out by hand from the specification's formulas: samplers (3.11 and Appendix C), the node
// hierarchy, linear blend skinning (3.7.3) and morph targets (3.7.2.2).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"
#include "scene/animation.hpp"

namespace gt::scene {
namespace {

constexpr float kEps = 1e-5f;
const float kHalfSqrt2 = std::sqrt(0.5f);

AnimationSampler sampler(std::vector<float> times, std::vector<float> values, uint32_t components,
                         Interpolation interpolation) {
    AnimationSampler s;
    s.times = std::move(times);
    s.values = std::move(values);
    s.components = components;
    s.interpolation = interpolation;
    return s;
}

std::array<float, 4> sample(const AnimationSampler& s, AnimatedPath path, float t) {
    std::array<float, 4> out{};
    sampleAnimation(s, path, t, std::span<float>(out.data(), s.components));
    return out;
}

void expectVec3(const glm::vec3& got, const glm::vec3& want, float eps = kEps) {
    EXPECT_NEAR(got.x, want.x, eps) << "x";
    EXPECT_NEAR(got.y, want.y, eps) << "y";
    EXPECT_NEAR(got.z, want.z, eps) << "z";
}

glm::vec3 origin(const glm::mat4& m) {
    return glm::vec3(m[3]);
}

// A rotation of `degrees` about +Y as glTF stores it: x, y, z, w.
std::vector<float> rotationY(float degrees) {
    const float half = glm::radians(degrees) * 0.5f;
    return {0.0f, std::sin(half), 0.0f, std::cos(half)};
}

// Rotates +X by a sampled x, y, z, w quaternion: sign-independent, unlike the components.
glm::vec3 rotateX(const std::array<float, 4>& q) {
    return glm::quat(q[3], q[0], q[1], q[2]) * glm::vec3(1.0f, 0.0f, 0.0f);
}

RigNode node(int parent, const glm::vec3& translation = glm::vec3(0.0f),
             const glm::quat& rotation = glm::quat(1.0f, 0.0f, 0.0f, 0.0f)) {
    RigNode n;
    n.parent = parent;
    n.rest.translation = translation;
    n.rest.rotation = rotation;
    return n;
}

Animation animation(std::string name, AnimationSampler s, uint32_t target, AnimatedPath path) {
    Animation a;
    a.name = std::move(name);
    a.duration = s.times.back();
    a.samplers.push_back(std::move(s));
    a.channels.push_back({0, target, path});
    return a;
}

Vertex vertex(const glm::vec3& position, const glm::vec3& normal) {
    return {position, normal, glm::vec2(0.0f)};
}

TEST(AnimationSampler, LinearTranslationAtMidpointAndQuarter) {
    const AnimationSampler s = sampler({0.0f, 2.0f}, {0, 0, 0, 4, -2, 6}, 3, Interpolation::Linear);
    const auto mid = sample(s, AnimatedPath::Translation, 1.0f);
    expectVec3({mid[0], mid[1], mid[2]}, {2.0f, -1.0f, 3.0f});
    const auto quarter = sample(s, AnimatedPath::Translation, 0.5f);
    expectVec3({quarter[0], quarter[1], quarter[2]}, {1.0f, -0.5f, 1.5f});
}

TEST(AnimationSampler, StepHoldsEachKeyUntilTheNextAndClampsOutside) {
    const AnimationSampler s =
        sampler({0.0f, 1.0f, 2.0f}, {1, 0, 0, 5, 0, 0, 9, 0, 0}, 3, Interpolation::Step);
    EXPECT_FLOAT_EQ(sample(s, AnimatedPath::Translation, -1.0f)[0], 1.0f); // before the first key
    EXPECT_FLOAT_EQ(sample(s, AnimatedPath::Translation, 0.99f)[0], 1.0f);
    EXPECT_FLOAT_EQ(sample(s, AnimatedPath::Translation, 1.0f)[0], 5.0f);
    EXPECT_FLOAT_EQ(sample(s, AnimatedPath::Translation, 1.5f)[0], 5.0f);
    EXPECT_FLOAT_EQ(sample(s, AnimatedPath::Translation, 2.5f)[0], 9.0f); // after the last key
}

TEST(AnimationSampler, OneKeyHoldsItsValueAtEveryTime) {
    const AnimationSampler s = sampler({0.5f}, {3, 4, 5}, 3, Interpolation::Linear);
    for (const float t : {0.0f, 0.5f, 7.0f}) {
        const auto v = sample(s, AnimatedPath::Scale, t);
        expectVec3({v[0], v[1], v[2]}, {3.0f, 4.0f, 5.0f});
    }
}

// Appendix C: keys at 1 and 3 s (interval 2), x: v0 = 0, out-tangent b0 = 1, in-tangent a1 = -1,
// v1 = 2; the unused in-tangent of key 0 and out-tangent of key 1 are 100. At t = 1.5, u = 0.25:
// h00 = 2u³-3u²+1 = 0.84375, h10 = u³-2u²+u = 0.140625, h01 = -2u³+3u² = 0.15625,
// h11 = u³-u² = -0.046875; p = 0.84375*0 + 0.140625*(2*1) + 0.15625*2 + (-0.046875)*(2*-1)
// = 0.28125 + 0.3125 + 0.09375 = 0.6875. y is 1 at both keys with zero tangents: constant.
TEST(AnimationSampler, CubicSplineIsHermiteWithTangentsScaledByTheKeyInterval) {
    const AnimationSampler s = sampler({1.0f, 3.0f},
                                       {100, 0, 0, 0, 1, 0, 1, 0, 0,   // key 0: a0, v0, b0
                                        -1, 0, 0, 2, 1, 0, 100, 0, 0}, // key 1: a1, v1, b1
                                       3, Interpolation::CubicSpline);
    const auto v = sample(s, AnimatedPath::Translation, 1.5f);
    EXPECT_NEAR(v[0], 0.6875f, kEps);
    EXPECT_NEAR(v[1], 1.0f, kEps);
    // Outside the keys the value holds, never a tangent.
    EXPECT_FLOAT_EQ(sample(s, AnimatedPath::Translation, 0.0f)[0], 0.0f);
    EXPECT_FLOAT_EQ(sample(s, AnimatedPath::Translation, 5.0f)[0], 2.0f);
    EXPECT_FLOAT_EQ(sample(s, AnimatedPath::Translation, 3.0f)[0], 2.0f);
}

// Identity to 90° about Y with zero tangents: at u = 0.5 the Hermite gives the plain average
// (0, 0.35355, 0, 0.85355), of length 0.92388; normalised it is 45° about Y.
TEST(AnimationSampler, CubicSplineRotationIsNormalised) {
    std::vector<float> values = {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0};
    const std::vector<float> ninety = rotationY(90.0f);
    values.insert(values.end(), {0, 0, 0, 0});
    values.insert(values.end(), ninety.begin(), ninety.end());
    values.insert(values.end(), {0, 0, 0, 0});
    const auto q = sample(sampler({0.0f, 1.0f}, values, 4, Interpolation::CubicSpline),
                          AnimatedPath::Rotation, 0.5f);
    const std::vector<float> want = rotationY(45.0f);
    for (int i = 0; i < 4; ++i)
        EXPECT_NEAR(q[i], want[i], kEps) << i;
}

// Slerp (Appendix C) from identity to 90° about Y: at u = 0.5 it is 45° (0, sin 22.5°, 0,
// cos 22.5°), at u = 0.25 22.5° (0, 0.19509, 0, 0.98079); a normalised lerp would give
// (0, 0.18737, 0, 0.98229) there.
TEST(AnimationSampler, LinearRotationIsSphericalAtConstantAngularSpeed) {
    std::vector<float> values = {0, 0, 0, 1};
    const std::vector<float> ninety = rotationY(90.0f);
    values.insert(values.end(), ninety.begin(), ninety.end());
    const AnimationSampler s = sampler({0.0f, 1.0f}, values, 4, Interpolation::Linear);
    for (const auto& [t, degrees] : {std::pair{0.5f, 45.0f}, std::pair{0.25f, 22.5f}}) {
        const auto q = sample(s, AnimatedPath::Rotation, t);
        const std::vector<float> want = rotationY(degrees);
        for (int i = 0; i < 4; ++i)
            EXPECT_NEAR(q[i], want[i], kEps) << "t " << t << " " << i;
    }
}

// The second key is -(90° about Y): the same rotation with every sign flipped. The shorter arc
// passes 45° about Y at u = 0.5, turning +X to (cos 45°, 0, -sin 45°); the longer arc would pass
// -135° about Y, turning +X to (-0.70711, 0, 0.70711).
TEST(AnimationSampler, LinearRotationTakesTheShorterArcPastASignFlip) {
    std::vector<float> values = {0, 0, 0, 1};
    for (const float c : rotationY(90.0f))
        values.push_back(-c);
    const auto q = sample(sampler({0.0f, 1.0f}, values, 4, Interpolation::Linear),
                          AnimatedPath::Rotation, 0.5f);
    expectVec3(rotateX(q), {kHalfSqrt2, 0.0f, -kHalfSqrt2});
    EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0f, kEps);
}

TEST(AnimationPose, LoopsEachAnimationOverItsDuration) {
    Rig rig;
    rig.nodes.push_back(node(-1));
    rig.animations.push_back(
        animation("slide", sampler({0.0f, 2.0f}, {0, 0, 0, 4, 0, 0}, 3, Interpolation::Linear), 0,
                  AnimatedPath::Translation));
    const AnimationChoice all = chooseAnimation(rig, "all");
    EXPECT_NEAR(origin(evaluatePose(rig, all, 0.5).world[0]).x, 1.0f, kEps);
    EXPECT_NEAR(origin(evaluatePose(rig, all, 5.0).world[0]).x, 2.0f, kEps); // 5 s = 2 * 2 s + 1 s
    EXPECT_NEAR(origin(evaluatePose(rig, all, 102.5).world[0]).x, 1.0f, kEps); // 51 loops + 0.5 s
    EXPECT_NEAR(origin(evaluatePose(rig, all, -0.5).world[0]).x, 3.0f, kEps);  // 2 s - 0.5 s
    // "none" leaves the rest pose.
    EXPECT_NEAR(origin(evaluatePose(rig, chooseAnimation(rig, "none"), 1.0).world[0]).x, 0.0f,
                kEps);
}

TEST(AnimationPose, BeforeTheFirstKeyTheFirstValueHolds) {
    Rig rig;
    rig.nodes.push_back(node(-1, {7.0f, 0.0f, 0.0f}));
    rig.animations.push_back(
        animation("late", sampler({1.0f, 2.0f}, {1, 0, 0, 3, 0, 0}, 3, Interpolation::Linear), 0,
                  AnimatedPath::Translation));
    EXPECT_NEAR(origin(evaluatePose(rig, {}, 0.5).world[0]).x, 1.0f, kEps);
    EXPECT_NEAR(origin(evaluatePose(rig, {}, 1.5).world[0]).x, 2.0f, kEps);
}

// The parent at (10, 0, 0) is turned 90° about Y by a one-key animation (duration 0: it holds);
// the child sits at (1, 0, 0) in the parent's space. World = parent * child: Ry(90°) turns +X to
// -Z, so the child is at (10, 0, -1) and its +X axis points along -Z.
TEST(AnimationPose, ChildFollowsItsRotatedParent) {
    Rig rig;
    rig.nodes.push_back(node(-1, {10.0f, 0.0f, 0.0f}));
    rig.nodes.push_back(node(0, {1.0f, 0.0f, 0.0f}));
    rig.animations.push_back(animation("turn",
                                       sampler({0.0f}, rotationY(90.0f), 4, Interpolation::Linear),
                                       0, AnimatedPath::Rotation));
    ASSERT_EQ(rig.animations[0].duration, 0.0f);
    const Pose pose = evaluatePose(rig, {}, 3.7);
    expectVec3(origin(pose.world[1]), {10.0f, 0.0f, -1.0f});
    expectVec3(glm::vec3(pose.world[1][0]), {0.0f, 0.0f, -1.0f});
}

TEST(AnimationPose, MatrixNodesKeepTheirMatrixUnderAnimatedParents) {
    Rig rig;
    rig.nodes.push_back(node(-1));
    RigNode child = node(0);
    child.hasMatrix = true;
    child.matrix = glm::translate(glm::mat4(1.0f), {0.0f, 2.0f, 0.0f});
    rig.nodes.push_back(child);
    rig.animations.push_back(
        animation("lift", sampler({0.0f, 1.0f}, {0, 0, 0, 0, 0, 4}, 3, Interpolation::Linear), 0,
                  AnimatedPath::Translation));
    expectVec3(origin(evaluatePose(rig, {}, 0.5).world[1]), {0.0f, 2.0f, 2.0f});
}

TEST(AnimationPose, OneChoicePlaysOnlyThatAnimation) {
    Rig rig;
    rig.nodes.push_back(node(-1));
    rig.animations.push_back(animation("x", sampler({0.0f}, {1, 0, 0}, 3, Interpolation::Step), 0,
                                       AnimatedPath::Translation));
    rig.animations.push_back(
        animation("s", sampler({0.0f}, {2, 2, 2}, 3, Interpolation::Step), 0, AnimatedPath::Scale));
    const Pose x = evaluatePose(rig, chooseAnimation(rig, "0"), 0.0);
    expectVec3(origin(x.world[0]), {1.0f, 0.0f, 0.0f});
    EXPECT_NEAR(x.world[0][0][0], 1.0f, kEps);
    const Pose s = evaluatePose(rig, chooseAnimation(rig, "s"), 0.0);
    expectVec3(origin(s.world[0]), {0.0f, 0.0f, 0.0f});
    EXPECT_NEAR(s.world[0][0][0], 2.0f, kEps);
}

// Two joints: joint 0 at the origin, joint 1 its child at (0, 1, 0) in the bind pose
// (inverse bind = translate(0, -1, 0)), posed turned 90° about Z. The mesh node sits at
// (100, 0, 0), which skinning ignores (glTF 3.7.3.3). A vertex at (1, 1, 0) bound fully to
// joint 1: translate(0, 1, 0) * Rz(90°) * translate(0, -1, 0) takes it to (1, 0, 0), then
// (0, 1, 0), then (0, 2, 0); its normal +X turns to +Y. Half to each joint: the blend of the
// matrices takes it to 0.5 * (1, 1, 0) + 0.5 * (0, 2, 0) = (0.5, 1.5, 0), and its normal by
// (0.5 I + 0.5 Rz(90°))^-T to (1, 1, 0) / sqrt 2.
Rig twoJointRig() {
    Rig rig;
    rig.nodes.push_back(node(-1));
    rig.nodes.push_back(node(0, {0.0f, 1.0f, 0.0f},
                             glm::angleAxis(glm::radians(90.0f), glm::vec3(0.0f, 0.0f, 1.0f))));
    rig.nodes.push_back(node(-1, {100.0f, 0.0f, 0.0f}));
    rig.skins.push_back(
        {"arm", {0, 1}, {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), {0.0f, -1.0f, 0.0f})}});
    RigMesh mesh;
    mesh.vertices = {vertex({1.0f, 1.0f, 0.0f}, {1.0f, 0.0f, 0.0f}),
                     vertex({1.0f, 1.0f, 0.0f}, {1.0f, 0.0f, 0.0f}),
                     vertex({0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 1.0f})};
    mesh.joints = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 0, 0}};
    mesh.weights = {{1.0f, 0.0f, 0.0f, 0.0f}, {0.5f, 0.5f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f, 0.0f}};
    rig.meshes.push_back(mesh);
    rig.instances.push_back({2, 0, 0});
    return rig;
}

TEST(AnimationSkin, JointRotated90DegreesMovesItsVerticesWhereTheMathsSays) {
    const Rig rig = twoJointRig();
    const Pose pose = evaluatePose(rig, {}, 0.0);
    std::vector<Vertex> out;
    deformInstance(rig, rig.instances[0], pose, out);
    ASSERT_EQ(out.size(), 3u);
    expectVec3(out[0].position, {0.0f, 2.0f, 0.0f});
    expectVec3(out[0].normal, {0.0f, 1.0f, 0.0f});
    expectVec3(out[1].position, {0.5f, 1.5f, 0.0f});
    expectVec3(out[1].normal, {kHalfSqrt2, kHalfSqrt2, 0.0f});
    expectVec3(out[2].position, {0.0f, 0.0f, 3.0f}); // joint 0 is at its bind pose
    EXPECT_TRUE(deforms(rig, rig.instances[0]));
    EXPECT_EQ(instanceTransform(rig, rig.instances[0], pose), glm::mat4(1.0f));
}

// A mirrored joint (scale -1 in X) flips positions; the normal follows the inverse transpose,
// (-1, 0, 0) for +X, not the cofactor's unsigned direction.
TEST(AnimationSkin, MirroredJointTurnsNormalsByTheInverseTranspose) {
    Rig rig = twoJointRig();
    rig.nodes[0].rest.scale = {-1.0f, 1.0f, 1.0f};
    rig.nodes[1].rest.rotation = glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
    std::vector<Vertex> out;
    deformInstance(rig, rig.instances[0], evaluatePose(rig, {}, 0.0), out);
    expectVec3(out[0].position, {-1.0f, 1.0f, 0.0f});
    expectVec3(out[0].normal, {-1.0f, 0.0f, 0.0f});
}

// One target moves the vertex by (0, 4, 0) and adds (4, 0, 0) to its normal; a second moves it
// by (0, 0, 8). With the node's weights (0.25, 0) the vertex (1, 0, 0) moves a quarter of the
// way to (1, 1, 0) and its normal (0, 0, 1) turns to (1, 0, 1) / sqrt 2. The node at
// (100, 0, 0) is not applied: a mesh that is not skinned stays in its own space.
Rig morphRig() {
    Rig rig;
    RigNode n = node(-1, {100.0f, 0.0f, 0.0f});
    n.weights = {0.25f, 0.0f};
    rig.nodes.push_back(n);
    RigMesh mesh;
    mesh.vertices = {vertex({1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f})};
    mesh.targets.push_back({{{0.0f, 4.0f, 0.0f}}, {{4.0f, 0.0f, 0.0f}}});
    mesh.targets.push_back({{{0.0f, 0.0f, 8.0f}}, {}});
    rig.meshes.push_back(mesh);
    rig.instances.push_back({0, 0, -1});
    return rig;
}

TEST(AnimationMorph, WeightedTargetsMoveVerticesAndTurnNormals) {
    const Rig rig = morphRig();
    const Pose pose = evaluatePose(rig, {}, 0.0);
    std::vector<Vertex> out;
    deformInstance(rig, rig.instances[0], pose, out);
    ASSERT_EQ(out.size(), 1u);
    expectVec3(out[0].position, {1.0f, 1.0f, 0.0f});
    expectVec3(out[0].normal, {kHalfSqrt2, 0.0f, kHalfSqrt2});
    EXPECT_TRUE(deforms(rig, rig.instances[0]));
    expectVec3(origin(instanceTransform(rig, rig.instances[0], pose)), {100.0f, 0.0f, 0.0f});
}

// A weights channel replaces the node's default weights: LINEAR from (0, 0) to (1, 0.5) at
// 0.5 s gives (0.5, 0.25): the vertex moves by 0.5 * (0, 4, 0) + 0.25 * (0, 0, 8).
TEST(AnimationMorph, WeightsChannelOverridesTheNodeDefaults) {
    Rig rig = morphRig();
    rig.animations.push_back(
        animation("breathe", sampler({0.0f, 1.0f}, {0, 0, 1, 0.5f}, 2, Interpolation::Linear), 0,
                  AnimatedPath::Weights));
    const Pose pose = evaluatePose(rig, {}, 0.5);
    ASSERT_EQ(pose.weights[0].size(), 2u);
    EXPECT_NEAR(pose.weights[0][0], 0.5f, kEps);
    EXPECT_NEAR(pose.weights[0][1], 0.25f, kEps);
    std::vector<Vertex> out;
    deformInstance(rig, rig.instances[0], pose, out);
    expectVec3(out[0].position, {1.0f, 2.0f, 2.0f});
    EXPECT_EQ(evaluatePose(rig, chooseAnimation(rig, "none"), 0.5).weights[0],
              (std::vector<float>{0.25f, 0.0f}));
}

// A target that cancels a normal leaves a zero normal, not a NaN that would reach the shading.
TEST(AnimationMorph, CancelledNormalStaysFinite) {
    Rig rig = morphRig();
    rig.nodes[0].weights = {1.0f, 0.0f};
    rig.meshes[0].targets[0].normals = {{0.0f, 0.0f, -1.0f}};
    std::vector<Vertex> out;
    deformInstance(rig, rig.instances[0], evaluatePose(rig, {}, 0.0), out);
    expectVec3(out[0].normal, {0.0f, 0.0f, 0.0f});
}

std::string chooseError(const Rig& rig, const std::string& value) {
    try {
        (void)chooseAnimation(rig, value);
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(AnimationChoose, ResolvesKeywordsIndicesAndNames) {
    Rig rig;
    rig.animations.resize(2);
    rig.animations[0].name = "idle";
    rig.animations[1].name = "run";
    EXPECT_EQ(chooseAnimation(rig, "all").kind, AnimationChoice::Kind::All);
    EXPECT_EQ(chooseAnimation(rig, "none").kind, AnimationChoice::Kind::None);
    const AnimationChoice byIndex = chooseAnimation(rig, "1");
    EXPECT_EQ(byIndex.kind, AnimationChoice::Kind::One);
    EXPECT_EQ(byIndex.index, 1u);
    const AnimationChoice byName = chooseAnimation(rig, "idle");
    EXPECT_EQ(byName.kind, AnimationChoice::Kind::One);
    EXPECT_EQ(byName.index, 0u);
}

TEST(AnimationChoose, UnknownValueNamesItAndListsTheScenesAnimations) {
    Rig rig;
    rig.animations.resize(2);
    rig.animations[0].name = "idle";
    rig.animations[1].name = "run";
    const std::string list = "the scene has 2 animations: \"idle\", \"run\" (or an index 0-1)";
    EXPECT_EQ(chooseError(rig, "walk"), "animation \"walk\": " + list);
    EXPECT_EQ(chooseError(rig, "2"), "animation \"2\": " + list);
    EXPECT_EQ(chooseError(rig, "-1"), "animation \"-1\": " + list);
    EXPECT_EQ(chooseError(rig, "1x"), "animation \"1x\": " + list);
    EXPECT_EQ(chooseError(rig, ""), "animation \"\": " + list);
    rig.animations.resize(1);
    rig.animations[0].name.clear();
    EXPECT_EQ(chooseError(rig, "idle"),
              "animation \"idle\": the scene has 1 animation: (unnamed) (or the index 0)");
    EXPECT_EQ(chooseError(Rig{}, "0"),
              "animation \"0\": the scene has no animations (use all or none)");
}

} // namespace
} // namespace gt::scene
