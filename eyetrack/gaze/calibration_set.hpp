#pragma once
// A calibration file (version 3): one entry per tracked eye ("both" for a single camera on one
// eye, or "left" and "right" from one binocular session), each with the 2D polynomial and, when
// the eye camera's intrinsics were known, the 3D eye model's calibration:
//   {"format": "gazetrace-calibration", "version": 3,
//    "eyes": [{"eye": "left", "poly": {version-2 calibration}, "model3d": {...}}, ...]}
// Version-2 files (a bare polynomial) still load, as one eye "both".
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gaze/calibration.hpp"
#include "gaze/gaze_mapper.hpp"
#include "model/model3d_calibration.hpp"

namespace gt::eyetrack {

struct EyeCalibration {
    std::string eye = "both"; // both | left | right
    Calibration poly;
    std::optional<Model3dCalibration> model3d;
};

class CalibrationSet {
public:
    static constexpr int kVersion = 3;

    std::vector<EyeCalibration> eyes;

    // The entry for `eye`; "both" on a one-eye file gives its entry (whichever eye it is). Throws
    // CalibrationError naming the eyes the file has (a one-eye file cannot drive two eyes).
    [[nodiscard]] const EyeCalibration& eye(const std::string& name) const;

    [[nodiscard]] nlohmann::json toJson() const;
    [[nodiscard]] static CalibrationSet fromJson(const nlohmann::json& j, const std::string& what);
    void save(const std::filesystem::path& file) const; // atomic
    [[nodiscard]] static CalibrationSet load(const std::filesystem::path& file);
};

// The gaze models a calibration can drive.
enum class GazeModel {
    TwoD,   // the polynomial from pupil centre to screen
    ThreeD, // the eye model (needs the file's 3D calibration)
};

// The mapper for one eye; for ThreeD, `intrinsics`, when given, replace the file's. Throws
// CalibrationError when the eye has no 3D calibration.
[[nodiscard]] std::unique_ptr<GazeMapper>
makeGazeMapper(const EyeCalibration& eye, GazeModel model,
               const std::optional<CameraIntrinsics>& intrinsics = std::nullopt);

} // namespace gt::eyetrack
