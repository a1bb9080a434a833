#include "foveation/gaze_trace.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/error.hpp"

namespace gt::foveation {

GazeTrace GazeTrace::load(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) throw LoadError(file.string() + ": cannot open gaze trace");
    std::string line;
    std::vector<GazeTraceSample> samples;
    int lineNo = 0;
    bool header = false;
    while (std::getline(in, line)) {
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty() || line[0] == '#') continue;
        if (!header) {
            std::string h = line;
            h.erase(std::remove(h.begin(), h.end(), ' '), h.end());
            if (h.rfind("t_ms,x,y", 0) != 0) {
                throw LoadError(file.string() + ":" + std::to_string(lineNo) +
                                ": expected the header 't_ms,x,y'");
            }
            header = true;
            continue;
        }
        double v[3];
        const char* p = line.c_str();
        for (int i = 0; i < 3; ++i) {
            char* end = nullptr;
            v[i] = std::strtod(p, &end);
            if (end == p || !std::isfinite(v[i])) {
                throw LoadError(file.string() + ":" + std::to_string(lineNo) +
                                ": expected three numbers t_ms,x,y");
            }
            p = end;
            while (*p == ' ')
                ++p;
            if (i < 2) {
                if (*p != ',') {
                    throw LoadError(file.string() + ":" + std::to_string(lineNo) +
                                    ": expected three numbers t_ms,x,y");
                }
                ++p;
            }
        }
        if (!samples.empty() && v[0] <= samples.back().tMs) {
            throw LoadError(file.string() + ":" + std::to_string(lineNo) + ": t_ms must increase");
        }
        samples.push_back({v[0], {static_cast<float>(v[1]), static_cast<float>(v[2])}});
    }
    if (samples.empty()) throw LoadError(file.string() + ": gaze trace has no samples");
    return fromSamples(std::move(samples));
}

GazeTrace GazeTrace::fromSamples(std::vector<GazeTraceSample> samples) {
    if (samples.empty()) throw LoadError("gaze trace has no samples");
    GazeTrace t;
    t.mSamples = std::move(samples);
    return t;
}

glm::vec2 GazeTrace::at(double tMs) const {
    if (tMs <= mSamples.front().tMs) return mSamples.front().position;
    if (tMs >= mSamples.back().tMs) return mSamples.back().position;
    const auto it = std::upper_bound(mSamples.begin(), mSamples.end(), tMs,
                                     [](double t, const GazeTraceSample& s) { return t < s.tMs; });
    const GazeTraceSample& b = *it;
    const GazeTraceSample& a = *(it - 1);
    const auto f = static_cast<float>((tMs - a.tMs) / (b.tMs - a.tMs));
    return glm::mix(a.position, b.position, f);
}

} // namespace gt::foveation
