#pragma once
// Small statistics shared by the tracker's calibration and reports.
#include <algorithm>
#include <vector>

namespace gt::eyetrack {

// The median (upper median for even sizes); 0 for an empty set.
[[nodiscard]] inline double median(std::vector<double> v) {
    if (v.empty()) {
        return 0.0;
    }
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

} // namespace gt::eyetrack
