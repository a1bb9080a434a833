#pragma once
// The renderer's scene: a flat triangle list in world space (node transforms already applied),
// materials (glTF metallic-roughness subset), base-colour textures, punctual lights, a camera
// and a sky. Built-in scenes and the glTF loader both produce this; the BVH and the tracers
// consume it.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/environment.hpp"

namespace gt::scene {

struct Rig; // animation.hpp

struct Material {
    glm::vec4 baseColor{1.0f}; // linear RGBA factor
    int baseColorTexture = -1; // index into Scene::textures
    float metallic = 0.0f;
    float roughness = 1.0f;
    // glTF's metallicRoughnessTexture (linear; G scales roughness, B metallic), read with the
    // base colour's UVs; -1: the factors alone. Only the path integrator reads it.
    int metallicRoughnessTexture = -1;
    // glTF's normalTexture (tangent space, read with the base colour's UVs) and its scale;
    // -1: the interpolated vertex normal. Only the path integrator reads it.
    int normalTexture = -1;
    float normalScale = 1.0f;
    // glTF's emissiveTexture (sRGB), multiplying `emissive`; -1: none. Only the path
    // integrator reads it.
    int emissiveTexture = -1;
    // KHR_materials_transmission: the share of a dielectric's diffuse lobe replaced by
    // transmission through the surface, times transmissionTexture's R (-1: none); and
    // KHR_materials_ior's index of refraction, which sets a dielectric's Fresnel reflectance at
    // normal incidence. Only the path integrator reads them.
    float transmission = 0.0f;
    int transmissionTexture = -1;
    float ior = 1.5f;
    bool unlit = false; // KHR_materials_unlit: the base colour is the radiance
    // alphaMode MASK: hits where the base colour's alpha is below this are passed through
    // (negative: opaque).
    float alphaCutoff = -1.0f;
    // alphaMode BLEND: the base colour's alpha is the surface's coverage. The path integrator
    // lets (1 - alpha) of the light through untouched; the direct one draws it opaque.
    bool alphaBlend = false;
    glm::vec3 emissive{0.0f}; // linear radiance added on hit
    // KHR_materials_specular's specularFactor: the weight of a dielectric's specular lobe (0: a
    // pure Lambertian). Only the path integrator reads it.
    float specular = 1.0f;
    std::string name;
};

// 8-bit sRGB-encoded RGBA texels, row-major, top row first (as glTF images are stored).
struct Texture {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<uint32_t> rgba; // packed little-endian R | G<<8 | B<<16 | A<<24
    std::string name;
};

enum class LightType : uint32_t { Point = 0, Spot = 1, Directional = 2 };

// KHR_lights_punctual semantics: point/spot intensity in candela, directional in lux.
struct Light {
    LightType type = LightType::Point;
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, -1.0f, 0.0f}; // direction the light travels
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    float range = 0.0f; // 0 = infinite
    float innerConeCos = 1.0f;
    float outerConeCos = 0.70710678f;
    // The light stands in for an emissive surface of the scene, which the direct integrator
    // cannot sample; the path integrator samples the surface itself and skips this light, so
    // that the lamp is not counted twice.
    bool standsInForEmitter = false;
};

struct Camera {
    glm::vec3 position{0.0f, 1.0f, 5.0f};
    glm::vec3 forward{0.0f, 0.0f, -1.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float yfov = 0.8f; // radians, vertical
};

// A camera at `eye` looking at `target` (which must differ from it), with glTF's +Y up; looking
// straight up or down, the image's up is -Z instead, since +Y gives no basis there.
[[nodiscard]] Camera lookAt(glm::vec3 eye, glm::vec3 target, float yfov);

struct Sky {
    glm::vec3 horizon{0.8f, 0.85f, 0.9f};
    glm::vec3 zenith{0.35f, 0.5f, 0.8f};
    glm::vec3 ground{0.25f, 0.23f, 0.2f};
    float ambient = 0.15f; // share of sky radiance applied as ambient light
};

struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec2 uv;
};

// A Catmull-Clark control cage (the geometric LOD of Guenter et al. 2012, section 6): polygons over
// shared control points in world space, refined by OpenSubdiv to as many levels as the renderer's
// LOD needs (scene/subdivision.hpp). Its triangles are not in Scene::vertices.
struct SubdivisionCage {
    std::vector<glm::vec3> points;
    std::vector<uint32_t> faceSizes; // corners of each face (3 or more)
    std::vector<uint32_t> indices;   // into points, faceSizes[i] per face, counter-clockwise
    uint32_t material = 0;
    std::string name;
};

struct Scene {
    std::string name;
    std::vector<Vertex> vertices; // 3 per triangle, world space
    std::vector<uint32_t> triangleMaterial;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<Light> lights;
    Camera camera;
    // The camera is the loader's framing from outside the bounds (a glTF without a camera), not
    // one the scene's author placed: a viewer may want to start inside instead (start_view.hpp).
    bool cameraFramed = false;
    Sky sky;
    Environment environment;            // used for misses when it has texels (cubemap scenes)
    std::vector<SubdivisionCage> cages; // refined per LOD level, beside `vertices`
    float exposure = 1.0f;
    // What moves (animation.hpp): mesh instances kept out of `vertices`, their nodes, skins,
    // morph targets and animations. Null for a scene where nothing moves.
    std::shared_ptr<const Rig> rig;

    [[nodiscard]] bool animated() const noexcept { return rig != nullptr; }
    [[nodiscard]] std::size_t triangleCount() const noexcept { return triangleMaterial.size(); }
    // Whether any material is alpha-masked (its hits must test the texture's alpha).
    [[nodiscard]] bool hasAlphaMask() const noexcept;
    [[nodiscard]] glm::vec3 boundsMin() const;
    [[nodiscard]] glm::vec3 boundsMax() const;
};

// Helpers for procedural scenes: each shape is appended with one material and a transform.
class SceneBuilder {
public:
    explicit SceneBuilder(Scene& scene) : mScene(scene) {}
    uint32_t material(const Material& m);
    void triangle(const Vertex& a, const Vertex& b, const Vertex& c, uint32_t material);
    // Quad from corner `o` spanned by `u` and `v`; normal = normalize(cross(u, v)).
    void quad(glm::vec3 o, glm::vec3 u, glm::vec3 v, uint32_t material, glm::vec2 uvScale = {1, 1});
    void box(const glm::mat4& transform, uint32_t material); // unit cube [-0.5, 0.5]^3
    void cylinder(const glm::mat4& transform, uint32_t material,
                  int segments = 16); // r 0.5, y 0..1
    void sphere(const glm::mat4& transform, uint32_t material, int rings = 8, int segments = 12);
    // Catmull-Clark cages: a cube [-0.5, 0.5]^3 (6 quads; a rounded blob once refined) and a
    // torus of `ring` x `tube` quads around y (radii 0.5 and 0.2 before the transform).
    void boxCage(const glm::mat4& transform, uint32_t material, const std::string& name = "box");
    void torusCage(const glm::mat4& transform, uint32_t material, int ring = 8, int tube = 4);

private:
    Scene& mScene;
};

} // namespace gt::scene
