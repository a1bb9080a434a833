#include "eye_camera_args.hpp"

#include <cmath>
#include <cstdio>

#include "core/error.hpp"

namespace gt::app {

std::optional<eyetrack::CameraIntrinsics> eyeCamera(const EyeCameraArgs& a) {
    if (!a.intrinsics.empty()) {
        if (a.focal != 0.0 || !a.principal.empty()) {
            throw ArgumentError("--intrinsics: give the file or --focal/--principal, not both");
        }
        return eyetrack::CameraIntrinsics::load(a.intrinsics);
    }
    if (a.focal == 0.0 && a.principal.empty()) {
        return std::nullopt;
    }
    if (!(a.focal > 0.0) || !std::isfinite(a.focal) || a.focal > 1e6) {
        throw ArgumentError("--focal: expected a focal length in pixels (0 < f <= 1e6)");
    }
    double x = 0.0, y = 0.0;
    char extra = 0;
    if (a.principal.empty() || std::sscanf(a.principal.c_str(), "%lf,%lf%c", &x, &y, &extra) != 2 ||
        !std::isfinite(x) || !std::isfinite(y)) {
        throw ArgumentError("--principal: expected X,Y in pixels with --focal, got '" +
                            a.principal + "'");
    }
    return eyetrack::CameraIntrinsics{a.focal, a.focal, x, y};
}

} // namespace gt::app
