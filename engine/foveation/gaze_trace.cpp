#include "foveation/gaze_trace.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/input.hpp"
#include "limits.hpp"

namespace gt::foveation {

namespace {

std::string trim(std::string s) {
    s.erase(std::remove(s.begin(), s.end(), ' '), s.end());
    return s;
}

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream in(line);
    for (std::string f; std::getline(in, f, ',');) {
        out.push_back(trim(f));
    }
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
}

glm::vec2 interpolate(const std::vector<GazeTraceSample>& v, double tMs) {
    if (tMs <= v.front().tMs) return v.front().position;
    if (tMs >= v.back().tMs) return v.back().position;
    const auto it = std::upper_bound(v.begin(), v.end(), tMs,
                                     [](double t, const GazeTraceSample& s) { return t < s.tMs; });
    const GazeTraceSample& b = *it;
    const GazeTraceSample& a = *(it - 1);
    const auto f = static_cast<float>((tMs - a.tMs) / (b.tMs - a.tMs));
    return glm::mix(a.position, b.position, f);
}

} // namespace

GazeTrace GazeTrace::load(const std::filesystem::path& file) {
    // A regular file of bounded size only: a FIFO blocked forever, /dev/zero grew without end.
    std::istringstream in(readInput(file, io::limits::kTextTableBytes));
    std::string line;
    std::vector<GazeTraceSample> samples;
    int lineNo = 0;
    std::optional<GazeUnits> units;
    bool eyeColumn = false;
    std::string expected;
    auto bad = [&](const std::string& why) {
        return LoadError(file.string() + ":" + std::to_string(lineNo) + ": " + why);
    };
    while (std::getline(in, line)) {
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty() || line[0] == '#') continue;
        if (!units) {
            const std::string h = trim(line);
            if (h == "t_ms,x,y") {
                units = GazeUnits::Pixels;
                expected = "three numbers t_ms,x,y";
            } else if (h == "t_ms,yaw_deg,pitch_deg" || h == "t_ms,yaw_deg,pitch_deg,eye") {
                units = GazeUnits::AnglesDeg;
                eyeColumn = h.size() > 22;
                expected = eyeColumn ? "t_ms,yaw_deg,pitch_deg,eye (left|right|both)"
                                     : "three numbers t_ms,yaw_deg,pitch_deg";
            } else {
                throw bad("expected the header 't_ms,x,y' or 't_ms,yaw_deg,pitch_deg[,eye]'");
            }
            continue;
        }
        const std::vector<std::string> f = split(line);
        if (f.size() != (eyeColumn ? 4u : 3u)) throw bad("expected " + expected);
        double v[3];
        for (int i = 0; i < 3; ++i) {
            char* end = nullptr;
            v[i] = std::strtod(f[static_cast<std::size_t>(i)].c_str(), &end);
            if (f[static_cast<std::size_t>(i)].empty() || *end != '\0') {
                throw bad("expected " + expected);
            }
            if (!std::isfinite(v[i])) {
                throw bad("'" + f[static_cast<std::size_t>(i)] + "' is not a finite number");
            }
        }
        GazeEye eye = GazeEye::Both;
        if (eyeColumn) {
            if (f[3] == "left") {
                eye = GazeEye::Left;
            } else if (f[3] == "right") {
                eye = GazeEye::Right;
            } else if (f[3] != "both") {
                throw bad("eye must be left, right or both, got '" + f[3] + "'");
            }
        }
        // Times feed frame counts and interpolation weights: 1e300 ms overflowed the former.
        if (std::abs(v[0]) > io::limits::kTableTimeMs) {
            char bound[32];
            std::snprintf(bound, sizeof bound, "%g", io::limits::kTableTimeMs);
            throw bad("t_ms " + f[0] + " is out of range (+-" + bound + ")");
        }
        if (*units == GazeUnits::AnglesDeg && (std::abs(v[1]) >= 90.0 || std::abs(v[2]) >= 90.0)) {
            throw bad("gaze angles must lie within +-90 degrees, got " + f[1] + ", " + f[2]);
        }
        // Positions are kept as floats: 1e300 became infinity (a fuzz regression case). Gaze may
        // leave the screen, but not by a million pixels.
        if (*units == GazeUnits::Pixels && (std::abs(v[1]) > 1e6 || std::abs(v[2]) > 1e6)) {
            throw bad("gaze pixels must lie within +-1000000, got " + f[1] + ", " + f[2]);
        }
        samples.push_back({v[0], {static_cast<float>(v[1]), static_cast<float>(v[2])}, eye});
    }
    if (!units || samples.empty()) throw LoadError(file.string() + ": gaze trace has no samples");
    try {
        return fromSamples(std::move(samples), *units);
    } catch (const LoadError& e) {
        throw LoadError(file.string() + ": " + e.what());
    }
}

GazeTrace GazeTrace::fromSamples(std::vector<GazeTraceSample> samples) {
    return fromSamples(std::move(samples), GazeUnits::Pixels);
}

GazeTrace GazeTrace::fromSamples(std::vector<GazeTraceSample> samples, GazeUnits units) {
    if (samples.empty()) throw LoadError("gaze trace has no samples");
    GazeTrace t;
    t.mUnits = units;
    for (const GazeTraceSample& s : samples) {
        auto& stream = t.mPerEye[static_cast<int>(s.eye)];
        if (!stream.empty() && s.tMs <= stream.back().tMs) {
            throw LoadError("t_ms must increase (at " + std::to_string(s.tMs) + " ms)");
        }
        stream.push_back(s);
    }
    const auto [first, last] = std::minmax_element(
        samples.begin(), samples.end(),
        [](const GazeTraceSample& a, const GazeTraceSample& b) { return a.tMs < b.tMs; });
    t.mStartMs = first->tMs;
    t.mEndMs = last->tMs;
    t.mSamples = std::move(samples);
    return t;
}

bool GazeTrace::hasEye(GazeEye eye) const noexcept {
    return !mPerEye[static_cast<int>(eye)].empty();
}

glm::vec2 GazeTrace::at(double tMs) const {
    for (const GazeEye e : {GazeEye::Both, GazeEye::Left, GazeEye::Right}) {
        if (hasEye(e)) return interpolate(mPerEye[static_cast<int>(e)], tMs);
    }
    return mSamples.front().position;
}

glm::vec2 GazeTrace::at(double tMs, GazeEye eye) const {
    return hasEye(eye) ? interpolate(mPerEye[static_cast<int>(eye)], tMs) : at(tMs);
}

} // namespace gt::foveation
