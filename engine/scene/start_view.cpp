#include "scene/start_view.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gt::scene {

std::optional<Camera> insideStartView(const Scene& scene, const Bvh& bvh) {
    if (scene.triangleCount() == 0) return std::nullopt;
    const glm::vec3 lo = scene.boundsMin(), hi = scene.boundsMax();
    const glm::vec3 centre = 0.5f * (lo + hi);
    auto cast = [&](glm::vec3 origin, glm::vec3 dir) {
        return bvh.intersect(
            {origin, glm::normalize(dir), 1e-4f, std::numeric_limits<float>::infinity()});
    };
    // Enclosed: the 26 directions of a cube's faces, edges and corners nearly all hit.
    int hits = 0;
    for (int x = -1; x <= 1; ++x) {
        for (int y = -1; y <= 1; ++y) {
            for (int z = -1; z <= 1; ++z) {
                if (x == 0 && y == 0 && z == 0) continue;
                hits += cast(centre, glm::vec3(x, y, z)).valid() ? 1 : 0;
            }
        }
    }
    if (hits < 23) return std::nullopt;
    const Hit down = cast(centre, {0, -1, 0});
    const Hit up = cast(centre, {0, 1, 0});
    if (!down.valid()) return std::nullopt;
    const float floorY = centre.y - down.t;
    const float ceilingY = up.valid() ? centre.y + up.t : hi.y;
    const float height = ceilingY - floorY;
    const float eyeY = floorY + std::min(1.6f, 0.6f * height);
    const glm::vec3 eye(centre.x, eyeY, centre.z);
    // Look where there is the most room.
    glm::vec3 best(0, 0, -1);
    float bestT = -1.0f;
    for (int i = 0; i < 16; ++i) {
        const float a = static_cast<float>(i) * 0.39269908f; // 22.5 degrees
        const glm::vec3 d(std::sin(a), 0.0f, -std::cos(a));
        const Hit h = cast(eye, d);
        const float t = h.valid() ? h.t : std::numeric_limits<float>::infinity();
        if (t > bestT) {
            bestT = t;
            best = d;
        }
    }
    return lookAt(eye, eye + best, scene.camera.yfov);
}

} // namespace gt::scene
