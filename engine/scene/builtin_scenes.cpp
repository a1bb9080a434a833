#include "scene/builtin_scenes.hpp"

#include <cmath>
#include <cstdint>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"

namespace gt::scene {

namespace {

// Small deterministic generator (PCG32), so the scenes are identical on every platform.
class Pcg32 {
public:
    explicit Pcg32(uint64_t seed)
        : mState(seed * 6364136223846793005ull + 1442695040888963407ull) {}
    uint32_t next() {
        const uint64_t old = mState;
        mState = old * 6364136223846793005ull + 1442695040888963407ull;
        const auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        const auto rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }
    float uniform() { return static_cast<float>(next() >> 8) * (1.0f / 16777216.0f); }
    float range(float a, float b) { return a + (b - a) * uniform(); }

private:
    uint64_t mState;
};

glm::mat4 trs(glm::vec3 t, glm::vec3 s, float yawRadians = 0.0f) {
    glm::mat4 m = glm::translate(glm::mat4(1.0f), t);
    m = glm::rotate(m, yawRadians, glm::vec3(0, 1, 0));
    return glm::scale(m, s);
}

Material diffuse(glm::vec3 c, const char* name) {
    Material m;
    m.baseColor = glm::vec4(c, 1.0f);
    m.name = name;
    return m;
}

// A standing person about 1.75 m tall, facing `yaw`, built from boxes and a sphere.
void addFigure(SceneBuilder& b, glm::vec3 feet, float yaw, float height, uint32_t clothes,
               uint32_t trousers, uint32_t skin) {
    const float s = height / 1.75f;
    const glm::mat4 base = glm::scale(
        glm::rotate(glm::translate(glm::mat4(1.0f), feet), yaw, glm::vec3(0, 1, 0)), glm::vec3(s));
    auto part = [&](glm::vec3 c, glm::vec3 size) {
        return base * glm::scale(glm::translate(glm::mat4(1.0f), c), size);
    };
    b.box(part({-0.1f, 0.42f, 0}, {0.14f, 0.84f, 0.16f}), trousers); // legs
    b.box(part({0.1f, 0.42f, 0}, {0.14f, 0.84f, 0.16f}), trousers);
    b.box(part({0, 1.14f, 0}, {0.42f, 0.62f, 0.24f}), clothes);        // torso
    b.box(part({-0.28f, 1.12f, 0.02f}, {0.1f, 0.6f, 0.12f}), clothes); // arms
    b.box(part({0.28f, 1.12f, 0.02f}, {0.1f, 0.6f, 0.12f}), clothes);
    b.cylinder(part({0, 1.45f, 0}, {0.1f, 0.08f, 0.1f}), skin, 8);     // neck
    b.sphere(part({0, 1.62f, 0}, {0.22f, 0.26f, 0.23f}), skin, 6, 10); // head
}

// The market's tree at `treeBase`: trunk, planter and a crown of 2,400 small leaves.
void addTree(SceneBuilder& b, Pcg32& rng, glm::vec3 treeBase, uint32_t barkMat, uint32_t wallMat,
             const uint32_t (&leafMats)[4]) {
    b.cylinder(trs(treeBase, {0.35f, 3.2f, 0.35f}), barkMat, 12);
    b.box(trs(treeBase + glm::vec3(0, 0.25f, 0), {1.8f, 0.5f, 1.8f}), wallMat); // planter
    for (int i = 0; i < 2400; ++i) {
        glm::vec3 d;
        do {
            d = {rng.range(-1, 1), rng.range(-1, 1), rng.range(-1, 1)};
        } while (glm::dot(d, d) > 1.0f);
        const glm::vec3 c = treeBase + glm::vec3(0, 3.8f, 0) + d * glm::vec3(1.9f, 1.4f, 1.9f);
        const glm::vec3 u =
            glm::normalize(glm::vec3(rng.range(-1, 1), rng.range(-1, 1), rng.range(-1, 1))) * 0.16f;
        glm::vec3 v =
            glm::cross(u, glm::normalize(glm::vec3(rng.range(-1, 1), 1.0f, rng.range(-1, 1))));
        v = glm::normalize(v) * 0.09f;
        b.triangle({c - u, glm::normalize(glm::cross(u, v)), {0, 0}},
                   {c + v, glm::normalize(glm::cross(u, v)), {1, 0}},
                   {c + u, glm::normalize(glm::cross(u, v)), {1, 1}}, leafMats[i % 4]);
        b.triangle({c - u, glm::normalize(glm::cross(u, v)), {0, 0}},
                   {c + u, glm::normalize(glm::cross(u, v)), {1, 1}},
                   {c - v, glm::normalize(glm::cross(u, v)), {0, 1}}, leafMats[(i + 1) % 4]);
    }
}

// Two rows of dark pillars, and ceiling light panels between them with a spot under each (the
// panels are what the eye sees, the spots what casts the shadows under the direct integrator;
// a path tracer samples the panels themselves, so the spots stand in for them).
void addPillarsAndLights(Scene& scene, SceneBuilder& b, float height, uint32_t pillarMat,
                         uint32_t lampMat) {
    for (int i = 0; i < 6; ++i) {
        const float z = 6.0f - 6.5f * static_cast<float>(i);
        for (float x : {-5.0f, 5.0f})
            b.cylinder(trs({x, 0, z}, {0.7f, height, 0.7f}), pillarMat, 20);
        b.quad({-1.2f, height - 0.02f, z - 3.6f}, {2.4f, 0, 0}, {0, 0, 0.6f}, lampMat);
        // Downlights (spots) so the ceiling around each panel stays dim: bright panels on a
        // darker ceiling, as in the study's "lights on the ceiling of a shop".
        Light light;
        light.type = LightType::Spot;
        light.position = {0.0f, height - 0.05f, z - 3.3f};
        light.direction = {0.0f, -1.0f, 0.0f};
        light.color = {1.0f, 0.95f, 0.85f};
        light.intensity = 70.0f;
        light.innerConeCos = std::cos(glm::radians(35.0f));
        light.outerConeCos = std::cos(glm::radians(75.0f));
        light.standsInForEmitter = true; // for the panel above it
        scene.lights.push_back(light);
    }
}

} // namespace

Scene makeMarket() {
    Scene scene;
    scene.name = "builtin:market";
    SceneBuilder b(scene);
    Pcg32 rng(2016);

    // Hall: x in [-10, 10], z in [-30, 10], y in [0, 7]; the far end (z = -30) is open.
    constexpr float kW = 10.0f, kZ0 = -30.0f, kZ1 = 10.0f, kH = 7.0f;
    const uint32_t floorMat = b.material(diffuse({0.42f, 0.40f, 0.37f}, "floor"));
    const uint32_t wallMat = b.material(diffuse({0.88f, 0.86f, 0.80f}, "wall"));
    const uint32_t ceilingMat = b.material(diffuse({0.80f, 0.80f, 0.78f}, "ceiling"));
    const uint32_t pillarMat = b.material(diffuse({0.035f, 0.035f, 0.04f}, "pillar"));
    Material lamp = diffuse({1.0f, 1.0f, 1.0f}, "lamp");
    lamp.emissive = glm::vec3(12.0f, 11.0f, 9.5f);
    const uint32_t lampMat = b.material(lamp);
    Material glass = diffuse({0.75f, 0.8f, 0.85f}, "shop glass");
    glass.metallic = 0.85f;
    glass.roughness = 0.05f;
    const uint32_t glassMat = b.material(glass);
    Material chrome = diffuse({0.95f, 0.93f, 0.88f}, "chrome");
    chrome.metallic = 1.0f;
    chrome.roughness = 0.0f;
    const uint32_t chromeMat = b.material(chrome);
    const uint32_t barkMat = b.material(diffuse({0.16f, 0.1f, 0.06f}, "bark"));
    const uint32_t awningMats[3] = {b.material(diffuse({0.7f, 0.12f, 0.1f}, "awning red")),
                                    b.material(diffuse({0.1f, 0.35f, 0.65f}, "awning blue")),
                                    b.material(diffuse({0.85f, 0.6f, 0.1f}, "awning yellow"))};
    uint32_t leafMats[4];
    for (int i = 0; i < 4; ++i) {
        leafMats[i] = b.material(diffuse(
            {0.08f + 0.04f * static_cast<float>(i), 0.35f + 0.06f * static_cast<float>(i), 0.06f},
            "leaf"));
    }
    uint32_t clothes[6];
    const glm::vec3 clothColours[6] = {{0.7f, 0.1f, 0.1f},  {0.1f, 0.2f, 0.6f},
                                       {0.9f, 0.9f, 0.85f}, {0.05f, 0.05f, 0.05f},
                                       {0.2f, 0.5f, 0.2f},  {0.8f, 0.5f, 0.1f}};
    for (int i = 0; i < 6; ++i)
        clothes[i] = b.material(diffuse(clothColours[i], "clothes"));
    const uint32_t denim = b.material(diffuse({0.12f, 0.15f, 0.3f}, "trousers"));
    const uint32_t skinMats[3] = {b.material(diffuse({0.8f, 0.6f, 0.5f}, "skin")),
                                  b.material(diffuse({0.45f, 0.3f, 0.2f}, "skin")),
                                  b.material(diffuse({0.25f, 0.16f, 0.1f}, "skin"))};

    // Shell: floor, ceiling, side walls, the near wall behind the camera.
    b.quad({-kW, 0, kZ1}, {2 * kW, 0, 0}, {0, 0, kZ0 - kZ1}, floorMat, {8, 16});
    b.quad({-kW, kH, kZ0}, {2 * kW, 0, 0}, {0, 0, kZ1 - kZ0}, ceilingMat);
    b.quad({-kW, 0, kZ0}, {0, 0, kZ1 - kZ0}, {0, kH, 0}, wallMat);
    b.quad({kW, 0, kZ1}, {0, 0, kZ0 - kZ1}, {0, kH, 0}, wallMat);
    b.quad({kW, 0, kZ1}, {-2 * kW, 0, 0}, {0, kH, 0}, wallMat);

    // Two rows of dark pillars, and ceiling light panels between them with a spot under each.
    addPillarsAndLights(scene, b, kH, pillarMat, lampMat);
    // Shopfronts along both walls: glass windows, a counter and a coloured awning.
    for (int i = 0; i < 5; ++i) {
        const float z = 3.0f - 7.0f * static_cast<float>(i);
        for (float side : {-1.0f, 1.0f}) {
            const float x = side * (kW - 0.02f);
            b.quad({x, 0.9f, z + 2.5f}, {0, 0, -5.0f}, {0, 1.8f, 0}, glassMat);
            b.box(trs({side * (kW - 0.6f), 0.45f, z}, {1.0f, 0.9f, 4.8f}), wallMat);
            b.box(trs({side * (kW - 0.9f), 3.0f, z}, {1.8f, 0.08f, 5.0f}),
                  awningMats[(i + (side > 0 ? 1 : 0)) % 3]);
        }
    }
    // The tree: a trunk and a crown of many small leaves (thesis, 6.3: flickering leaves).
    const glm::vec3 treeBase(2.2f, 0.0f, -9.0f);
    addTree(b, rng, treeBase, barkMat, wallMat, leafMats);
    // A mirror sphere on a plinth.
    b.box(trs({-2.0f, 0.4f, -4.0f}, {1.2f, 0.8f, 1.2f}), pillarMat);
    b.sphere(trs({-2.0f, 1.45f, -4.0f}, {1.3f, 1.3f, 1.3f}), chromeMat, 16, 24);
    // Human figures scattered along the hall.
    for (int i = 0; i < 14; ++i) {
        const glm::vec3 feet(rng.range(-7.5f, 7.5f), 0.0f, rng.range(-26.0f, 4.0f));
        if (std::abs(feet.x - treeBase.x) < 1.5f && std::abs(feet.z - treeBase.z) < 1.5f) continue;
        addFigure(b, feet, rng.range(0.0f, 6.283f), rng.range(1.55f, 1.9f), clothes[i % 6], denim,
                  skinMats[i % 3]);
    }

    scene.camera.position = {0.6f, 1.7f, 8.5f};
    scene.camera.forward = glm::normalize(glm::vec3(-0.05f, -0.06f, -1.0f));
    scene.camera.yfov = glm::radians(75.0f);
    scene.sky.horizon = {2.2f, 2.3f, 2.4f}; // the open end is much brighter than the hall
    scene.sky.zenith = {0.9f, 1.3f, 2.2f};
    scene.sky.ambient = 0.08f;
    scene.exposure = 1.0f;
    return scene;
}

Scene makeCornell() {
    Scene scene;
    scene.name = "builtin:cornell";
    SceneBuilder b(scene);
    const uint32_t white = b.material(diffuse({0.73f, 0.73f, 0.73f}, "white"));
    const uint32_t red = b.material(diffuse({0.65f, 0.05f, 0.05f}, "red"));
    const uint32_t green = b.material(diffuse({0.12f, 0.45f, 0.15f}, "green"));
    Material lamp = diffuse({1, 1, 1}, "lamp");
    lamp.emissive = {15.0f, 15.0f, 15.0f};
    const uint32_t lampMat = b.material(lamp);
    Material mirror = diffuse({0.9f, 0.9f, 0.9f}, "mirror");
    mirror.metallic = 1.0f;
    mirror.roughness = 0.0f;
    const uint32_t mirrorMat = b.material(mirror);

    b.quad({-1, 0, 1}, {2, 0, 0}, {0, 0, -2}, white); // floor
    b.quad({-1, 2, -1}, {2, 0, 0}, {0, 0, 2}, white); // ceiling
    b.quad({-1, 0, -1}, {2, 0, 0}, {0, 2, 0}, white); // back
    b.quad({-1, 0, 1}, {0, 0, -2}, {0, 2, 0}, red);   // left
    b.quad({1, 0, -1}, {0, 0, 2}, {0, 2, 0}, green);  // right
    b.quad({-0.25f, 1.995f, -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, lampMat);
    b.box(trs({-0.35f, 0.6f, -0.3f}, {0.6f, 1.2f, 0.6f}, 0.3f), white);
    b.box(trs({0.35f, 0.3f, 0.3f}, {0.6f, 0.6f, 0.6f}, -0.3f), mirrorMat);

    Light light;
    light.type = LightType::Spot;
    light.position = {0.0f, 1.98f, 0.0f};
    light.direction = {0.0f, -1.0f, 0.0f};
    light.intensity = 3.0f;
    light.innerConeCos = std::cos(glm::radians(50.0f));
    light.outerConeCos = std::cos(glm::radians(85.0f));
    light.standsInForEmitter = true; // the ceiling lamp's light, for the direct integrator
    scene.lights.push_back(light);
    scene.camera.position = {0.0f, 1.0f, 3.4f};
    scene.camera.forward = {0.0f, 0.0f, -1.0f};
    scene.camera.yfov = glm::radians(40.0f);
    scene.sky.ambient = 0.1f;
    return scene;
}

// A sculpture gallery made of Catmull-Clark cages (the geometric LOD's test content, Guenter et al.
// 2012 section 6): rounded blocks, slabs, pillars and rings on plinths along a hall, lit by a sun
// through the open side and lamps; only the room itself is plain triangles.
Scene makeGallery() {
    Scene scene;
    scene.name = "builtin:gallery";
    SceneBuilder b(scene);
    Pcg32 rng(2012);
    constexpr float kW = 8.0f, kZ0 = -34.0f, kZ1 = 6.0f, kH = 6.0f;
    const uint32_t floorMat = b.material(diffuse({0.30f, 0.29f, 0.27f}, "floor"));
    const uint32_t wallMat = b.material(diffuse({0.82f, 0.80f, 0.76f}, "wall"));
    const uint32_t plinthMat = b.material(diffuse({0.9f, 0.9f, 0.88f}, "plinth"));
    const glm::vec3 colours[6] = {{0.75f, 0.2f, 0.12f}, {0.12f, 0.3f, 0.7f},   {0.85f, 0.7f, 0.2f},
                                  {0.1f, 0.5f, 0.3f},   {0.05f, 0.05f, 0.06f}, {0.9f, 0.9f, 0.9f}};
    uint32_t stone[6];
    for (int i = 0; i < 6; ++i)
        stone[i] = b.material(diffuse(colours[i], "sculpture"));
    Material bronze = diffuse({0.8f, 0.55f, 0.3f}, "bronze");
    bronze.metallic = 1.0f;
    bronze.roughness = 0.3f;
    const uint32_t bronzeMat = b.material(bronze);

    b.quad({-kW, 0, kZ1}, {2 * kW, 0, 0}, {0, 0, kZ0 - kZ1}, floorMat, {6, 16});
    b.quad({-kW, 0, kZ0}, {0, 0, kZ1 - kZ0}, {0, kH, 0}, wallMat); // left wall; right side open
    b.quad({kW, 0, kZ0}, {-2 * kW, 0, 0}, {0, kH, 0}, wallMat);    // far wall
    for (int i = 0; i < 7; ++i) {
        const float z = 2.0f - 5.0f * static_cast<float>(i);
        for (const float x : {-4.0f, 0.5f, 4.5f}) {
            const float jitter = 0.6f * (rng.uniform() - 0.5f);
            const glm::vec3 base(x + jitter, 0.0f, z + jitter);
            b.box(trs(base + glm::vec3(0, 0.4f, 0), {0.9f, 0.8f, 0.9f}), plinthMat);
            const float yaw = 6.28f * rng.uniform();
            const uint32_t mat = (i + static_cast<int>(x)) % 4 == 0
                                     ? bronzeMat
                                     : stone[static_cast<int>(rng.uniform() * 5.99f)];
            switch ((i * 3 + static_cast<int>(x + 4.0f)) % 4) {
            case 0: // a rounded block
                b.boxCage(trs(base + glm::vec3(0, 1.3f, 0), {1.0f, 1.0f, 1.0f}, yaw), mat);
                break;
            case 1: // a slab on edge
                b.boxCage(trs(base + glm::vec3(0, 1.6f, 0), {1.1f, 1.6f, 0.3f}, yaw), mat, "slab");
                break;
            case 2: // a ring standing up
                b.torusCage(glm::rotate(trs(base + glm::vec3(0, 1.7f, 0), {1.6f, 1.6f, 1.6f}, yaw),
                                        1.5708f, glm::vec3(1, 0, 0)),
                            mat, 12, 6);
                break;
            default: // a pillar
                b.boxCage(trs(base + glm::vec3(0, 2.0f, 0), {0.35f, 2.4f, 0.35f}, yaw), mat,
                          "pillar");
                break;
            }
        }
    }
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(-0.6f, -0.7f, -0.3f));
    sun.intensity = 2.5f;
    sun.color = {1.0f, 0.95f, 0.85f};
    scene.lights.push_back(sun);
    for (int i = 0; i < 3; ++i) {
        Light lamp;
        lamp.position = {0.0f, kH - 0.3f, -2.0f - 12.0f * static_cast<float>(i)};
        lamp.intensity = 40.0f;
        lamp.color = {1.0f, 0.9f, 0.75f};
        scene.lights.push_back(lamp);
    }
    scene.camera = lookAt({0.5f, 1.7f, 5.0f}, {0.3f, 1.4f, -10.0f}, glm::radians(60.0f));
    scene.sky.ambient = 0.12f;
    return scene;
}

std::vector<std::string> builtinSceneNames() {
    return {"builtin:market", "builtin:cornell", "builtin:gallery"};
}

Scene makeBuiltin(const std::string& spec) {
    if (spec == "builtin:market") return makeMarket();
    if (spec == "builtin:cornell") return makeCornell();
    if (spec == "builtin:gallery") return makeGallery();
    throw LoadError("unknown built-in scene '" + spec +
                    "' (known: builtin:market, builtin:cornell, builtin:gallery)");
}

} // namespace gt::scene
