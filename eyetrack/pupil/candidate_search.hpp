#pragma once
// Stage 1 of the starburst detector: where the pupil may be.
//
// The coarse search of Świrski, Bulling & Dodgson 2012: on a downscaled image's integral image, a
// centre-surround box feature (mean of a surrounding ring minus mean of an inner box) over a
// range of radii finds dark compact regions; the strongest local maxima of each radius, after
// non-maximum suppression across radii, are candidates. Cost O(1) per position and radius. The
// same feature, restricted to the inside of an ellipse, finds a pupil inside a dark iris
// (inside()). Tracking last frame's pupil is the detector's: it puts that pupil first in the list.
#include <algorithm>
#include <cstddef>
#include <limits>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

namespace gt::eyetrack::starburst {

// A dark blob: a seed inside the pupil and the scale it responded at (full-resolution pixels).
struct Candidate {
    cv::Point2d centre;
    double radius = 0.0;
    double response = 0.0; // ring mean less inner mean, grey levels
};

// Centre-surround responses along row y of the image behind a CV_32S integral image: at column x,
// the mean of the ring between the (2 ho + 1)^2 and (2 hi + 1)^2 boxes minus the inner box's mean
// (dark centre: positive), both boxes clipped at the border; -inf when the clipped ring is no
// larger than the inner box. The row's clipping and pointers are set once: the searches call
// at() for every position and scale, the larger part of the detector's work.
class CentreSurroundRow {
public:
    // The row keeps pointers into `ii`: a temporary integral image would leave them dangling.
    CentreSurroundRow(const cv::Mat&& ii, int y, int hi, int ho) = delete;
    CentreSurroundRow(const cv::Mat& ii, int y, int hi, int ho)
        : mW(ii.cols - 1), mHi(hi), mHo(ho),
          mInnerRows(std::min(ii.rows - 1, y + hi + 1) - std::max(0, y - hi)),
          mOuterRows(std::min(ii.rows - 1, y + ho + 1) - std::max(0, y - ho)),
          mI0(ii.ptr<int>(std::max(0, y - hi))),
          mI1(ii.ptr<int>(std::min(ii.rows - 1, y + hi + 1))),
          mO0(ii.ptr<int>(std::max(0, y - ho))),
          mO1(ii.ptr<int>(std::min(ii.rows - 1, y + ho + 1))) {}

    [[nodiscard]] double at(int x) const {
        const int ix0 = std::max(0, x - mHi), ix1 = std::min(mW, x + mHi + 1);
        const int ox0 = std::max(0, x - mHo), ox1 = std::min(mW, x + mHo + 1);
        const long long inner = static_cast<long long>(mI1[ix1]) - mI1[ix0] - mI0[ix1] + mI0[ix0];
        const long long outer = static_cast<long long>(mO1[ox1]) - mO1[ox0] - mO0[ox1] + mO0[ox0];
        const int innerArea = (ix1 - ix0) * mInnerRows;
        const int ringArea = (ox1 - ox0) * mOuterRows - innerArea;
        if (ringArea <= innerArea) {
            return -std::numeric_limits<double>::infinity();
        }
        return static_cast<double>(outer - inner) / ringArea -
               static_cast<double>(inner) / innerArea;
    }

    // out[k] = at(k * step) for k in [0, count): the same values, with the part of the row where
    // neither box is clipped (the areas fixed there) as a loop the compiler vectorises — at one
    // coarse pixel's step it is most of the coarse search. Box sums are taken as differences of
    // two column differences, each within the integral image's (int) range.
    void fill(int step, int count, double* out) const {
        const int first = std::min(count, (mHo + step - 1) / step);
        const int end =
            std::max(first, std::min(count, mW - mHo >= 1 ? (mW - mHo - 1) / step + 1 : 0));
        for (int k = 0; k < first; ++k) {
            out[k] = at(k * step);
        }
        const int innerArea = (2 * mHi + 1) * mInnerRows;
        const int ringArea = (2 * mHo + 1) * mOuterRows - innerArea;
        if (ringArea <= innerArea) {
            std::fill(out + first, out + end, -std::numeric_limits<double>::infinity());
        } else {
            const int *i0 = mI0, *i1 = mI1, *o0 = mO0, *o1 = mO1;
            const int hi = mHi, ho = mHo;
            const auto one = [&](int x) {
                const int inner = (i1[x + hi + 1] - i0[x + hi + 1]) - (i1[x - hi] - i0[x - hi]);
                const int outer = (o1[x + ho + 1] - o0[x + ho + 1]) - (o1[x - ho] - o0[x - ho]);
                return static_cast<double>(outer - inner) / ringArea -
                       static_cast<double>(inner) / innerArea;
            };
            if (step == 1) {
                for (int x = first; x < end; ++x) {
                    out[x] = one(x);
                }
            } else {
                for (int k = first; k < end; ++k) {
                    out[k] = one(k * step);
                }
            }
        }
        for (int k = end; k < count; ++k) {
            out[k] = at(k * step);
        }
    }

private:
    int mW, mHi, mHo, mInnerRows, mOuterRows;
    const int *mI0, *mI1, *mO0, *mO1;
};

class CandidateSearch {
public:
    // minContrast: the least pupil-to-surround step; blobs responding below half of it are noise.
    explicit CandidateSearch(double minContrast) : mMinContrast(minContrast) {}

    // The strongest dark blobs of `grey` (`fullIntegral`: its CV_32S integral image) with radii in
    // [minR, maxR], each unlike those already in `out`, appended until `out` holds `limit`.
    void find(const cv::Mat& grey, const cv::Mat& fullIntegral, double minR, double maxR,
              std::vector<Candidate>& out, std::size_t limit);
    // The same search on `grey` closed (a grey-level closing) with a square of `side` pixels:
    // dark structures narrower than the square (lashes, eyeliner, the gaps of a lash cluster) are
    // removed, so a pupil they cross or crowd is a round blob again.
    void findClosed(const cv::Mat& grey, int side, double minR, double maxR,
                    std::vector<Candidate>& out, std::size_t limit);
    // The strongest smaller dark blob within an outer blob (its centre and minor semi-axis, and
    // outerInterior: the level around a pupil in it), on find()'s coarse image.
    [[nodiscard]] std::optional<Candidate> inside(cv::Point2d outerCentre, double outerSemiMinor,
                                                  double outerInterior, double minR);

private:
    void search(const cv::Mat& grey, const cv::Mat& fullIntegral, double minR, double maxR,
                cv::Mat& small, cv::Mat& integral, std::vector<Candidate>& out, std::size_t limit);
    // One scale's local maxima (radius r in coarse pixels) into mHeap, the strongest kept.
    void keepPeaks(const cv::Mat& integral, double r);

    double mMinContrast;
    int mCoarseFactor = 1; // full-resolution pixels per coarse pixel
    // Scratch buffers reused between frames (no per-frame allocation in steady state).
    cv::Mat mSmall, mIntegral, mInnerClipped, mInnerIntegral;
    cv::Mat mClosed, mClosedIntegral, mClosedSmall, mClosedSmallIntegral;
    std::vector<Candidate> mHeap;
    std::vector<double> mResponses; // one scale's centre-surround responses
};

} // namespace gt::eyetrack::starburst
