// The emissive triangles' alias table the path tracer draws lights from (gpu_scene.cpp,
// packEmitters): each triangle is drawn with probability emitted power / total power.
#include <bit>
#include <map>

#include <gtest/gtest.h>

#include "scene/builtin_scenes.hpp"
#include "scene/bvh.hpp"
#include "scene/scene.hpp"
#include "trace/gpu_scene.hpp"

namespace gt {
namespace {

TEST(EmitterTable, DrawsEachTriangleByItsPower) {
    scene::Scene s;
    scene::SceneBuilder b(s);
    scene::Material dark, dim, bright, unlit;
    dim.emissive = {1.0f, 1.0f, 1.0f};
    bright.emissive = {0.0f, 8.0f, 0.0f};
    unlit.emissive = {5.0f, 5.0f, 5.0f};
    unlit.unlit = true; // its base colour is what the eye sees: no light to sample
    b.quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, b.material(dark));
    b.quad({0, 0, 1}, {2, 0, 0}, {0, 1, 0}, b.material(dim));       // area 2, luminance 1
    b.quad({0, 0, 2}, {1, 0, 0}, {0, 0.5f, 0}, b.material(bright)); // area 0.5, lum 8 * 0.7152
    b.quad({0, 0, 3}, {1, 0, 0}, {0, 1, 0}, b.material(unlit));
    const scene::Bvh bvh(s);
    const trace::PackedScene p = trace::packScene(s, bvh);
    ASSERT_EQ(p.uniforms.emitters.x, 4u); // two triangles per emissive quad
    ASSERT_EQ(p.emitters.size(), 4u);
    EXPECT_EQ(p.uniforms.emitters.y, p.materials.size());
    const double dimPower = 2.0, brightPower = 0.5 * 8.0 * 0.7152;
    EXPECT_NEAR(std::bit_cast<float>(p.uniforms.emitters.z), dimPower + brightPower, 1e-4);
    // The probability of each triangle: its own entry kept, plus the entries aliasing it.
    std::map<uint32_t, double> drawn;
    for (const glm::vec4& e : p.emitters) {
        const uint32_t alias = std::bit_cast<uint32_t>(e.y);
        ASSERT_LT(alias, p.emitters.size());
        drawn[std::bit_cast<uint32_t>(e.z)] += e.x / 4.0;
        drawn[std::bit_cast<uint32_t>(p.emitters[alias].z)] += (1.0 - e.x) / 4.0;
    }
    ASSERT_EQ(drawn.size(), 4u);
    for (const auto& [tri, probability] : drawn) {
        const glm::vec4 e1 = p.triangles[3 * tri + 1], e2 = p.triangles[3 * tri + 2];
        const double area = 0.5 * glm::length(glm::cross(glm::vec3(e1), glm::vec3(e2)));
        const bool isBright = std::abs(area - 0.25) < 1e-6;
        const double power = area * (isBright ? 8.0 * 0.7152 : 1.0);
        EXPECT_NEAR(probability, power / (dimPower + brightPower), 1e-6) << "triangle " << tri;
    }
}

// A built-in scene that has emissive geometry lights it under the direct integrator with
// punctual stand-ins, which the path tracer must skip (it samples the emitters): every punctual
// light of the market and the Cornell box says so, or the path tracer counts that light twice.
TEST(EmitterTable, BuiltinScenesMarkTheirPunctualStandIns) {
    for (const scene::Scene& s : {scene::makeMarket(), scene::makeCornell()}) {
        bool emissive = false;
        for (const scene::Material& m : s.materials)
            emissive = emissive || m.emissive != glm::vec3(0.0f);
        ASSERT_TRUE(emissive) << s.name;
        ASSERT_FALSE(s.lights.empty()) << s.name;
        for (const scene::Light& l : s.lights)
            EXPECT_TRUE(l.standsInForEmitter) << s.name;
    }
}

} // namespace
} // namespace gt
