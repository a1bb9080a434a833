#include "score/detection_score.hpp"

#include <algorithm>

#include "stats.hpp"

namespace gt::eyetrack {

bool isRight(const DetectionRecord& r, double radiusPx) {
    return r.visible && r.answered && r.errorPx <= radiusPx;
}

DetectionScore scoreDetections(const std::vector<DetectionRecord>& records, double radiusPx) {
    DetectionScore s;
    s.frames = static_cast<int>(records.size());
    std::vector<double> errors, right, wrong;
    for (const DetectionRecord& r : records) {
        if (r.visible) {
            ++s.visible;
            if (r.answered) {
                errors.push_back(r.errorPx);
            }
            if (isRight(r, radiusPx)) {
                ++s.withinRadius;
            }
        }
        if (!r.answered) {
            continue;
        }
        (isRight(r, radiusPx) ? right : wrong).push_back(r.confidence);
        if (!r.visible) {
            ++s.wrongHidden;
        }
    }
    s.detectionRate = s.visible > 0 ? static_cast<double>(s.withinRadius) / s.visible : 0.0;
    s.medianErrorPx = median(errors);
    s.right = static_cast<int>(right.size());
    s.wrong = static_cast<int>(wrong.size());
    if (!right.empty() && !wrong.empty()) {
        // Mann-Whitney U by sorting the wrong answers once and counting per right answer.
        std::sort(wrong.begin(), wrong.end());
        double u = 0.0;
        for (const double c : right) {
            const auto lo = std::lower_bound(wrong.begin(), wrong.end(), c);
            const auto hi = std::upper_bound(wrong.begin(), wrong.end(), c);
            u += static_cast<double>(lo - wrong.begin()) + 0.5 * static_cast<double>(hi - lo);
        }
        s.rocAuc = u / (static_cast<double>(right.size()) * static_cast<double>(wrong.size()));
    }
    return s;
}

ThresholdRates ratesAt(const std::vector<DetectionRecord>& records, double threshold,
                       double radiusPx) {
    ThresholdRates t;
    t.threshold = threshold;
    int right = 0, kept = 0, wrong = 0, rejected = 0;
    for (const DetectionRecord& r : records) {
        if (!r.answered) {
            continue;
        }
        if (isRight(r, radiusPx)) {
            ++right;
            if (r.confidence >= threshold) {
                ++kept;
            }
        } else {
            ++wrong;
            if (r.confidence < threshold) {
                ++rejected;
            }
        }
    }
    t.rightKept = right > 0 ? static_cast<double>(kept) / right : 1.0;
    t.wrongRejected = wrong > 0 ? static_cast<double>(rejected) / wrong : 1.0;
    return t;
}

} // namespace gt::eyetrack
