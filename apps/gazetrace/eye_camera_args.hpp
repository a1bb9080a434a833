#pragma once
// The eye camera's intrinsics from the command line: --intrinsics FILE (written by
// `gazetrace eyesim --intrinsics-out`, or by any calibration tool as {"fx","fy","cx","cy"}), or
// --focal F with --principal X,Y. Shared by calibrate, track and slippage.
#include <optional>
#include <string>

#include "model/camera_intrinsics.hpp"

namespace gt::app {

struct EyeCameraArgs {
    std::string intrinsics; // file
    double focal = 0.0;     // pixels
    std::string principal;  // X,Y pixels
};

// nullopt when none was given; throws ArgumentError for a bad or incomplete set.
[[nodiscard]] std::optional<eyetrack::CameraIntrinsics> eyeCamera(const EyeCameraArgs& a);

} // namespace gt::app
