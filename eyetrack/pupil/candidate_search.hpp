#pragma once
// Stage 1 of the starburst detector: where the pupil may be.
//
// The coarse search of Świrski, Bulling & Dodgson 2012: on a downscaled image's integral image, a
// centre-surround box feature (mean of a surrounding ring minus mean of an inner box) over a
// range of radii finds dark compact regions; the strongest local maxima of each radius, after
// non-maximum suppression across radii, are candidates. Cost O(1) per position and radius. The
// same feature, restricted to the inside of an ellipse, finds a pupil inside a dark iris
// (inside()). Tracking last frame's pupil is the detector's: it puts that pupil first in the list.
#include <cstddef>
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
    CentreSurroundRow(const cv::Mat& ii, int y, int hi, int ho);

    [[nodiscard]] double at(int x) const;
    // out[k] = at(k * step) for k in [0, count), the unclipped middle of the row vectorised.
    void fill(int step, int count, double* out) const;

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
