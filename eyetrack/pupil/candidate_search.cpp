#include "pupil/candidate_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "pupil/image_sampling.hpp"

namespace gt::eyetrack::starburst {

void CandidateSearch::find(const cv::Mat& grey, const cv::Mat& fullIntegral, double minR,
                           double maxR, std::vector<Candidate>& out, std::size_t limit) {
    search(grey, fullIntegral, minR, maxR, mSmall, mIntegral, out, limit);
}

void CandidateSearch::findClosed(const cv::Mat& grey, int side, double minR, double maxR,
                                 std::vector<Candidate>& out, std::size_t limit) {
    cv::morphologyEx(grey, mClosed, cv::MORPH_CLOSE,
                     cv::getStructuringElement(cv::MORPH_RECT, {side, side}));
    cv::integral(mClosed, mClosedIntegral, CV_32S);
    search(grey, mClosedIntegral, minR, maxR, mClosedSmall, mClosedSmallIntegral, out, limit);
}

void CandidateSearch::search(const cv::Mat& grey, const cv::Mat& fullIntegral, double minR,
                             double maxR, cv::Mat& small, cv::Mat& integral,
                             std::vector<Candidate>& out, std::size_t limit) {
    // Downscale so the coarse image is ~60 rows: the search only needs a seed inside the pupil.
    const int f = std::max(1, std::min(grey.rows, grey.cols) / 60);
    mCoarseFactor = f;
    // The coarse image: the means of f x f blocks, rounded, read off the full-resolution
    // integral image (the detector builds it first, for the glint test) at a tenth of cv::resize's
    // cost. The same pixels as INTER_AREA's when f divides the image's size (320 x 240 and
    // 640 x 480 both); otherwise the right and bottom remainders are left out, and a coarse
    // pixel's centre stays exactly where the search maps it back to.
    small.create(grey.rows / f, grey.cols / f, CV_8UC1);
    const double blockArea = static_cast<double>(f) * f;
    for (int y = 0; y < small.rows; ++y) {
        auto* row = small.ptr<uchar>(y);
        for (int x = 0; x < small.cols; ++x) {
            const long long sum = boxSum(fullIntegral, x * f, y * f, x * f + f, y * f + f);
            row[x] = cv::saturate_cast<uchar>(static_cast<double>(sum) / blockArea);
        }
    }
    cv::integral(small, integral, CV_32S);
    mHeap.clear();
    for (double r = std::max(1.5, minR / f); r <= maxR / f + 1e-9; r *= 1.3) {
        keepPeaks(integral, r);
    }
    const auto weaker = [](const Candidate& a, const Candidate& b) {
        return a.response > b.response;
    };
    std::sort_heap(mHeap.begin(), mHeap.end(), weaker); // strongest first
    for (const Candidate& c : mHeap) {
        // Suppress only the same blob at a similar scale: a pupil inside a dark iris (low
        // pupil/iris contrast) is a smaller blob within a larger one and must stay a candidate.
        if (out.size() >= limit) {
            break;
        }
        const bool near = std::any_of(out.begin(), out.end(), [&](const Candidate& k) {
            const double ratio = std::max(k.radius, c.radius) / std::min(k.radius, c.radius);
            return cv::norm(k.centre - c.centre) < std::max(k.radius, c.radius) && ratio < 1.8;
        });
        if (!near) {
            out.push_back(c);
        }
    }
}

void CandidateSearch::keepPeaks(const cv::Mat& integral, double r) {
    // The strongest responses, kept in a bounded min-heap (sorting every position would cost
    // more than the rest of the detector).
    constexpr std::size_t kKeep = 48;
    const int f = mCoarseFactor;
    const int w = integral.cols - 1, h = integral.rows - 1;
    std::vector<Candidate>& all = mHeap;
    const auto weaker = [](const Candidate& a, const Candidate& b) {
        return a.response > b.response;
    };
    const int hi = std::max(1, static_cast<int>(std::lround(0.75 * r)));
    const int ho = std::max(hi + 1, static_cast<int>(std::lround(1.8 * r)));
    const int step = std::max(1, static_cast<int>(r / 2.0));
    const int gw = (w + step - 1) / step, gh = (h + step - 1) / step;
    const auto cell = [gw](int x, int y) {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(gw) +
               static_cast<std::size_t>(x);
    };
    if (mResponses.size() < cell(0, gh)) {
        mResponses.resize(cell(0, gh)); // every cell is written below
    }
    for (int gy = 0; gy < gh; ++gy) {
        CentreSurroundRow(integral, gy * step, hi, ho).fill(step, gw, &mResponses[cell(0, gy)]);
    }
    // Only local maxima over the 3x3 neighbourhood at this scale compete: a large dark
    // shadow responds strongly at every position around it and would otherwise fill the
    // kept set with copies of itself, crowding a fainter pupil out before the suppression
    // below could set them aside.
    const double minResponse = 0.5 * mMinContrast;
    for (int gy = 0; gy < gh; ++gy) {
        const double* row = &mResponses[cell(0, gy)];
        const double* above = gy > 0 ? row - gw : nullptr;
        const double* below = gy + 1 < gh ? row + gw : nullptr;
        for (int gx = 0; gx < gw; ++gx) {
            const double response = row[gx];
            if (response < minResponse) {
                continue;
            }
            // Ties go to the first in scan order, so a flat top keeps one peak: a neighbour
            // later in the scan may equal the response, an earlier one may not.
            const auto under = [response](double other, bool later) {
                return other < response || (later && other == response);
            };
            const bool left = gx > 0, right = gx + 1 < gw;
            const bool peak =
                (!above || ((!left || under(above[gx - 1], false)) && under(above[gx], false) &&
                            (!right || under(above[gx + 1], false)))) &&
                (!left || under(row[gx - 1], false)) && (!right || under(row[gx + 1], true)) &&
                (!below || ((!left || under(below[gx - 1], true)) && under(below[gx], true) &&
                            (!right || under(below[gx + 1], true))));
            if (!peak) {
                continue;
            }
            if (all.size() == kKeep) {
                if (response <= all.front().response) continue;
                std::pop_heap(all.begin(), all.end(), weaker);
                all.pop_back();
            }
            const int x = gx * step, y = gy * step;
            all.push_back({{(x + 0.5) * f - 0.5, (y + 0.5) * f - 0.5}, r * f, response});
            std::push_heap(all.begin(), all.end(), weaker);
        }
    }
}

std::optional<Candidate> CandidateSearch::inside(cv::Point2d outerCentre, double outerSemiMinor,
                                                 double outerInterior, double minR) {
    // ellipse, restricted to centres inside it and radii below 0.7 of its minor semi-axis. The
    // coarse image is clipped at the outer blob's upper-quartile level (its iris) first, so the
    // sclera beyond it and glints on it cannot pull the ring's mean up and the seed off the
    // pupil, and the ring may reach past the outer blob's edge.
    const int f = mCoarseFactor;
    const double maxR = 0.7 * outerSemiMinor / f;
    const double lo = std::max(1.5, minR / f);
    if (maxR < lo) return std::nullopt;
    const double reach = 0.6 * outerSemiMinor / f;
    const double ox = (outerCentre.x + 0.5) / f - 0.5, oy = (outerCentre.y + 0.5) / f - 0.5;
    const int margin = static_cast<int>(std::ceil(reach + 1.8 * maxR)) + 2;
    const cv::Rect roi = cv::Rect(static_cast<int>(ox) - margin, static_cast<int>(oy) - margin,
                                  2 * margin + 1, 2 * margin + 1) &
                         cv::Rect(0, 0, mSmall.cols, mSmall.rows);
    if (roi.width < 3 || roi.height < 3) return std::nullopt;
    cv::min(mSmall(roi), cv::Scalar(std::clamp(outerInterior, 0.0, 255.0)), mInnerClipped);
    cv::integral(mInnerClipped, mInnerIntegral, CV_32S);
    const int w = roi.width, h = roi.height;
    const double cx = ox - roi.x, cy = oy - roi.y;
    std::optional<Candidate> best;
    for (double r = lo; r <= maxR + 1e-9; r *= 1.25) {
        const int hi = std::max(1, static_cast<int>(std::lround(0.75 * r)));
        const int ho = std::max(hi + 1, static_cast<int>(std::lround(1.8 * r)));
        for (int y = std::max(0, static_cast<int>(cy - reach));
             y <= std::min(h - 1, static_cast<int>(cy + reach) + 1); ++y) {
            const CentreSurroundRow row(mInnerIntegral, y, hi, ho);
            for (int x = std::max(0, static_cast<int>(cx - reach));
                 x <= std::min(w - 1, static_cast<int>(cx + reach) + 1); ++x) {
                if ((x - cx) * (x - cx) + (y - cy) * (y - cy) > reach * reach) continue;
                const double response = row.at(x);
                if (response < 0.5 * mMinContrast) continue;
                if (!best || response > best->response)
                    best = Candidate{{(x + roi.x + 0.5) * f - 0.5, (y + roi.y + 0.5) * f - 0.5},
                                     r * f,
                                     response};
            }
        }
    }
    return best;
}

} // namespace gt::eyetrack::starburst
