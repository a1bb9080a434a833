// The path integrator's materials beyond base colour and metallic-roughness: thin-walled
// transmission and the index of refraction (KHR_materials_transmission, KHR_materials_ior),
// normal and emissive textures, and texture filtering by ray cones.
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/glm.hpp>

#include "path_test_fixture.hpp"
#include "scene/bvh.hpp"
#include "scene/scene.hpp"

namespace gt {
namespace {

using trace::Integrator;

class PathMaterialsTest : public test::PathFixture {
protected:
    std::vector<glm::vec4> renderScene(const scene::Scene& s, uint32_t size, uint32_t spp,
                                       uint32_t bounces) {
        const scene::Bvh bvh(s);
        const trace::GpuScene gpuScene(ctx(), s, bvh);
        return render(gpuScene, s, size, spp, 1, Integrator::Path, bounces);
    }
};

scene::Texture solidTexture(uint32_t r, uint32_t g, uint32_t b) {
    scene::Texture t;
    t.width = t.height = 1;
    t.rgba = {r | (g << 8) | (b << 16) | (255u << 24)};
    return t;
}

glm::dvec3 mean(const std::vector<glm::vec4>& image) {
    glm::dvec3 sum(0.0);
    for (const glm::vec4& p : image)
        sum += glm::dvec3(p);
    return sum / static_cast<double>(image.size());
}

// The mean of the size x size image's centre `box` x `box` pixels.
glm::dvec3 centreMean(const std::vector<glm::vec4>& image, uint32_t size, uint32_t box) {
    glm::dvec3 sum(0.0);
    const uint32_t lo = (size - box) / 2;
    for (uint32_t y = lo; y < lo + box; ++y)
        for (uint32_t x = lo; x < lo + box; ++x)
            sum += glm::dvec3(image[static_cast<std::size_t>(y) * size + x]);
    return sum / static_cast<double>(box * box);
}

// A camera on +z looking at the origin with a `fovDeg` vertical field of view.
scene::Camera frontCamera(float distance, float fovDeg) {
    scene::Camera c;
    c.position = {0.0f, 0.0f, distance};
    c.forward = {0.0f, 0.0f, -1.0f};
    c.up = {0.0f, 1.0f, 0.0f};
    c.yfov = glm::radians(fovDeg);
    return c;
}

// A 10 x 10 Lambertian floor (no specular lobe) in the y = 0 plane, facing +y.
void whiteFloor(scene::SceneBuilder& b) {
    scene::Material white;
    white.specular = 0.0f;
    b.quad({-5.0f, 0.0f, 5.0f}, {10.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -10.0f}, b.material(white));
}

// A 2 x 2 quad in the z = 0 plane facing +z, its u along +x.
void facingQuad(scene::SceneBuilder& b, uint32_t material, glm::vec2 uvScale = {1, 1}) {
    b.quad({-1.0f, -1.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}, material, uvScale);
}

// A sheet of tinted glass seen at normal incidence against a uniform sky: the eye gets the
// sky reflected by Fresnel's F0 = ((ior - 1) / (ior + 1))^2 and transmitted straight through,
// tinted, (1 - F0) * base. At ior 2, F0 = 1/9; at glTF's default 1.5 it would be 0.04.
TEST_F(PathMaterialsTest, ThinGlassTransmitsItsTintAndReflectsByItsIor) {
    scene::Scene s;
    scene::SceneBuilder b(s);
    scene::Material glass;
    glass.baseColor = glm::vec4(1.0f, 0.5f, 0.25f, 1.0f);
    glass.roughness = 0.0f;
    glass.transmission = 1.0f;
    glass.ior = 2.0f;
    facingQuad(b, b.material(glass));
    s.sky.horizon = s.sky.zenith = s.sky.ground = glm::vec3(1.0f);
    s.camera = frontCamera(3.0f, 10.0f);
    const glm::dvec3 m = mean(renderScene(s, 32, 64, 4));
    const double f0 = 1.0 / 9.0;
    for (int c = 0; c < 3; ++c) {
        const double expected = f0 + (1.0 - f0) * glass.baseColor[c];
        std::printf("channel %d: %.4f, expected %.4f\n", c, m[c], expected);
        EXPECT_NEAR(m[c], expected, 0.006) << "channel " << c;
    }
}

// alphaMode BLEND with alpha 0.25, black and without a specular lobe, against a uniform sky:
// the eye gets the sky through the uncovered 0.75 of the surface.
TEST_F(PathMaterialsTest, BlendedSurfaceLetsItsUncoveredShareThrough) {
    scene::Scene s;
    scene::SceneBuilder b(s);
    scene::Material veil;
    veil.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 0.25f);
    veil.specular = 0.0f;
    veil.alphaBlend = true;
    facingQuad(b, b.material(veil));
    s.sky.horizon = s.sky.zenith = s.sky.ground = glm::vec3(1.0f, 0.5f, 2.0f);
    s.camera = frontCamera(3.0f, 10.0f);
    const glm::dvec3 m = mean(renderScene(s, 32, 16, 4));
    std::printf("through the veil: %.4f %.4f %.4f of the sky\n", m.r, m.g / 0.5, m.b / 2.0);
    EXPECT_NEAR(m.r, 0.75, 0.006);
    EXPECT_NEAR(m.g, 0.375, 0.003);
    EXPECT_NEAR(m.b, 1.5, 0.012);
}

// A floor lit by a point light straight above it through a pane of tinted glass: the shadow
// ray crosses the pane, which passes (1 - F0) * base of the light at normal incidence. One
// vertex (direct light only), a black sky; against the same floor without the pane.
TEST_F(PathMaterialsTest, ShadowRaysCrossThinGlassTinted) {
    const auto floorScene = [](bool pane) {
        scene::Scene s;
        scene::SceneBuilder b(s);
        whiteFloor(b);
        if (pane) {
            scene::Material glass;
            glass.baseColor = glm::vec4(1.0f, 0.5f, 0.25f, 1.0f);
            glass.roughness = 0.0f;
            glass.transmission = 1.0f;
            b.quad({-5.0f, 1.0f, 5.0f}, {10.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -10.0f},
                   b.material(glass));
        }
        scene::Light l;
        l.position = {0.0f, 2.0f, 0.0f};
        l.intensity = 10.0f;
        s.lights.push_back(l);
        s.sky.horizon = s.sky.zenith = s.sky.ground = glm::vec3(0.0f);
        s.camera = scene::lookAt({0.0f, 0.5f, 2.0f}, {0.0f, 0.0f, 0.0f}, glm::radians(10.0f));
        return s;
    };
    const glm::dvec3 open = centreMean(renderScene(floorScene(false), 32, 4, 1), 32, 4);
    const glm::dvec3 glazed = centreMean(renderScene(floorScene(true), 32, 4, 1), 32, 4);
    const glm::dvec3 base(1.0, 0.5, 0.25);
    for (int c = 0; c < 3; ++c) {
        const double ratio = glazed[c] / open[c];
        std::printf("channel %d: through the pane %.4f of the light, expected %.4f\n", c, ratio,
                    0.96 * base[c]);
        EXPECT_NEAR(ratio, 0.96 * base[c], 0.01) << "channel " << c;
    }
}

// A Lambertian quad facing the camera, lit by a directional light 60 degrees off its normal
// towards +x (the quad's +u): a normal texture bending the normal 60 degrees towards +u
// turns it to the light (twice the radiance of cos 60), one bending it towards -u turns it
// 120 degrees from the light (dark), and scale 0 leaves the normal as it was.
TEST_F(PathMaterialsTest, NormalTextureBendsTheShadingNormal) {
    const auto litQuad = [](int texture, float scale, int towards) {
        scene::Scene s;
        scene::SceneBuilder b(s);
        scene::Material m;
        m.specular = 0.0f;
        m.normalTexture = texture;
        m.normalScale = scale;
        facingQuad(b, b.material(m));
        const float sx = 0.8660254f * static_cast<float>(towards);
        // Tangent space (x along +u, z the normal), encoded as (n + 1) / 2.
        s.textures.push_back(solidTexture(static_cast<uint32_t>(std::lround((sx + 1) * 127.5)),
                                          128u, static_cast<uint32_t>(std::lround(1.5 * 127.5))));
        scene::Light l;
        l.type = scene::LightType::Directional;
        l.direction = -glm::vec3(0.8660254f, 0.0f, 0.5f);
        s.lights.push_back(l);
        s.sky.horizon = s.sky.zenith = s.sky.ground = glm::vec3(0.0f);
        s.camera = frontCamera(3.0f, 20.0f);
        return s;
    };
    const double plain = mean(renderScene(litQuad(-1, 1.0f, 1), 16, 1, 1)).g;
    const double toLight = mean(renderScene(litQuad(0, 1.0f, 1), 16, 1, 1)).g;
    const double away = mean(renderScene(litQuad(0, 1.0f, -1), 16, 1, 1)).g;
    const double unscaled = mean(renderScene(litQuad(0, 0.0f, 1), 16, 1, 1)).g;
    std::printf("plain %.4f (1 / (2 pi) = %.4f), towards the light %.4f, away %.4f, scale 0 "
                "%.4f\n",
                plain, 0.5 / 3.14159265, toLight, away, unscaled);
    EXPECT_NEAR(plain, 0.5 / 3.14159265, 0.002);
    EXPECT_NEAR(toLight / plain, 2.0, 0.04);
    EXPECT_LT(away, 0.01 * plain);
    EXPECT_NEAR(unscaled / plain, 1.0, 0.02);
}

// An emitter whose emissive texture is pure red: what it lights is red only, and as bright as
// under an untextured emitter of the same red radiance (the emitter table weighs the factor;
// next-event estimation reads the texture where its sample lands). One vertex, black sky.
TEST_F(PathMaterialsTest, EmissiveTextureTintsTheEmitterAndItsLight) {
    const auto lampScene = [](bool textured) {
        scene::Scene s;
        scene::SceneBuilder b(s);
        whiteFloor(b);
        scene::Material lamp;
        lamp.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
        lamp.emissive = textured ? glm::vec3(4.0f) : glm::vec3(4.0f, 0.0f, 0.0f);
        lamp.emissiveTexture = textured ? 0 : -1;
        b.quad({-0.5f, 1.0f, -0.5f}, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, b.material(lamp));
        s.textures.push_back(solidTexture(255u, 0u, 0u));
        s.sky.horizon = s.sky.zenith = s.sky.ground = glm::vec3(0.0f);
        s.camera = scene::lookAt({0.0f, 0.4f, 2.0f}, {0.0f, 0.0f, 0.0f}, glm::radians(20.0f));
        return s;
    };
    const glm::dvec3 textured = centreMean(renderScene(lampScene(true), 32, 16, 1), 32, 8);
    const glm::dvec3 red = centreMean(renderScene(lampScene(false), 32, 16, 1), 32, 8);
    std::printf("floor under the textured emitter %.4f %.4f %.4f, under the red one %.4f\n",
                textured.r, textured.g, textured.b, red.r);
    EXPECT_GT(red.r, 0.01);
    EXPECT_NEAR(textured.r / red.r, 1.0, 0.03);
    EXPECT_LT(textured.g, 1e-6);
    EXPECT_LT(textured.b, 1e-6);
}

// An unlit quad tiled with a one-texel checkerboard, 32 texels to a pixel: with the ray cone
// of a pixel each ray reads the mip level where the checks average to grey, so one path per
// pixel is already within a few per cent of the grey everywhere. Sampled at level 0 each path
// would read black, white or a bilinear mix of them (a standard deviation near 0.4).
TEST_F(PathMaterialsTest, RayConesFilterAMinifiedTexture) {
    scene::Scene s;
    scene::SceneBuilder b(s);
    scene::Material checks;
    checks.unlit = true;
    checks.baseColorTexture = 0;
    facingQuad(b, b.material(checks), {16.0f, 16.0f});
    scene::Texture t;
    t.width = t.height = 64;
    for (uint32_t y = 0; y < 64; ++y)
        for (uint32_t x = 0; x < 64; ++x)
            t.rgba.push_back(((x + y) % 2 == 0) ? 0xffffffffu : 0xff000000u);
    s.textures.push_back(t);
    s.camera = frontCamera(3.0f, 28.0f);
    const std::vector<glm::vec4> image = renderScene(s, 32, 1, 1);
    double sum = 0.0, sumSq = 0.0;
    for (const glm::vec4& p : image) {
        sum += p.g;
        sumSq += static_cast<double>(p.g) * p.g;
    }
    const double n = static_cast<double>(image.size());
    const double m = sum / n, sd = std::sqrt(std::max(0.0, sumSq / n - m * m));
    std::printf("checks at 32 texels per pixel, 1 path: mean %.4f, standard deviation %.4f\n", m,
                sd);
    EXPECT_NEAR(m, 0.5, 0.03);
    EXPECT_LT(sd, 0.05);
}

} // namespace
} // namespace gt
