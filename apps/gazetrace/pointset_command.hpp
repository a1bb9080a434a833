#pragma once
// `gazetrace pointset`: generate (or load from the cache) the perceptual point set of a display
// profile, report the thesis's Table 1 figures, optionally draw it (Figure 12).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gt::app {

struct PointSetOptions {
    std::string profile = "fove";
    double scale = 1.0;
    uint64_t seed = 1;
    std::string out;   // write the point set file here too
    std::string image; // draw every point into this PNG
    std::string cacheDir;
    std::vector<double> sweep; // scales for a Figure 14 sweep (overrides --scale)
    // An HMD: compare laying the set in the eye's image with laying it on the panel after the
    // lens (engine/display/display_space.hpp); the profile becomes the HMD's.
    std::string hmd;
};

nlohmann::json runPointSet(const PointSetOptions& options);

} // namespace gt::app
