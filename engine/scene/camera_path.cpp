#include "scene/camera_path.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "atomic_write.hpp"
#include "core/error.hpp"
#include "core/input.hpp"
#include "limits.hpp"

namespace gt::scene {

namespace {
bool sameEyeAndTarget(const CameraKey& k) {
    return glm::length(k.target - k.eye) < 1e-6f;
}

constexpr std::array<const char*, 7> kColumns = {"t_ms", "ex", "ey", "ez", "tx", "ty", "tz"};

// Column i's bound: times within io::limits::kTableTimeMs, eye and target coordinates within
// io::limits::kSceneCoordinate (1e300 turned into an infinite float and a NaN camera).
double columnLimit(std::size_t i) {
    return i == 0 ? io::limits::kTableTimeMs : io::limits::kSceneCoordinate;
}

bool inRange(double v, std::size_t column) {
    return std::isfinite(v) && std::abs(v) <= columnLimit(column);
}

// One data row: seven numbers, each finite and within its column's bound. `where` is
// "FILE:LINE" and starts every message.
CameraKey parseRow(std::string_view line, const std::string& where) {
    std::array<double, 7> v{};
    std::size_t column = 0;
    for (std::size_t start = 0; start <= line.size(); ++column) {
        std::size_t comma = line.find(',', start);
        if (comma == std::string_view::npos) comma = line.size();
        const std::string field(line.substr(start, comma - start));
        start = comma + 1;
        char* end = nullptr;
        const double x = std::strtod(field.c_str(), &end);
        if (column >= v.size() || end == field.c_str() || *end != '\0') {
            throw LoadError(where + ": expected seven numbers t_ms,ex,ey,ez,tx,ty,tz");
        }
        if (!inRange(x, column)) {
            char bound[32];
            std::snprintf(bound, sizeof bound, "%g", columnLimit(column));
            throw LoadError(where + ": " + kColumns[column] + " " + field +
                            " is not a finite number within +-" + bound);
        }
        v[column] = x;
    }
    if (column != v.size()) {
        throw LoadError(where + ": expected seven numbers t_ms,ex,ey,ez,tx,ty,tz");
    }
    return {v[0], glm::vec3(v[1], v[2], v[3]), glm::vec3(v[4], v[5], v[6])};
}
} // namespace

CameraPath CameraPath::fromKeys(std::vector<CameraKey> keys) {
    if (keys.empty()) throw LoadError("camera path: no rows");
    for (std::size_t i = 0; i < keys.size(); ++i) {
        const CameraKey& k = keys[i];
        const std::array<double, 7> v = {k.tMs,      k.eye.x,    k.eye.y,   k.eye.z,
                                         k.target.x, k.target.y, k.target.z};
        for (std::size_t c = 0; c < v.size(); ++c) {
            if (!inRange(v[c], c)) {
                throw LoadError("camera path: row " + std::to_string(i + 1) + " has " +
                                kColumns[c] + " " + std::to_string(v[c]) + " out of range");
            }
        }
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
    // A regular file of bounded size only: a FIFO blocked forever, /dev/zero grew without end.
    const std::string text = readInput(file, io::limits::kTextTableBytes);
    std::vector<CameraKey> keys;
    int number = 0;
    bool header = false;
    for (std::size_t at = 0; at < text.size();) {
        std::size_t eol = text.find('\n', at);
        if (eol == std::string::npos) eol = text.size();
        std::string_view line(text.data() + at, eol - at);
        at = eol + 1;
        ++number;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (line.empty() || line[0] == '#') continue;
        const std::string where = file.string() + ":" + std::to_string(number);
        if (!header) {
            if (line != "t_ms,ex,ey,ez,tx,ty,tz") {
                throw LoadError(where + ": expected the header t_ms,ex,ey,ez,tx,ty,tz");
            }
            header = true;
            continue;
        }
        keys.push_back(parseRow(line, where));
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
