#include "pupil/edge_rays.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "pupil/image_sampling.hpp"

namespace gt::eyetrack::starburst {

namespace {

// Rays walk in whole pixels and look back half a pixel at the crossing, so the edge is found at
// half-pixel resolution for half the samples (the walk is most of the detector's time). On the
// 3x3-smoothed image, a crossing that the whole-pixel walk steps over (one that crosses back
// within the same pixel) needs a feature barely above the threshold for less than a pixel:
// noise, which the island test would skip anyway.
constexpr double kStep = 0.5;
constexpr double kWalk = 1.0;

// Direction of the image gradient at p by central differences (zero when flat or at the border).
cv::Point2d unitGradient(const cv::Mat& img, cv::Point2d p) {
    const double l = sample(img, p.x - 1.0, p.y), r = sample(img, p.x + 1.0, p.y);
    const double u = sample(img, p.x, p.y - 1.0), d = sample(img, p.x, p.y + 1.0);
    if (l < 0.0 || r < 0.0 || u < 0.0 || d < 0.0) return {0.0, 0.0};
    const cv::Point2d g(r - l, d - u);
    const double len = std::hypot(g.x, g.y);
    return len > 1.0 ? g * (1.0 / len) : cv::Point2d(0.0, 0.0);
}

// A bright island that ends within a few pixels past the crossing at p (sample v) is a glint or
// noise inside the pupil: how far on the ray is dark again, so the walk steps over it and keeps
// looking for the real boundary; -1 when the crossing is no glint's.
double glintIsland(const RayImage& image, cv::Point2d p, cv::Point2d dir, double v,
                   double maxDistance, const RayLevels& lv) {
    using Side = BilinearRange::Side;
    const BilinearRange::Level threshold = BilinearRange::level(lv.threshold);
    const Bilinear sampleAt(image.smooth);
    const double island = std::max(4.0, 0.25 * maxDistance);
    // Only a glint (a spot brighter than its neighbourhood) counts as an island: dark lashes
    // just outside the pupil must not make the real boundary look like one.
    double back = -1.0, peak = v, peakAt = 0.0;
    // Past a pupil's real edge nothing is dark again within the island's reach, and the cells
    // show it: the samples (and the peak, used only for an island) are needed only when some
    // cell reaches below the threshold.
    bool darkAgain = false;
    for (double s = 1.0; s <= island; s += kStep) {
        const Side ahead = image.cells.side(p.x + dir.x * s, p.y + dir.y * s, threshold);
        if (ahead == Side::Outside) {
            break;
        }
        if (ahead != Side::AtOrAbove) {
            darkAgain = true;
            break;
        }
    }
    for (double s = 1.0; darkAgain && s <= island; s += kStep) {
        const double w = sampleAt(p.x + dir.x * s, p.y + dir.y * s);
        if (w < 0.0) break;
        if (w > peak) {
            peak = w;
            peakAt = s;
        }
        if (w < lv.threshold) {
            back = s;
            break;
        }
    }
    return back > 0.0 && isGlint(image.smooth, image.fullIntegral, p + dir * peakAt, lv) ? back
                                                                                         : -1.0;
}

} // namespace

// The median absolute difference between the image and its 3x3 box mean (every other row):
// edges and texture are a small share of the pixels, so the median sees the noise alone. For
// white noise of sigma s the difference has sigma s * sqrt(8/9), and a normal variable's median
// absolute value is 0.6745 of its sigma.
double noiseSigma(const cv::Mat& grey, const cv::Mat& smooth) {
    std::array<int, 256> histogram{};
    int n = 0;
    for (int y = 1; y + 1 < grey.rows; y += 2) {
        const std::uint8_t* g = grey.ptr<std::uint8_t>(y);
        const std::uint8_t* m = smooth.ptr<std::uint8_t>(y);
        for (int x = 1; x + 1 < grey.cols; ++x) {
            ++histogram[static_cast<std::size_t>(std::abs(int{g[x]} - int{m[x]}))];
            ++n;
        }
    }
    int seen = 0;
    for (std::size_t v = 0; v < histogram.size(); ++v) {
        seen += histogram[v];
        if (2 * seen >= n) {
            return (static_cast<double>(v) + 0.5) / (0.6745 * std::sqrt(8.0 / 9.0));
        }
    }
    return 0.0;
}

std::optional<RayLevels> measureLevels(const cv::Mat& grey, const Candidate& c, double minContrast,
                                       double noise) {
    const cv::Rect none(0, 0, 0, 0);
    RayLevels levels;
    // The 30th percentile of the inner box: robust to glints and to a box that overlaps the iris.
    levels.pupil = percentile(grey, boxAround(c.centre, 0.6 * c.radius), none, 0.3);
    levels.surround = percentile(grey, boxAround(c.centre, 2.0 * c.radius),
                                 boxAround(c.centre, 1.3 * c.radius), 0.5);
    if (levels.pupil < 0.0 || levels.surround < 0.0) return std::nullopt;
    if (levels.surround - levels.pupil < minContrast) return std::nullopt;
    // The ring may reach past the iris onto the sclera, so the first threshold sits low in the
    // range, a quarter of the way up; the detector re-measures the level just outside the fitted
    // ellipse and recasts. But the 30th percentile lies below a noisy pupil's mean, and a
    // quarter of the way up from it can lie within the pupil's own noise: rays would then stop
    // inside a pupil only 15-20 grey levels darker than its iris and no fit would form. So the
    // threshold also clears the frame's noise (noiseSigma) three times over, up to half-way.
    // Half-way always would let rays run past a low-contrast pupil into the iris and cost a
    // third of the detector's speed; the inner box's spread in place of the noise would count a
    // lid across the box as noise.
    const double span = levels.surround - levels.pupil;
    levels.threshold = levels.pupil + std::max({0.5 * minContrast, 0.25 * span,
                                                std::min(0.5 * span, 3.0 * noise)});
    levels.glint =
        std::max(levels.surround + 30.0, levels.surround + 0.5 * (255.0 - levels.surround));
    return levels;
}

bool isGlint(const cv::Mat& grey, const cv::Mat& fullIntegral, cv::Point2d p, const RayLevels& lv) {
    // A glint is a small spot much brighter than its 9x9 neighbourhood (a top-hat test on the
    // integral image), or anything saturated; a plain pupil-iris edge is never more than a few
    // grey levels above its box mean.
    // Nearest pixel, halves away from zero as std::lround, which is a library call here and
    // this test runs five times at every ray's crossing.
    const auto nearest = [](double v) {
        // NOLINTNEXTLINE(bugprone-incorrect-roundings): off only for the double just below 0.5
        return v >= 0.0 ? static_cast<int>(v + 0.5) : -static_cast<int>(0.5 - v);
    };
    const int x = nearest(p.x), y = nearest(p.y);
    if (x < 0 || y < 0 || x >= grey.cols || y >= grey.rows) return false;
    const double v = grey.at<uchar>(y, x);
    if (v >= lv.glint) return true;
    const int x0 = std::max(0, x - 4), x1 = std::min(grey.cols, x + 5);
    const int y0 = std::max(0, y - 4), y1 = std::min(grey.rows, y + 5);
    const double mean =
        static_cast<double>(boxSum(fullIntegral, x0, y0, x1, y1)) / ((x1 - x0) * (y1 - y0));
    return v - mean > std::max(25.0, 0.3 * (lv.surround - lv.pupil));
}

EdgeRays::EdgeRays(int rays) {
    mDirections.reserve(static_cast<std::size_t>(rays));
    for (int i = 0; i < rays; ++i) {
        const double a = (i + 0.5) * 2.0 * std::numbers::pi / rays;
        mDirections.emplace_back(std::cos(a), std::sin(a));
    }
}

void EdgeRays::cast(const RayImage& image, cv::Point2d from, double maxDistance,
                    const RayLevels& lv, bool irisOnly, int stride) {
    mPoints.clear();
    mGradients.clear();
    for (std::size_t ray = 0; ray < mDirections.size(); ray += static_cast<std::size_t>(stride)) {
        walk(image, from, mDirections[ray], maxDistance, lv, irisOnly);
    }
}

void EdgeRays::walk(const RayImage& image, cv::Point2d from, cv::Point2d dir, double maxDistance,
                    const RayLevels& lv, bool irisOnly) {
    const Bilinear sampleAt(image.smooth);
    using Side = BilinearRange::Side;
    const BilinearRange::Level threshold = BilinearRange::level(lv.threshold);
    bool inside = false;
    // The last step's grey level; after a step that its cell decided, it is sampled only if the
    // crossing needs it (prevKnown false). Steps are multiples of half a pixel, so t - kWalk is
    // that step's t exactly.
    double prev = -1.0;
    bool prevKnown = true;
    for (double t = 0.0; t <= maxDistance; t += kWalk) {
        cv::Point2d p = from + dir * t;
        // Most steps lie plainly on one side of the threshold (inside the pupil; before reaching
        // the dark): the cell answers and the sample is skipped. The result is the same as
        // sampling every step.
        const Side side = image.cells.side(p.x, p.y, threshold);
        if (side == Side::Below || (side == Side::AtOrAbove && !inside)) {
            if (side == Side::Below) {
                inside = true;
            } else if (t > 0.5 * maxDistance) {
                break;
            }
            prevKnown = false;
            continue;
        }
        double v = sampleAt(p.x, p.y);
        if (v < 0.0) break; // left the image
        if (!inside) {
            // Start counting once in the dark (the seed may sit on a glint).
            if (v < lv.threshold)
                inside = true;
            else if (t > 0.5 * maxDistance)
                break;
            prev = v;
            prevKnown = true;
            continue;
        }
        if (v >= lv.threshold) {
            // Which half of the last step crossed the threshold.
            const cv::Point2d half = from + dir * (t - kStep);
            if (const double m = sampleAt(half.x, half.y); m >= lv.threshold) {
                if (!prevKnown) {
                    const cv::Point2d last = from + dir * (t - kWalk);
                    prev = sampleAt(last.x, last.y);
                }
                t -= kStep;
                p = half;
                v = m;
            } else {
                prev = m;
            }
            if (const double back = glintIsland(image, p, dir, v, maxDistance, lv); back > 0.0) {
                t += back - kWalk;
                prev = lv.threshold - 1.0;
                prevKnown = true;
                continue;
            }
            keepEdge(image, from, dir, t, prev, v, lv, irisOnly);
            return;
        }
        prev = v;
        prevKnown = true;
    }
}

void EdgeRays::keepEdge(const RayImage& image, cv::Point2d from, cv::Point2d dir, double t,
                        double prev, double v, const RayLevels& lv, bool irisOnly) {
    const Bilinear sampleAt(image.smooth);
    const double u = (lv.threshold - prev) / std::max(1e-6, v - prev);
    const double tEdge = t - kStep + kStep * std::clamp(u, 0.0, 1.0);
    // Glint suppression: a glint at the crossing means the edge is (partly) the glint's, so the
    // point is dropped rather than trusted.
    bool glint = false;
    for (double s = -1.0; s <= 3.0 && !glint; s += 1.0)
        glint = isGlint(image.smooth, image.fullIntegral, from + dir * (tEdge + s), lv);
    // A pupil is ringed by its iris: an edge that opens onto something much brighter than the
    // iris (skin beyond lashes or a lid margin over the pupil, sclera beyond a dark iris) is not
    // the pupil's. The mean of 2-5 px beyond the crossing: one pixel's noise (a few grey levels
    // in the hard preset) must not decide it.
    double outside = 0.0;
    int nOutside = 0;
    for (double s = 2.0; s <= 5.0; s += 1.0) {
        const cv::Point2d beyond = from + dir * (tEdge + s);
        const double w = sampleAt(beyond.x, beyond.y);
        if (w >= 0.0) {
            outside += w;
            ++nOutside;
        }
    }
    outside = nOutside > 0 ? outside / nOutside : -1.0;
    const double range = lv.surround - lv.pupil;
    const bool tooBright = outside > lv.pupil + 1.8 * range && outside < lv.glint;
    // Second pass (the iris level is measured around the first fit): the iris must be what lies
    // beyond, not a lid margin or lashes darker than it, nor skin — an edge along the lid over
    // the pupil would make the fit hug the lid and put the centre below the pupil's.
    const bool notIris =
        irisOnly && outside < lv.glint &&
        (outside < lv.surround - 0.45 * range || outside > lv.surround + kSkinAboveIris * range);
    if (!glint && !tooBright && !notIris) {
        const cv::Point2d e = from + dir * tEdge;
        mPoints.push_back(e);
        mGradients.push_back(unitGradient(image.smooth, e));
    }
}

} // namespace gt::eyetrack::starburst
