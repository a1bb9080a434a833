#include "gaze/calibration_set.hpp"

#include "error.hpp"
#include "formats/atomic_file.hpp"
#include "formats/json_file.hpp"
#include "model/eye_model_mapper.hpp"

namespace gt::eyetrack {

const EyeCalibration& CalibrationSet::eye(const std::string& name) const {
    if (eyes.size() == 1 && name == "both") {
        return eyes.front();
    }
    for (const EyeCalibration& e : eyes) {
        if (e.eye == name) {
            return e;
        }
    }
    std::string have;
    for (const EyeCalibration& e : eyes) {
        have += (have.empty() ? "" : ", ") + e.eye;
    }
    throw CalibrationError("calibration has no '" + name + "' eye (it has: " + have + ")");
}

nlohmann::json CalibrationSet::toJson() const {
    nlohmann::json list = nlohmann::json::array();
    for (const EyeCalibration& e : eyes) {
        nlohmann::json j{{"eye", e.eye}, {"poly", e.poly.toJson()}};
        if (e.model3d) {
            j["model3d"] = e.model3d->toJson();
        }
        list.push_back(j);
    }
    return {{"format", "gazetrace-calibration"}, {"version", kVersion}, {"eyes", list}};
}

CalibrationSet CalibrationSet::fromJson(const nlohmann::json& j, const std::string& what) {
    auto bad = [&](const std::string& why) {
        return FormatError("calibration " + what + ": " + why);
    };
    if (!j.is_object()) {
        throw bad("not a JSON object");
    }
    CalibrationSet set;
    // Version 2: the bare polynomial (Calibration::fromJson checks everything else).
    if (j.contains("version") && j["version"].is_number_integer() &&
        j["version"].get<long long>() == Calibration::kVersion) {
        set.eyes.push_back({"both", Calibration::fromJson(j, what), std::nullopt});
        return set;
    }
    if (!j.contains("format") || !j["format"].is_string() ||
        j["format"].get<std::string>() != "gazetrace-calibration") {
        throw bad("not a gazetrace calibration (\"format\" is missing or wrong)");
    }
    if (!j.contains("version") || !j["version"].is_number_integer()) {
        throw bad("\"version\" is missing");
    }
    if (j["version"].get<long long>() != kVersion) {
        throw bad("version " + std::to_string(j["version"].get<long long>()) +
                  " is not supported (expected 2 or 3; run gazetrace calibrate again)");
    }
    if (!j.contains("eyes") || !j["eyes"].is_array() || j["eyes"].empty() || j["eyes"].size() > 2) {
        throw bad("\"eyes\" must list one or two eyes");
    }
    for (const auto& e : j["eyes"]) {
        if (!e.is_object() || !e.contains("eye") || !e["eye"].is_string() || !e.contains("poly")) {
            throw bad("each eye needs \"eye\" and \"poly\"");
        }
        EyeCalibration c;
        c.eye = e["eye"].get<std::string>();
        if (c.eye != "both" && c.eye != "left" && c.eye != "right") {
            throw bad("eye '" + c.eye + "' is not both, left or right");
        }
        for (const EyeCalibration& other : set.eyes) {
            if (other.eye == c.eye) {
                throw bad("eye '" + c.eye + "' is listed twice");
            }
        }
        c.poly = Calibration::fromJson(e["poly"], what);
        if (e.contains("model3d")) {
            c.model3d = Model3dCalibration::fromJson(e["model3d"], c.poly.display(), what);
        }
        set.eyes.push_back(std::move(c));
    }
    return set;
}

void CalibrationSet::save(const std::filesystem::path& file) const {
    AtomicFile out(file);
    out.stream() << toJson().dump(2) << "\n";
    out.commit();
}

CalibrationSet CalibrationSet::load(const std::filesystem::path& file) {
    return fromJson(readJsonFile(file, "calibration"), file.string());
}

std::unique_ptr<GazeMapper> makeGazeMapper(const EyeCalibration& eye, GazeModel model,
                                           const std::optional<CameraIntrinsics>& intrinsics) {
    if (model == GazeModel::TwoD) {
        return std::make_unique<PolynomialMapper>(eye.poly);
    }
    if (!eye.model3d) {
        throw CalibrationError("the calibration of eye '" + eye.eye +
                               "' has no 3D model: calibrate it again with the camera's intrinsics "
                               "or focal length");
    }
    Model3dCalibration m = *eye.model3d;
    if (intrinsics) {
        m.camera = *intrinsics;
    }
    return std::make_unique<EyeModelMapper>(m);
}

} // namespace gt::eyetrack
