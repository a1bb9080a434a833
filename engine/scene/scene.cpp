#include "scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <glm/gtc/constants.hpp>

#include "core/error.hpp"

namespace gt::scene {

glm::vec3 Scene::boundsMin() const {
    glm::vec3 m(std::numeric_limits<float>::max());
    for (const Vertex& v : vertices)
        m = glm::min(m, v.position);
    for (const SubdivisionCage& c : cages) // the limit surface lies inside its cage's hull
        for (const glm::vec3& p : c.points)
            m = glm::min(m, p);
    return m;
}

glm::vec3 Scene::boundsMax() const {
    glm::vec3 m(-std::numeric_limits<float>::max());
    for (const Vertex& v : vertices)
        m = glm::max(m, v.position);
    for (const SubdivisionCage& c : cages)
        for (const glm::vec3& p : c.points)
            m = glm::max(m, p);
    return m;
}

// Every front end builds its camera here (--camera, camera paths, start views), so a camera that
// gives no picture is refused here, once: a position or field of view that is not finite, or a
// view direction that is not (eye and target at 1e30 and 0: the float difference squares to
// infinity, and normalising it gave NaN). The direction is computed in double for that reason.
Camera lookAt(glm::vec3 eye, glm::vec3 target, float yfov) {
    const glm::dvec3 d = glm::dvec3(target) - glm::dvec3(eye);
    const double length = glm::length(d);
    const bool finite = std::isfinite(eye.x) && std::isfinite(eye.y) && std::isfinite(eye.z);
    if (!finite || !std::isfinite(length) || !(length > 0.0) || !std::isfinite(yfov) ||
        !(yfov > 0.0f && yfov < glm::pi<float>())) {
        char text[256];
        std::snprintf(text, sizeof text,
                      "camera: eye (%g, %g, %g), target (%g, %g, %g) and field of view %g rad "
                      "give no view",
                      eye.x, eye.y, eye.z, target.x, target.y, target.z, yfov);
        throw ArgumentError(text);
    }
    Camera c;
    c.position = eye;
    c.forward = glm::vec3(d / length);
    c.up =
        std::abs(c.forward.y) > 0.999f ? glm::vec3(0.0f, 0.0f, -1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    c.yfov = yfov;
    return c;
}

bool Scene::hasAlphaMask() const noexcept {
    return std::any_of(materials.begin(), materials.end(),
                       [](const Material& m) { return m.alphaCutoff >= 0.0f; });
}

uint32_t SceneBuilder::material(const Material& m) {
    mScene.materials.push_back(m);
    return static_cast<uint32_t>(mScene.materials.size() - 1);
}

void SceneBuilder::triangle(const Vertex& a, const Vertex& b, const Vertex& c, uint32_t material) {
    mScene.vertices.push_back(a);
    mScene.vertices.push_back(b);
    mScene.vertices.push_back(c);
    mScene.triangleMaterial.push_back(material);
}

void SceneBuilder::quad(glm::vec3 o, glm::vec3 u, glm::vec3 v, uint32_t material,
                        glm::vec2 uvScale) {
    const glm::vec3 n = glm::normalize(glm::cross(u, v));
    const Vertex p00{o, n, {0, 0}};
    const Vertex p10{o + u, n, {uvScale.x, 0}};
    const Vertex p11{o + u + v, n, {uvScale.x, uvScale.y}};
    const Vertex p01{o + v, n, {0, uvScale.y}};
    triangle(p00, p10, p11, material);
    triangle(p00, p11, p01, material);
}

namespace {
Vertex transformed(const glm::mat4& m, const glm::mat3& nm, glm::vec3 p, glm::vec3 n,
                   glm::vec2 uv) {
    return {glm::vec3(m * glm::vec4(p, 1.0f)), glm::normalize(nm * n), uv};
}
} // namespace

void SceneBuilder::box(const glm::mat4& t, uint32_t material) {
    const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(t)));
    // Six faces, each as (centre normal, u axis, v axis) on the unit cube.
    const glm::vec3 axes[6][3] = {
        {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
    };
    for (const auto& f : axes) {
        const glm::vec3 n = f[0], u = f[1], v = f[2];
        const glm::vec3 o = 0.5f * n - 0.5f * u - 0.5f * v;
        const Vertex a = transformed(t, nm, o, n, {0, 0});
        const Vertex b = transformed(t, nm, o + u, n, {1, 0});
        const Vertex c = transformed(t, nm, o + u + v, n, {1, 1});
        const Vertex d = transformed(t, nm, o + v, n, {0, 1});
        triangle(a, b, c, material);
        triangle(a, c, d, material);
    }
}

void SceneBuilder::cylinder(const glm::mat4& t, uint32_t material, int segments) {
    const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(t)));
    const float step = 2.0f * 3.14159265f / static_cast<float>(segments);
    for (int i = 0; i < segments; ++i) {
        const float a0 = step * static_cast<float>(i), a1 = step * static_cast<float>(i + 1);
        const glm::vec3 n0(std::cos(a0), 0, std::sin(a0)), n1(std::cos(a1), 0, std::sin(a1));
        const glm::vec3 b0 = 0.5f * n0, b1 = 0.5f * n1;
        const glm::vec3 up(0, 1, 0);
        const float u0 = static_cast<float>(i) / static_cast<float>(segments);
        const float u1 = static_cast<float>(i + 1) / static_cast<float>(segments);
        const Vertex v00 = transformed(t, nm, b0, n0, {u0, 0});
        const Vertex v10 = transformed(t, nm, b1, n1, {u1, 0});
        const Vertex v01 = transformed(t, nm, b0 + up, n0, {u0, 1});
        const Vertex v11 = transformed(t, nm, b1 + up, n1, {u1, 1});
        triangle(v00, v11, v10, material);
        triangle(v00, v01, v11, material);
        // Caps.
        triangle(transformed(t, nm, up, up, {0.5f, 0.5f}), transformed(t, nm, b1 + up, up, {0, 0}),
                 transformed(t, nm, b0 + up, up, {0, 0}), material);
        triangle(transformed(t, nm, {0, 0, 0}, -up, {0.5f, 0.5f}),
                 transformed(t, nm, b0, -up, {0, 0}), transformed(t, nm, b1, -up, {0, 0}),
                 material);
    }
}

void SceneBuilder::sphere(const glm::mat4& t, uint32_t material, int rings, int segments) {
    const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(t)));
    auto point = [&](int r, int s) {
        const float theta = 3.14159265f * static_cast<float>(r) / static_cast<float>(rings);
        const float phi = 2.0f * 3.14159265f * static_cast<float>(s) / static_cast<float>(segments);
        const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                          std::sin(theta) * std::sin(phi));
        return transformed(t, nm, 0.5f * n, n,
                           {static_cast<float>(s) / static_cast<float>(segments),
                            static_cast<float>(r) / static_cast<float>(rings)});
    };
    for (int r = 0; r < rings; ++r) {
        for (int s = 0; s < segments; ++s) {
            const Vertex a = point(r, s), b = point(r, s + 1), c = point(r + 1, s + 1),
                         d = point(r + 1, s);
            if (r > 0) triangle(a, b, c, material);
            if (r < rings - 1) triangle(a, c, d, material);
        }
    }
}

} // namespace gt::scene

namespace gt::scene {

void SceneBuilder::boxCage(const glm::mat4& t, uint32_t material, const std::string& name) {
    SubdivisionCage c;
    c.material = material;
    c.name = name;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 p((i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f);
        c.points.emplace_back(t * glm::vec4(p, 1.0f));
    }
    // Counter-clockwise seen from outside.
    const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) {
        c.faceSizes.push_back(4);
        c.indices.insert(c.indices.end(), std::begin(f), std::end(f));
    }
    mScene.cages.push_back(std::move(c));
}

void SceneBuilder::torusCage(const glm::mat4& t, uint32_t material, int ring, int tube) {
    SubdivisionCage c;
    c.material = material;
    c.name = "torus";
    constexpr float kTwoPi = 6.28318531f;
    for (int i = 0; i < ring; ++i) {
        const float a = kTwoPi * static_cast<float>(i) / static_cast<float>(ring);
        for (int j = 0; j < tube; ++j) {
            const float b = kTwoPi * static_cast<float>(j) / static_cast<float>(tube);
            const float r = 0.5f + 0.2f * std::cos(b);
            c.points.emplace_back(
                t * glm::vec4(r * std::cos(a), 0.2f * std::sin(b), r * std::sin(a), 1.0f));
        }
    }
    auto at = [&](int i, int j) {
        return static_cast<uint32_t>(((i + ring) % ring) * tube + (j + tube) % tube);
    };
    for (int i = 0; i < ring; ++i) {
        for (int j = 0; j < tube; ++j) {
            c.faceSizes.push_back(4);
            for (const uint32_t v : {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)}) {
                c.indices.push_back(v);
            }
        }
    }
    mScene.cages.push_back(std::move(c));
}

} // namespace gt::scene
