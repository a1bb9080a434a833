#pragma once
// A recorded camera path: CSV with the header `t_ms,ex,ey,ez,tx,ty,tz` (milliseconds, increasing;
// eye and look-at target in scene units, glTF's +Y up), linear interpolation between rows,
// clamped at both ends. Moving views are where temporal artefacts show, so the demo records one
// and `render` and `demo` play it back.
#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.hpp"

namespace gt::scene {

struct CameraKey {
    double tMs = 0.0;
    glm::vec3 eye{0.0f}, target{0.0f, 0.0f, -1.0f};
};

class CameraPath {
public:
    // Throws gt::LoadError naming the file and line for anything malformed.
    [[nodiscard]] static CameraPath load(const std::filesystem::path& file);
    [[nodiscard]] static CameraPath fromKeys(std::vector<CameraKey> keys); // validates too
    // Writes atomically (temporary file, renamed when complete).
    void save(const std::filesystem::path& file) const;

    [[nodiscard]] const std::vector<CameraKey>& keys() const noexcept { return mKeys; }
    [[nodiscard]] double startMs() const { return mKeys.front().tMs; }
    [[nodiscard]] double endMs() const { return mKeys.back().tMs; }
    // The camera at `tMs` with vertical field of view `yfov`.
    [[nodiscard]] Camera at(double tMs, float yfov) const;

private:
    std::vector<CameraKey> mKeys;
};

} // namespace gt::scene
