#include "scene/camera_path.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "atomic_write.hpp"
#include "core/error.hpp"

namespace gt::scene {

namespace {
bool sameEyeAndTarget(const CameraKey& k) {
    return glm::length(k.target - k.eye) < 1e-6f;
}
} // namespace

CameraPath CameraPath::fromKeys(std::vector<CameraKey> keys) {
    if (keys.empty()) throw LoadError("camera path: no rows");
    for (std::size_t i = 0; i < keys.size(); ++i) {
        if (sameEyeAndTarget(keys[i])) {
            throw LoadError("camera path: row " + std::to_string(i + 1) +
                            " has the eye on its target");
        }
        if (i > 0 && !(keys[i].tMs > keys[i - 1].tMs)) {
            throw LoadError("camera path: times must increase (row " + std::to_string(i + 1) + ")");
        }
    }
    CameraPath p;
    p.mKeys = std::move(keys);
    return p;
}

CameraPath CameraPath::load(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec)) {
        throw LoadError(file.string() + ": is a folder, not a camera path CSV");
    }
    if (!in) throw LoadError(file.string() + ": cannot open camera path");
    std::vector<CameraKey> keys;
    std::string line;
    int number = 0;
    bool header = false;
    while (std::getline(in, line)) {
        ++number;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty() || line[0] == '#') continue;
        if (!header) {
            if (line != "t_ms,ex,ey,ez,tx,ty,tz") {
                throw LoadError(file.string() + ":" + std::to_string(number) +
                                ": expected the header t_ms,ex,ey,ez,tx,ty,tz");
            }
            header = true;
            continue;
        }
        double v[7];
        char extra = 0;
        if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &v[3],
                        &v[4], &v[5], &v[6], &extra) != 7 ||
            !std::all_of(std::begin(v), std::end(v), [](double x) { return std::isfinite(x); })) {
            throw LoadError(file.string() + ":" + std::to_string(number) +
                            ": expected seven numbers t_ms,ex,ey,ez,tx,ty,tz");
        }
        keys.push_back({v[0], glm::vec3(v[1], v[2], v[3]), glm::vec3(v[4], v[5], v[6])});
    }
    if (!header) throw LoadError(file.string() + ": empty camera path (no header)");
    try {
        return fromKeys(std::move(keys));
    } catch (const LoadError& e) {
        throw LoadError(file.string() + ": " + e.what());
    }
}

void CameraPath::save(const std::filesystem::path& file) const {
    std::string text = "t_ms,ex,ey,ez,tx,ty,tz\n";
    char row[256];
    for (const CameraKey& k : mKeys) {
        std::snprintf(row, sizeof(row), "%.3f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", k.tMs, k.eye.x,
                      k.eye.y, k.eye.z, k.target.x, k.target.y, k.target.z);
        text += row;
    }
    try {
        io::writeFileAtomic(file, text);
    } catch (const io::WriteError& e) {
        throw Error(e.what());
    }
}

Camera CameraPath::at(double tMs, float yfov) const {
    const auto it = std::upper_bound(mKeys.begin(), mKeys.end(), tMs,
                                     [](double t, const CameraKey& k) { return t < k.tMs; });
    if (it == mKeys.begin()) return lookAt(mKeys.front().eye, mKeys.front().target, yfov);
    if (it == mKeys.end()) return lookAt(mKeys.back().eye, mKeys.back().target, yfov);
    const CameraKey& a = *(it - 1);
    const CameraKey& b = *it;
    const float f = static_cast<float>((tMs - a.tMs) / (b.tMs - a.tMs));
    const glm::vec3 eye = glm::mix(a.eye, b.eye, f);
    glm::vec3 target = glm::mix(a.target, b.target, f);
    if (glm::length(target - eye) < 1e-6f) target = eye + (b.target - b.eye);
    return lookAt(eye, target, yfov);
}

} // namespace gt::scene
