#pragma once
// Command-line values that describe a view, shared by `render` and `demo`.
#include <cstdint>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "scene/scene.hpp"

namespace gt::app {

// --camera X,Y,Z,TX,TY,TZ[,FOV]: eye and look-at target in scene units, and the vertical field
// of view in degrees (default: the scene camera's, known once the scene is loaded).
struct CameraArg {
    glm::vec3 eye{0.0f}, target{0.0f};
    std::optional<float> yfovDeg;
    // The camera this describes; `defaultYfov` when no field of view was given.
    [[nodiscard]] scene::Camera camera(float defaultYfov) const;
};

// The largest --camera coordinate, in scene units (a float's spacing reaches 1 unit there).
inline constexpr float kMaxCameraCoordinate = 1e7f;

// Empty text: no --camera. Throws ArgumentError naming --camera for anything malformed.
[[nodiscard]] std::optional<CameraArg> parseCamera(const std::string& text);

// --gaze X,Y in pixels on a w x h image; empty text: its centre. Throws ArgumentError naming
// --gaze for anything malformed or off the image.
[[nodiscard]] glm::vec2 parseGaze(const std::string& text, uint32_t w, uint32_t h);

} // namespace gt::app
