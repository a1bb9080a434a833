#include "view_args.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "core/error.hpp"

namespace gt::app {

scene::Camera CameraArg::camera(float defaultYfov) const {
    return scene::lookAt(eye, target, yfovDeg ? glm::radians(*yfovDeg) : defaultYfov);
}

std::optional<CameraArg> parseCamera(const std::string& text) {
    if (text.empty()) {
        return std::nullopt;
    }
    std::vector<float> v;
    std::vector<std::string> fields;
    std::stringstream in(text);
    for (std::string field; std::getline(in, field, ',');) {
        fields.push_back(field);
        char* end = nullptr;
        const float x = std::strtof(field.c_str(), &end);
        if (end != field.c_str() && *end == '\0' && std::isfinite(x)) {
            v.push_back(x);
        }
    }
    if (text.back() == ',' || v.size() != fields.size() || (v.size() != 6 && v.size() != 7)) {
        throw ArgumentError("--camera: expected X,Y,Z,TX,TY,TZ[,FOV_DEG], got '" + text + "'");
    }
    // Past 1e7 a float's spacing exceeds a scene unit: such a camera cannot be placed in a scene
    // (and 1e30 gave a NaN view direction).
    for (std::size_t i = 0; i < 6; ++i) {
        if (std::abs(v[i]) > kMaxCameraCoordinate) {
            throw ArgumentError("--camera: " + fields[i] + " is beyond +-1e7 scene units in '" +
                                text + "'");
        }
    }
    CameraArg c{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, std::nullopt};
    if (glm::length(c.target - c.eye) < 1e-6f) {
        throw ArgumentError("--camera: the eye and the target are the same point in '" + text +
                            "'");
    }
    if (v.size() == 7) {
        if (!(v[6] >= 1.0f && v[6] <= 179.0f)) {
            throw ArgumentError("--camera: the field of view must be 1..179 degrees, got " +
                                fields[6]);
        }
        c.yfovDeg = v[6];
    }
    return c;
}

glm::vec2 parseGaze(const std::string& text, uint32_t w, uint32_t h) {
    if (text.empty()) {
        return {0.5f * static_cast<float>(w), 0.5f * static_cast<float>(h)};
    }
    float x = 0, y = 0;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%f,%f%c", &x, &y, &extra) != 2 || !std::isfinite(x) ||
        !std::isfinite(y)) {
        throw ArgumentError("--gaze: expected X,Y in pixels, got '" + text + "'");
    }
    if (x < 0 || y < 0 || x >= static_cast<float>(w) || y >= static_cast<float>(h)) {
        throw ArgumentError("--gaze: " + text + " is outside the " + std::to_string(w) + "x" +
                            std::to_string(h) + " screen");
    }
    return {x, y};
}

} // namespace gt::app
