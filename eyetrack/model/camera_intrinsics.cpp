#include "model/camera_intrinsics.hpp"

#include <limits>

#include "error.hpp"
#include "formats/atomic_file.hpp"
#include "formats/json_file.hpp"

namespace gt::eyetrack {

namespace {

constexpr double kPxPerMmAt240 = 9.1; // the synthetic eye's scale (sim/synthetic_eye.hpp)
constexpr double kEyeDistanceMm = 35.0;

} // namespace

CameraIntrinsics CameraIntrinsics::eyesimDefault(cv::Size size) {
    const double f = kPxPerMmAt240 * (size.height / 240.0) * kEyeDistanceMm;
    return {f, f, 0.5 * (size.width - 1), 0.5 * (size.height - 1)};
}

nlohmann::json CameraIntrinsics::toJson() const {
    return {{"fx", fx}, {"fy", fy}, {"cx", cx}, {"cy", cy}};
}

CameraIntrinsics CameraIntrinsics::fromJson(const nlohmann::json& j, const std::string& what) {
    // Each field a finite number, named when it is not.
    const JsonFields fields(j, "intrinsics " + what);
    constexpr double kAny = std::numeric_limits<double>::max();
    CameraIntrinsics k;
    for (auto [key, field] :
         {std::pair{"fx", &k.fx}, {"fy", &k.fy}, {"cx", &k.cx}, {"cy", &k.cy}}) {
        *field = fields.number(key, -kAny, kAny);
    }
    if (!k.valid()) {
        throw FormatError("intrinsics " + what + ": focal lengths must be positive and finite");
    }
    return k;
}

CameraIntrinsics CameraIntrinsics::load(const std::filesystem::path& file) {
    return fromJson(readJsonFile(file, "camera intrinsics"), file.string());
}

void CameraIntrinsics::save(const std::filesystem::path& file) const {
    AtomicFile out(file);
    out.stream() << toJson().dump(2) << "\n";
    out.commit();
}

} // namespace gt::eyetrack
