#include "pupil/blob_detector.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "error.hpp"

namespace gt::eyetrack {

PupilResult BlobDetector::detect(const cv::Mat& grey, double /*tMs*/) {
    if (grey.empty() || grey.type() != CV_8UC1) {
        throw EyetrackError("pupil detector: expected an 8-bit greyscale image");
    }
    // Threshold 15 grey levels above the 1st percentile.
    std::array<int, 256> hist{};
    for (int y = 0; y < grey.rows; ++y) {
        const uchar* row = grey.ptr<uchar>(y);
        for (int x = 0; x < grey.cols; ++x) {
            ++hist[row[x]];
        }
    }
    const int target = static_cast<int>(0.01 * grey.total());
    int level = 0;
    for (int acc = 0; level < 255; ++level) {
        acc += hist[static_cast<std::size_t>(level)];
        if (acc > target) {
            break;
        }
    }
    cv::threshold(grey, mMask, level + 15, 255, cv::THRESH_BINARY_INV);
    const int n = cv::connectedComponentsWithStats(mMask, mLabels, mStats, mCentroids, 8, CV_32S);
    int best = 0, bestArea = 0;
    for (int i = 1; i < n; ++i) {
        const int area = mStats.at<int>(i, cv::CC_STAT_AREA);
        if (area > bestArea) {
            bestArea = area;
            best = i;
        }
    }
    PupilResult r;
    if (best == 0 || bestArea < 20) {
        return r;
    }
    cv::Mat blob = mLabels == best;
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(blob, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    if (contours.empty() || contours.front().size() < 5) {
        return r;
    }
    const auto& outline =
        *std::max_element(contours.begin(), contours.end(),
                          [](const auto& a, const auto& b) { return a.size() < b.size(); });
    r.ellipse = cv::fitEllipse(outline);
    const double ellipseArea =
        std::numbers::pi * 0.25 * r.ellipse.size.width * r.ellipse.size.height;
    r.confidence = ellipseArea > 0.0 ? std::clamp(bestArea / ellipseArea, 0.0, 1.0) : 0.0;
    r.found = r.confidence > 0.5;
    return r;
}

} // namespace gt::eyetrack
