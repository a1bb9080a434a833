#include "pupil/starburst_detector.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>

#include <opencv2/imgproc.hpp>

#include "error.hpp"
#include "pupil/bilinear.hpp"
#include "pupil/box_blur.hpp"
#include "pupil/ellipse_fit.hpp"
#include "pupil/limbus_fit.hpp"

namespace gt::eyetrack {

namespace {

// Second ray pass: an edge whose outside lies more than this share of the pupil-iris contrast
// above the iris level opens onto skin (a lid over the pupil), not the iris. 0.7 let the lower
// margin of a lid covering the pupil's top through (skin 0.4 of the contrast above the iris
// in the hard preset), and the fit hugged it with its centre ~5 px low — confidently, as the
// edge is crisp. eyescore on the dev seeds 1-100, 0.7 -> 0.25: hard 99.3 -> 99.6 % within
// 5 px, wrong answers rejected by the gate 93 -> 96 %; wild 91.6 -> 92.6 %.
constexpr double kSkinAboveIris = 0.25;

// A candidate at least this many times the smallest pupil radius is iris-sized: when it yields no
// fit, the pupil is looked for inside it. eyescore, development seeds, wild 1-150 / 151-300:
// 95.0 / 93.1 % -> 95.5 / 93.6 % within 5 px (2x: 95.4 / 93.3 %); hard unchanged.
constexpr double kIrisSized = 3.0;

inline double sample(const cv::Mat& img, double x, double y) {
    return Bilinear(img)(x, y);
}

// Sum over [x0, x1) x [y0, y1) from a CV_32S integral image.
inline long long boxSum(const cv::Mat& ii, int x0, int y0, int x1, int y1) {
    const int* a = ii.ptr<int>(y0);
    const int* b = ii.ptr<int>(y1);
    return static_cast<long long>(b[x1]) - b[x0] - a[x1] + a[x0];
}

// Centre-surround responses along row y of the image behind a CV_32S integral image: at column x,
// the mean of the ring between the (2 ho + 1)^2 and (2 hi + 1)^2 boxes minus the inner box's mean
// (dark centre: positive), both boxes clipped at the border; -inf when the clipped ring is no
// larger than the inner box. The row's clipping and pointers are set once: the searches call
// at() for every position and scale, the larger part of the detector's work.
class CentreSurroundRow {
public:
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

// Percentile of the grey levels in a rectangle (sparse sampling for large ones), optionally
// excluding an inner rectangle.
double percentile(const cv::Mat& img, cv::Rect outer, cv::Rect hole, double q) {
    outer &= cv::Rect(0, 0, img.cols, img.rows);
    std::array<int, 256> hist{};
    int count = 0;
    const int step = std::max(1, static_cast<int>(std::sqrt(outer.area() / 1500.0)));
    for (int y = outer.y; y < outer.y + outer.height; y += step) {
        const uchar* row = img.ptr<uchar>(y);
        for (int x = outer.x; x < outer.x + outer.width; x += step) {
            if (hole.contains({x, y})) continue;
            ++hist[row[x]];
            ++count;
        }
    }
    if (count == 0) return -1.0;
    const int target = static_cast<int>(q * (count - 1));
    int acc = 0;
    for (int v = 0; v < 256; ++v) {
        acc += hist[static_cast<std::size_t>(v)];
        if (acc > target) return v;
    }
    return 255.0;
}

// Calls fn(point, unit outward normal) at `count` evenly spaced parameter angles on an ellipse.
template <typename Fn> void forEachOutlinePoint(const cv::RotatedRect& e, int count, Fn&& fn) {
    const double th = e.angle * std::numbers::pi / 180.0;
    const cv::Point2d u(std::cos(th), std::sin(th)), v(-std::sin(th), std::cos(th));
    const double a = 0.5 * e.size.width, b = 0.5 * e.size.height;
    const cv::Point2d c(e.center.x, e.center.y);
    for (int k = 0; k < count; ++k) {
        const double phi = (k + 0.5) * 2.0 * std::numbers::pi / count;
        const cv::Point2d n = u * (std::cos(phi) / a) + v * (std::sin(phi) / b);
        fn(c + u * (a * std::cos(phi)) + v * (b * std::sin(phi)), n * (1.0 / cv::norm(n)));
    }
}

// Direction of the image gradient at p by central differences (zero when flat or at the border).
cv::Point2d unitGradient(const cv::Mat& img, cv::Point2d p) {
    const double l = sample(img, p.x - 1.0, p.y), r = sample(img, p.x + 1.0, p.y);
    const double u = sample(img, p.x, p.y - 1.0), d = sample(img, p.x, p.y + 1.0);
    if (l < 0.0 || r < 0.0 || u < 0.0 || d < 0.0) return {0.0, 0.0};
    const cv::Point2d g(r - l, d - u);
    const double len = std::hypot(g.x, g.y);
    return len > 1.0 ? g * (1.0 / len) : cv::Point2d(0.0, 0.0);
}

double smoothstep(double lo, double hi, double x) {
    const double t = std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// Median grey level of the part of ellipse e's inside that lies outside `inner` (3 rings of 32
// samples; glints left out); -1 when fewer than 4 samples fall there.
double medianBeyond(const cv::Mat& grey, const cv::RotatedRect& e, const cv::RotatedRect& inner,
                    double glint) {
    const auto axes = [](const cv::RotatedRect& r) {
        const double th = r.angle * std::numbers::pi / 180.0;
        return std::pair{cv::Point2d(std::cos(th), std::sin(th)),
                         cv::Point2d(-std::sin(th), std::cos(th))};
    };
    const auto [u, v] = axes(e);
    const auto [ui, vi] = axes(inner);
    const double a = 0.5 * e.size.width, b = 0.5 * e.size.height;
    const double ai = 0.5 * inner.size.width, bi = 0.5 * inner.size.height;
    const cv::Point2d c(e.center.x, e.center.y), ci(inner.center.x, inner.center.y);
    constexpr int kPerRing = 32;
    std::array<double, 3 * kPerRing> values{};
    std::size_t n = 0;
    for (const double r : {0.3, 0.55, 0.8}) {
        for (int k = 0; k < kPerRing; ++k) {
            const double phi = (k + 0.5) * 2.0 * std::numbers::pi / kPerRing;
            const cv::Point2d q = c + u * (r * a * std::cos(phi)) + v * (r * b * std::sin(phi));
            const cv::Point2d d = q - ci;
            const double x = d.dot(ui) / ai, y = d.dot(vi) / bi;
            if (x * x + y * y <= 1.1) {
                continue; // inside `inner` or on its outline
            }
            const double g = sample(grey, q.x, q.y);
            if (g >= 0.0 && g < glint) {
                values[n++] = g;
            }
        }
    }
    if (n < 4) {
        return -1.0;
    }
    const auto mid = values.begin() + static_cast<std::ptrdiff_t>(n / 2);
    std::nth_element(values.begin(), mid, values.begin() + static_cast<std::ptrdiff_t>(n));
    return *mid;
}

// The sensor noise's standard deviation, from the median absolute difference between the image
// and its 3x3 box mean (every other row): edges and texture are a small share of the pixels, so
// the median sees the noise alone. For white noise of sigma s the difference has sigma
// s * sqrt(8/9), and a normal variable's median absolute value is 0.6745 of its sigma.
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

// The running means of the detector's priors: a tenth of each new value, or the value itself when
// nothing was known (`known` false).
void learn(double& mean, double value, bool known) {
    mean = known ? 0.9 * mean + 0.1 * value : value;
}

cv::Rect boxAround(cv::Point2d c, double half) {
    const int h = std::max(1, static_cast<int>(std::lround(half)));
    return {static_cast<int>(std::lround(c.x)) - h, static_cast<int>(std::lround(c.y)) - h,
            2 * h + 1, 2 * h + 1};
}

} // namespace

StarburstDetector::StarburstDetector(StarburstConfig config) : mConfig(config) {
    if (mConfig.rays < 8) throw EyetrackError("pupil detector: at least 8 rays are needed");
    if (mConfig.seedRays < 8 || mConfig.rays % mConfig.seedRays != 0) {
        throw EyetrackError("pupil detector: seedRays must be at least 8 and divide rays");
    }
    if (mConfig.candidates < 1) {
        throw EyetrackError("pupil detector: at least 1 candidate is needed");
    }
    if (mConfig.fallbackCandidates < 0) {
        throw EyetrackError("pupil detector: fallback candidates cannot be negative");
    }
    if (mConfig.fallbackClosing < 0.0) {
        throw EyetrackError("pupil detector: fallbackClosing must be 0 (off) or more");
    }
    if (mConfig.eyeRatioMargin < 0.0) {
        throw EyetrackError("pupil detector: the eye's axis-ratio margin cannot be negative");
    }
    const int n = mConfig.rays;
    mRayDirections.reserve(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const double a = (i + 0.5) * 2.0 * std::numbers::pi / n;
        mRayDirections.emplace_back(std::cos(a), std::sin(a));
    }
}

void StarburstDetector::findCandidates(const cv::Mat& grey, const cv::Mat& fullIntegral,
                                       double minR, double maxR, cv::Mat& small, cv::Mat& integral,
                                       std::vector<Candidate>& out, std::size_t limit) {
    // Downscale so the coarse image is ~60 rows: the search only needs a seed inside the pupil.
    const int f = std::max(1, std::min(grey.rows, grey.cols) / 60);
    mCoarseFactor = f;
    // The coarse image: the means of f x f blocks, rounded, read off the full-resolution
    // integral image (detect() builds it first, for the glint test) at a tenth of cv::resize's
    // cost. The same pixels as INTER_AREA's when f divides the image's size (320 x 240 and
    // 640 x 480 both); otherwise the right and bottom remainders are left out, and a coarse
    // pixel's centre stays exactly where findCandidates maps it back to.
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
    const int w = small.cols, h = small.rows;
    // The strongest responses, kept in a bounded min-heap (sorting every position would cost
    // more than the rest of the detector).
    constexpr std::size_t kKeep = 48;
    std::vector<Candidate>& all = mHeap;
    all.clear();
    const auto weaker = [](const Candidate& a, const Candidate& b) {
        return a.response > b.response;
    };
    for (double r = std::max(1.5, minR / f); r <= maxR / f + 1e-9; r *= 1.3) {
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
        const double minResponse = 0.5 * mConfig.minContrast;
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
    std::sort_heap(all.begin(), all.end(), weaker); // strongest first
    for (const Candidate& c : all) {
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

void StarburstDetector::findFallbackCandidates(const cv::Mat& grey, double minR, double maxR,
                                               std::size_t firstRound) {
    if (mConfig.fallbackClosing <= 0.0) {
        return; // the plain search's next blobs are already there
    }
    // Lashes hanging across a pupil's top are as dark as the pupil: together they are one
    // irregular blob, and the ring around its centre is part lash, so the search ranks it below
    // lash clusters on skin and blurred shadows (wild seed 178: the merged blob was the 20th,
    // centred 11 px above the pupil; the pupil was no blob of its own). Closing removes every dark
    // structure narrower than the square — lashes, eyeliner, the gaps of a lash cluster — and
    // leaves the pupil round and whole (the least pupil, 2 minRadius across, is wider than the
    // square). The first round keeps the plain image's blobs: there a pupil 15 grey levels darker
    // than its iris is a blob of its own (closed, wild seed 153 lost it to the iris, 54 -> 22 %),
    // and the closing is paid only in the frames that reach the fallback round (bench, hard:
    // 1255-1269 fps before, 1264-1265 after). eyescore, development seeds, wild 1-150 / 151-300,
    // side 1.8 (13 px): 96.22 / 94.63 -> 96.32 / 95.28 % within 5 px (seeds 178: 73 -> 92 %, 287,
    // 227, 205, 295 +18 to +12 frames; 71: -22, 217: -13); gate 0.6, wrong answers rejected 91.4
    // / 92.5 -> 91.4 / 92.4 %, right ones kept 96.5 / 95.4 -> 96.4 / 95.1 %; hard 1-100 /
    // 101-200 99.77 / 99.80 -> 99.76 / 99.80 %. Sides of 7 / 9 / 11 / 15 / 19 px: 94.93 / 95.09
    // / 95.13 / 95.25 / 94.98 % on 151-300. Every blob from the image closed with a 7 px
    // square: 96.34 / 94.53 %, the ROC area on 151-300 0.986 -> 0.978.
    const int side = 2 * static_cast<int>(0.5 * mConfig.fallbackClosing * minR) + 1;
    cv::morphologyEx(grey, mClosed, cv::MORPH_CLOSE,
                     cv::getStructuringElement(cv::MORPH_RECT, {side, side}));
    cv::integral(mClosed, mClosedIntegral, CV_32S);
    mCandidates.resize(firstRound);
    findCandidates(grey, mClosedIntegral, minR, maxR, mClosedSmall, mClosedSmallIntegral,
                   mCandidates, firstRound + static_cast<std::size_t>(mConfig.fallbackCandidates));
}

bool StarburstDetector::measureLevels(const cv::Mat& grey, const Candidate& c,
                                      Levels& levels) const {
    const cv::Rect none(0, 0, 0, 0);
    // The 30th percentile of the inner box: robust to glints and to a box that overlaps the iris.
    levels.pupil = percentile(grey, boxAround(c.centre, 0.6 * c.radius), none, 0.3);
    levels.surround = percentile(grey, boxAround(c.centre, 2.0 * c.radius),
                                 boxAround(c.centre, 1.3 * c.radius), 0.5);
    if (levels.pupil < 0.0 || levels.surround < 0.0) return false;
    if (levels.surround - levels.pupil < mConfig.minContrast) return false;
    // The ring may reach past the iris onto the sclera, so the first threshold sits low in the
    // range, a quarter of the way up; refine() re-measures the level just outside the fitted
    // ellipse and recasts. But the 30th percentile lies below a noisy pupil's mean, and a
    // quarter of the way up from it can lie within the pupil's own noise: rays then stopped
    // inside a pupil only 15-20 grey levels darker than its iris and no fit formed (wild seed
    // 30187: pupil 17, surround 37, threshold 23 against a pupil averaging 23). So the threshold
    // also clears the frame's noise (noiseSigma) three times over, up to half-way. eyescore,
    // fresh wild seeds 30001-30300 / 40001-40300: 96.15 -> 96.71 % within 5 px; wild development
    // seeds 1-150 / 151-300 97.29 / 96.15 -> 97.67 / 96.77 %; hard 1-100 / 101-200 99.89 / 99.90
    // -> 99.85 / 99.90 %. Half-way always: 96.90 % on the fresh seeds, but bench --suite eye's
    // hard clip 1,390-1,480 -> 980-1,090 fps (rays ran past a pupil into the iris, and RANSAC's
    // adaptive stop came later); with the noise 1,290-1,450 fps. The inner box's spread (70th
    // less 30th percentile) in place of the noise: 96.74 %, but a lid across the box counted as
    // noise (wild seed 214, a pupil never seen whole: 86 -> 56 %; with the noise 72 %).
    const double span = levels.surround - levels.pupil;
    levels.threshold = levels.pupil + std::max({0.5 * mConfig.minContrast, 0.25 * span,
                                                std::min(0.5 * span, 3.0 * mNoise)});
    levels.glint =
        std::max(levels.surround + 30.0, levels.surround + 0.5 * (255.0 - levels.surround));
    return true;
}

void StarburstDetector::castRays(const cv::Mat& grey, const BilinearRange& cells, cv::Point2d from,
                                 double maxDistance, const Levels& lv, bool irisOnly, int stride) {
    mEdgePoints.clear();
    mEdgeGradients.clear();
    // Rays walk in whole pixels and look back half a pixel at the crossing, so the edge is
    // found at half-pixel resolution for half the samples (the walk is most of the detector's
    // time). On the 3x3-smoothed image, a crossing that the whole-pixel walk steps over (one
    // that crosses back within the same pixel) needs a feature barely above the threshold for
    // less than a pixel: noise, which the island test below would skip anyway.
    constexpr double kStep = 0.5;
    constexpr double kWalk = 1.0;
    const Bilinear sampleAt(grey);
    using Side = BilinearRange::Side;
    const BilinearRange::Level threshold = BilinearRange::level(lv.threshold);
    for (std::size_t ray = 0; ray < mRayDirections.size();
         ray += static_cast<std::size_t>(stride)) {
        const cv::Point2d dir = mRayDirections[ray];
        bool inside = false;
        // The last step's grey level; after a step that its cell decided, it is sampled only
        // if the crossing needs it (prevKnown false). Steps are multiples of half a pixel, so
        // t - kWalk is that step's t exactly.
        double prev = -1.0;
        bool prevKnown = true;
        for (double t = 0.0; t <= maxDistance; t += kWalk) {
            cv::Point2d p = from + dir * t;
            // Most steps lie plainly on one side of the threshold (inside the pupil; before
            // reaching the dark): the cell answers and the sample is skipped. The result is the
            // same as sampling every step.
            const Side side = cells.side(p.x, p.y, threshold);
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
                // A bright island that ends within a few pixels is a glint or noise inside the
                // pupil: step over it and keep looking for the real boundary.
                const double island = std::max(4.0, 0.25 * maxDistance);
                // Only a glint (a spot brighter than its neighbourhood) counts as an island: dark
                // lashes just outside the pupil must not make the real boundary look like one.
                double back = -1.0, peak = v, peakAt = 0.0;
                // Past a pupil's real edge nothing is dark again within the island's reach, and
                // the cells show it: the samples (and the peak, used only for an island) are
                // needed only when some cell reaches below the threshold.
                bool darkAgain = false;
                for (double s = 1.0; s <= island; s += kStep) {
                    const Side ahead = cells.side(p.x + dir.x * s, p.y + dir.y * s, threshold);
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
                if (back > 0.0 && isGlint(grey, p + dir * peakAt, lv)) {
                    t += back - kWalk;
                    prev = lv.threshold - 1.0;
                    prevKnown = true;
                    continue;
                }
                const double u = (lv.threshold - prev) / std::max(1e-6, v - prev);
                const double tEdge = t - kStep + kStep * std::clamp(u, 0.0, 1.0);
                // Glint suppression: a glint at the crossing means the edge is (partly) the
                // glint's, so the point is dropped rather than trusted.
                bool glint = false;
                for (double s = -1.0; s <= 3.0 && !glint; s += 1.0)
                    glint = isGlint(grey, from + dir * (tEdge + s), lv);
                // A pupil is ringed by its iris: an edge that opens onto something much brighter
                // than the iris (skin beyond lashes or a lid margin over the pupil, sclera beyond
                // a dark iris) is not the pupil's.
                // The mean of 2-5 px beyond the crossing: one pixel's noise (a few grey
                // levels in the hard preset) must not decide it.
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
                // Second pass (the iris level is measured around the first fit): the iris must
                // be what lies beyond, not a lid margin or lashes darker than it, nor skin — an
                // edge along the lid over the pupil would make the fit hug the lid and put the
                // centre below the pupil's.
                const bool notIris = irisOnly && outside < lv.glint &&
                                     (outside < lv.surround - 0.45 * range ||
                                      outside > lv.surround + kSkinAboveIris * range);
                if (!glint && !tooBright && !notIris) {
                    const cv::Point2d e = from + dir * tEdge;
                    mEdgePoints.push_back(e);
                    mEdgeGradients.push_back(unitGradient(grey, e));
                }
                break;
            }
            prev = v;
            prevKnown = true;
        }
    }
}

bool StarburstDetector::isGlint(const cv::Mat& grey, cv::Point2d p, const Levels& lv) const {
    // A glint is a small spot much brighter than its 9x9 neighbourhood (a top-hat test on the
    // integral image), or anything saturated; a plain pupil-iris edge is never more than a few
    // grey levels above its box mean.
    // Nearest pixel, halves away from zero as std::lround, which is a library call here and
    // this test runs five times at every ray's crossing (2 % of a frame's instructions).
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
        static_cast<double>(boxSum(mFullIntegral, x0, y0, x1, y1)) / ((x1 - x0) * (y1 - y0));
    return v - mean > std::max(25.0, 0.3 * (lv.surround - lv.pupil));
}

double StarburstDetector::outsideLevel(const cv::Mat& grey, const cv::RotatedRect& e,
                                       const Levels& lv) const {
    // Median grey level a few pixels outside the ellipse, glints excluded: the iris next to the
    // pupil, whatever lies further out.
    constexpr int kSamples = 48;
    const double d = std::max(2.5, 0.1 * std::min(e.size.width, e.size.height));
    std::vector<double> values;
    values.reserve(kSamples);
    forEachOutlinePoint(e, kSamples, [&](cv::Point2d p, cv::Point2d n) {
        const double out = sample(grey, p.x + d * n.x, p.y + d * n.y);
        if (out >= 0.0 && out < lv.glint) values.push_back(out);
    });
    if (values.size() < kSamples / 4) return -1.0;
    std::nth_element(values.begin(),
                     values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
    return values[values.size() / 2];
}

// The far end of the sharpness test's wide band outside an outline point p (unit normal n): the
// grey level `wide` px out, or the last level before the profile rises past 3x the edge's own
// step (in -> out) — a second edge. A pupil whose iris is a thin ring (a large pupil, a dark
// iris seen close) has the iris/sclera boundary within 0.3 of its minor axis; the wide step then
// measured the sclera and called the crisp pupil edge a shadow's (wild seed 279: the right fit
// scored sharpness 0 and the iris was picked in 42 % of its frames). A shadow's or a smudge's
// ramp keeps rising about as fast as within the edge, so it reaches 3x only past the band.
// -1 when the band leaves the image; a glint at its far end: `out` (the band ends at the edge).
double StarburstDetector::wideOutside(const cv::Mat& grey, cv::Point2d p, cv::Point2d n, double d,
                                      double wide, double in, double out, const Levels& lv) {
    const double far = sample(grey, p.x + wide * n.x, p.y + wide * n.y);
    if (far < 0.0) {
        return -1.0;
    }
    const double secondEdge = in + 3.0 * (out - in);
    double last = out;
    for (double t = d + 1.0; t <= wide; t += 1.0) {
        const double w = sample(grey, p.x + t * n.x, p.y + t * n.y);
        if (w < 0.0 || w >= lv.glint || w > secondEdge) {
            break;
        }
        last = w;
    }
    return far >= lv.glint ? out : std::max(out, std::min(far, last));
}

StarburstDetector::Support StarburstDetector::outlineSupport(const cv::Mat& grey,
                                                             const cv::RotatedRect& e,
                                                             const Levels& lv) const {
    constexpr int kSamples = 48;
    const double minor = std::min(e.size.width, e.size.height);
    const double d = std::max(1.5, 0.06 * minor);
    // Sharpness: the step across d against the step across a wider band. A pupil's edge is a
    // step blurred by the optics (~0.6 or more of the wide step within 1.5 px); a shadow on the
    // skin or a make-up smudge is blurred over many pixels (~0.3).
    const double wide = std::max(d + 2.5, 0.3 * minor);
    const double need = 0.3 * (lv.surround - lv.pupil);
    int supported = 0, counted = 0, covered = 0;
    std::array<double, kSamples> ratios{};
    int nRatios = 0;
    forEachOutlinePoint(e, kSamples, [&](cv::Point2d p, cv::Point2d n) {
        const double in = sample(grey, p.x - d * n.x, p.y - d * n.y);
        const double out = sample(grey, p.x + d * n.x, p.y + d * n.y);
        if (in < 0.0 || out < 0.0) {
            ++counted; // outside the image: unsupported
            return;
        }
        if (out >= lv.glint) return; // a glint on the boundary: neither for nor against
        ++counted;
        if (out - in > need && in < lv.threshold) {
            ++supported;
            const double wideIn = sample(grey, p.x - wide * n.x, p.y - wide * n.y);
            const double wideOut = wideOutside(grey, p, n, d, wide, in, out, lv);
            if (wideIn >= 0.0 && wideOut >= 0.0) {
                ratios[static_cast<std::size_t>(nRatios++)] =
                    (out - in) / std::max(out - in, wideOut - wideIn);
            }
        } else if (in >= lv.threshold && out >= lv.threshold) {
            ++covered;
        }
    });
    Support s;
    if (nRatios > 0) {
        auto mid = ratios.begin() + nRatios / 2;
        std::nth_element(ratios.begin(), mid, ratios.begin() + nRatios);
        s.sharpness = *mid;
    }
    if (counted > 0) s.all = static_cast<double>(supported) / counted;
    // At least half the outline must be in view to be judged on the visible part alone.
    const int visible = counted - covered;
    s.visible =
        2 * visible >= counted && visible > 0 ? static_cast<double>(supported) / visible : s.all;
    return s;
}

// The lid test: a straight run of at least 8 edge points within 1 px of one line, spanning 1.4
// semi-minor axes or more (a pupil's own arc that long bends 3 px or more away from its chord),
// within 30 deg of the image's horizontal and not through the ellipse's middle. Its points are
// dropped and the rest refitted; the refit counts only if its outline reaches at least 1 px
// beyond the line (the hidden arc) with its centre on the pupil's side. eyescore, dev seeds
// 1-100: hard 99.6 -> 99.7 %, wild 92.6 -> 93.3 %; held-out sets: hard 99.0-99.7 -> 99.7-99.8 %,
// the gate rejecting 85-98 -> 97-99 % of wrong answers (set B 85 -> 97).
std::optional<EllipseFit> StarburstDetector::fitBesideLid(const cv::RotatedRect& e,
                                                          const RansacEllipseParams& rp) {
    const std::size_t n = mEdgePoints.size();
    if (n < 20) {
        return std::nullopt;
    }
    const double semiMinor = 0.5 * std::min(e.size.width, e.size.height);
    const cv::Point2d centre(e.center.x, e.center.y);
    // Rays are cast in angle order, so a lid's points are neighbours: try the line through
    // every point and the one a few rays on, and follow it both ways while at most two points in
    // a row stray from it.
    constexpr std::size_t kStep = 6;
    constexpr int kMaxMisses = 2;
    std::vector<int> best;
    cv::Point2d bestNormal;
    double bestOffset = 0.0;
    std::vector<int> in;
    const int count = static_cast<int>(n);
    for (std::size_t i = 0; i < n; ++i) {
        const cv::Point2d a = mEdgePoints[i], b = mEdgePoints[(i + kStep) % n];
        cv::Point2d dir = b - a;
        const double len = cv::norm(dir);
        if (len < 4.0) {
            continue;
        }
        dir *= 1.0 / len;
        if (std::abs(dir.y) > 0.5) {
            continue; // a lid runs roughly across the image
        }
        const cv::Point2d normal(-dir.y, dir.x);
        const double offset = normal.dot(a);
        const double centreSide = normal.dot(centre) - offset;
        if (std::abs(centreSide) < 0.3 * semiMinor) {
            continue; // a chord through the middle
        }
        in.clear();
        double lo = 1e9, hi = -1e9;
        auto follow = [&](int from, int step) {
            int misses = 0;
            for (int k = 0; k < count && misses <= kMaxMisses; ++k) {
                const int j = ((from + step * k) % count + count) % count;
                const cv::Point2d q = mEdgePoints[static_cast<std::size_t>(j)];
                if (std::abs(normal.dot(q) - offset) > 1.0) {
                    ++misses;
                    continue;
                }
                misses = 0;
                in.push_back(j);
                const double t = dir.dot(q);
                lo = std::min(lo, t);
                hi = std::max(hi, t);
            }
        };
        follow(static_cast<int>(i), 1);
        follow(static_cast<int>(i) - 1, -1);
        if (in.size() >= 8 && in.size() < n && hi - lo >= 1.4 * semiMinor &&
            in.size() > best.size()) {
            best = in;
            bestNormal = centreSide > 0.0 ? normal : -normal; // towards the pupil's centre
            bestOffset = centreSide > 0.0 ? offset : -offset;
        }
    }
    if (best.empty()) {
        return std::nullopt;
    }
    std::sort(best.begin(), best.end());
    best.erase(std::unique(best.begin(), best.end()), best.end());
    std::vector<cv::Point2d> points, gradients;
    for (std::size_t j = 0, k = 0; j < n; ++j) {
        if (k < best.size() && best[k] == static_cast<int>(j)) {
            ++k;
            continue;
        }
        points.push_back(mEdgePoints[j]);
        gradients.push_back(mEdgeGradients[j]);
    }
    if (points.size() < 12) {
        return std::nullopt;
    }
    // What is left is mostly the pupil's own outline: fewer RANSAC draws find it.
    RansacEllipseParams rest = rp;
    rest.iterations = std::max(20, rp.iterations / 3);
    auto fit = fitEllipseRansac(points, rest, gradients);
    if (!fit) {
        return std::nullopt;
    }
    // The pupil's hidden arc lies beyond the lid: the new outline must cross the line, and its
    // centre stay on the pupil's side.
    const cv::RotatedRect& f = fit->ellipse;
    const cv::Point2d fc(f.center.x, f.center.y);
    if (bestNormal.dot(fc) - bestOffset <= 0.0) {
        return std::nullopt;
    }
    double reach = 1e9;
    for (int k = 0; k < 36; ++k) {
        const double t = k * std::numbers::pi / 18.0, th = f.angle * std::numbers::pi / 180.0;
        const cv::Point2d q(f.center.x + 0.5 * f.size.width * std::cos(t) * std::cos(th) -
                                0.5 * f.size.height * std::sin(t) * std::sin(th),
                            f.center.y + 0.5 * f.size.width * std::cos(t) * std::sin(th) +
                                0.5 * f.size.height * std::sin(t) * std::cos(th));
        reach = std::min(reach, bestNormal.dot(q) - bestOffset);
    }
    if (reach > -1.0) {
        return std::nullopt;
    }
    return fit;
}

std::optional<EllipseFit> StarburstDetector::fitAtRecentSize(const cv::Mat& grey,
                                                             const EllipseFit& fit,
                                                             const RansacEllipseParams& rp,
                                                             const Levels& lv) const {
    // Lashes hanging across the pupil's top are as dark as the pupil: rays run on through them
    // and stop at their far side, and the fit grows over them, its centre high (wild seed 1: a
    // 25 px pupil fitted with semi-major axes of 31-37 px, 86 % of frames within 5 px). When a fit
    // is clearly larger than the pupil has lately been, the same edge points are fitted again
    // within the recent size; that fit is taken when it keeps most of the inliers and its
    // outline is about as well supported — a dilating pupil's larger fit is supported all round,
    // a smaller ellipse inside it is not (wild seed 48, a pupil growing from 34 to 45 px while
    // half under the lid, where the prior lags).
    // eyescore, development seeds, wild 1-150 / 151-300: 95.57 / 93.69 -> 95.73 / 93.81 % within
    // 5 px (seed 1: 85.8 -> 94.1 %); ROC area 0.9725 / 0.9732 -> 0.9713 / 0.9725; gate 0.7,
    // wrong rejected 88.5 / 89.7 -> 88.9 / 89.8 %, right kept 93.1 / 92.7 -> 92.9 / 92.5 %;
    // hard 1-100 / 101-200: 99.77 / 99.77 -> 99.76 / 99.75 %. Without the support test: wild
    // 95.41 / 93.54 % (the lagging prior shrank growing pupils).
    constexpr double kOversize = 1.15;     // fit semi-major over the recent radius
    constexpr double kSizedMax = 1.1;      // the refit's largest semi-axis, over the recent radius
    constexpr double kKeptInliers = 0.6;   // of the larger fit's
    constexpr double kSupportMargin = 0.1; // visible support it may lose
    if (mRecentRadius <= 0.0) {
        return std::nullopt;
    }
    const double semiMajor = 0.5 * std::max(fit.ellipse.size.width, fit.ellipse.size.height);
    if (semiMajor <= kOversize * mRecentRadius) {
        return std::nullopt;
    }
    RansacEllipseParams sized = rp;
    sized.maxAxis = 2.0 * kSizedMax * mRecentRadius;
    sized.seed += 7;
    auto smaller = fitEllipseRansac(mEdgePoints, sized, mEdgeGradients);
    if (!smaller || static_cast<double>(smaller->inliers.size()) <
                        kKeptInliers * static_cast<double>(fit.inliers.size())) {
        return std::nullopt;
    }
    const double larger = outlineSupport(grey, fit.ellipse, lv).visible;
    if (outlineSupport(grey, smaller->ellipse, lv).visible < larger - kSupportMargin) {
        return std::nullopt;
    }
    return smaller;
}

std::optional<EllipseFit> StarburstDetector::fitUnderLid(const cv::Mat& grey, const EllipseFit& fit,
                                                         const RansacEllipseParams& rp,
                                                         const Levels& lv) const {
    // A lid over the pupil's top whose margin is lined with lashes or eyeliner gives edge points
    // that pass as the pupil's along a curve the lid-line test (fitBesideLid) does not take for
    // a line; the fit then hugs the lid: as wide as the pupil, but its minor axis 0.5-0.8 of
    // the pupil's and its centre 5-20 px low — the largest class of near misses on wild, where
    // 2/3 of the pupils in them were 50-80 % visible. When a fit about the recent pupil's size
    // is much narrower than the recent pupil, the edge points are fitted again with the minor
    // axis held near the recent one; that fit is taken when it keeps most of the inliers, its
    // visible outline is about as well supported, and what it adds to the narrow fit is under
    // something brighter than the iris (the lid): an eye turned away from the camera narrows
    // its pupil too, but there the wider ellipse reaches into the iris (wild seed 12, a saccade
    // to a pupil of axis ratio 0.63: 22 frames lost without that test, 1 with it).
    // eyescore, development seeds, wild 1-150 / 151-300: 95.78 / 93.86 -> 95.89 / 94.05 % within
    // 5 px (seeds 287: 76.7 -> 89.9 %, 113: 82.7 -> 98.6 %); gate 0.58, wrong rejected 90.4 /
    // 92.3 -> 90.8 / 92.3 %, right kept 96.0 / 95.1 -> 96.0 / 95.2 %.
    constexpr double kNarrow = 0.8;      // fit minor semi-axis over the recent one
    constexpr double kSameSize = 1.2;    // fit semi-major within this factor of the recent
    constexpr double kMinorFloor = 0.9;  // the refit's least minor semi-axis, over the recent
    constexpr double kLarger = 1.15;     // the refit's largest semi-axis, over the recent radius
    constexpr double kKeptInliers = 0.6; // of the narrow fit's
    if (mRecentRadius <= 0.0 || mRecentMinor <= 0.0) {
        return std::nullopt;
    }
    const double semiMajor = 0.5 * std::max(fit.ellipse.size.width, fit.ellipse.size.height);
    const double semiMinor = 0.5 * std::min(fit.ellipse.size.width, fit.ellipse.size.height);
    if (semiMinor >= kNarrow * mRecentMinor ||
        std::abs(std::log(semiMajor / mRecentRadius)) > std::log(kSameSize)) {
        return std::nullopt;
    }
    RansacEllipseParams wider = rp;
    wider.minAxis = 2.0 * kMinorFloor * mRecentMinor;
    wider.maxAxis = std::max(wider.minAxis + 1.0, 2.0 * kLarger * mRecentRadius);
    wider.seed += 11;
    auto fuller = fitEllipseRansac(mEdgePoints, wider, mEdgeGradients);
    if (!fuller || !addsOnlyLid(grey, *fuller, fit, lv, kKeptInliers)) {
        return std::nullopt;
    }
    return fuller;
}

bool StarburstDetector::addsOnlyLid(const cv::Mat& grey, const EllipseFit& larger,
                                    const EllipseFit& fit, const Levels& lv,
                                    double keptInliers) const {
    constexpr double kSupportMargin = 0.1; // visible support it may lose
    if (static_cast<double>(larger.inliers.size()) <
        keptInliers * static_cast<double>(fit.inliers.size())) {
        return false;
    }
    if (outlineSupport(grey, larger.ellipse, lv).visible <
        outlineSupport(grey, fit.ellipse, lv).visible - kSupportMargin) {
        return false;
    }
    const double added = medianBeyond(grey, larger.ellipse, fit.ellipse, lv.glint);
    return added >= lv.surround + kSkinAboveIris * (lv.surround - lv.pupil);
}

std::optional<EllipseFit> StarburstDetector::fitRounderUnderLid(const cv::Mat& grey,
                                                                const EllipseFit& fit,
                                                                const RansacEllipseParams& rp,
                                                                const Levels& lv) const {
    // fitUnderLid needs the recent pupil's size, which an eye whose pupil is never seen whole
    // (the upper lid always over its top) never teaches: there the fit keeps hugging the lid,
    // as wide as the pupil but flat, its centre low (wild seed 164, a pupil of axis ratio 0.68
    // half under the lid fitted at 0.46, 17 px low). Two things are known without the prior:
    // the edges along a lid over the pupil's top face up (dark below, skin above), and a pupil
    // seen by a head-mounted camera is seldom flatter than 0.7 (in wild, 0.75 or rounder in 94 %
    // of frames; the eye's own ratio, once learnt, raises the bound). So a flatter fit is redone
    // from the edge points that do not face up, held at least that round and about as wide; it is
    // taken when it keeps half the inliers, moves up under the lid, keeps its visible outline about
    // as well supported, and what it adds to the flat fit is brighter than the iris (the lid: a
    // pupil flattened by the eye turning away would add iris).
    // eyescore, development seeds, wild 1-150 / 151-300: 96.51 / 95.33 to 96.55 / 95.59 %
    // within 5 px (seeds 214: +29 frames, 165: +18, 126: +13, 159: +12; worst 55: -5); the
    // gate at 0.6 rejecting 91.1 / 92.3 to 90.8 / 92.4 % of wrong answers, keeping 96.4 / 95.0 %
    // of right ones; hard 1-100 / 101-200 99.75 / 99.80 to 99.77 / 99.81 %. With the edges at
    // y < -0.5 left out instead: bound 0.7 96.53 / 95.59 %, 0.65 96.54 / 95.46 %. On fourteen
    // of the seeds (164, 210, 298, ...; 75.3 % before), with y < -0.3: bounds 0.6 / 0.7 / 0.8
    // 75.7 / 76.1 / 75.4 %; with 0.7, every edge facing up at all (y < 0) left out: 75.9 %.
    constexpr double kRoundest = 0.7;    // the refit's least axis ratio (minor over major)
    constexpr double kEyeMargin = 0.1;   // or the eye's learnt ratio less this, if higher
    constexpr double kFacingUp = -0.7;   // edge points whose gradient's y is below are left out
    constexpr double kWider = 1.25;      // the refit's largest semi-axis, over the fit's
    constexpr double kKeptInliers = 0.5; // of the flat fit's
    const double semiMajor = 0.5 * std::max(fit.ellipse.size.width, fit.ellipse.size.height);
    const double semiMinor = 0.5 * std::min(fit.ellipse.size.width, fit.ellipse.size.height);
    const double ratio = std::max(kRoundest, mEyeRatio > 0.0 ? mEyeRatio - kEyeMargin : 0.0);
    if (semiMinor >= ratio * semiMajor) {
        return std::nullopt;
    }
    std::vector<cv::Point2d> points, gradients;
    for (std::size_t i = 0; i < mEdgePoints.size(); ++i) {
        if (mEdgeGradients[i].y >= kFacingUp) {
            points.push_back(mEdgePoints[i]);
            gradients.push_back(mEdgeGradients[i]);
        }
    }
    if (points.size() < 12) {
        return std::nullopt;
    }
    RansacEllipseParams rounder = rp;
    rounder.minAxisRatio = ratio;
    rounder.minAxis = 2.0 * std::max(0.5 * semiMajor, 1.1 * semiMinor);
    rounder.maxAxis = 2.0 * kWider * semiMajor;
    rounder.seed += 13;
    // Half the draws: the refit runs for every flat candidate, most of them no pupil under a lid,
    // and fails after all its draws when no round ellipse explains them (the full 150 cost 5 %
    // of the clean preset's instructions a frame, half 3 %; development seeds, wild 1-150 /
    // 151-300: 96.55 / 95.59 -> 96.56 / 95.59 % within 5 px).
    rounder.iterations = std::max(20, rp.iterations / 2);
    auto refit = fitEllipseRansac(points, rounder, gradients);
    // It must move towards the lid over the top.
    if (!refit || refit->ellipse.center.y >= fit.ellipse.center.y ||
        !addsOnlyLid(grey, *refit, fit, lv, kKeptInliers)) {
        return std::nullopt;
    }
    return refit;
}

std::optional<EllipseFit> StarburstDetector::fitWithLimbus(const cv::Mat& grey,
                                                           const EllipseFit& fit,
                                                           const Levels& lv) const {
    // A pupil under the upper lid whose visible arc leaves its height open (the refits above
    // need a size learnt from the whole pupil, or a lid whose edges face up, and on some eyes
    // have neither): the iris around it fixes it (limbus_fit.hpp). Wild development seeds: the
    // fits 5-20 px off with the centre low were 43 % of the misses, and half of all misses were
    // on pupils 50-70 % visible (84 % of those frames found within 5 px, 99 % of the pupils seen
    // nine-tenths whole). A fit flatter than 0.85 is refitted; the concentric fit is taken when
    // most of the visible arc's points and half the limbus points lie on it, the limbus points
    // span 100 deg or more (bunched on one side they leave the shape open), it moves the centre up
    // (towards the lid), makes the pupil rounder by 0.1 or more (a smaller change is within the
    // noise of the limbus's own shape: refitting every fit flatter than 0.85 moved right answers
    // on eyes seen from a steep angle, seed 296 95.5 -> 62.9 %) and adds nothing darker than the
    // iris (below). eyescore, development seeds, wild 1-150 / 151-300: 96.56 / 95.59 -> 96.84 /
    // 95.76 % within 5 px (seeds 87: 52.6 -> 89.1 %, 123: 33.0 -> 48.5 %, 288: 94.0 -> 99.3 %,
    // 55: 90.0 -> 95.4 %; worst 152: -4 frames); gate 0.6 rejecting 90.9 / 92.4 -> 91.4 / 92.8 %
    // of wrong answers, keeping 96.4 / 95.0 -> 96.3 / 95.2 % of right ones; hard 1-100 / 101-200
    // 99.77 / 99.81 -> 99.82 / 99.84 %. The limbus alone was not tried: its own arc is cut by the
    // same lid. Refitting only fits the refits above left alone lost seed 296 all the same.
    constexpr double kFlat = 0.85;         // fits flatter than this are refitted
    constexpr double kFacingUp = -0.7;     // pupil edge points with gradient y below: the lid's
    constexpr double kOnFit = 1.5;         // px from the fit: a point of the visible arc
    constexpr double kKeptPupil = 0.6;     // of the arc's points, on the concentric fit
    constexpr double kKeptLimbus = 0.5;    // of the limbus points, on it
    constexpr int kLeastPoints = 8;        // on each ellipse
    constexpr double kLeastSpread = 100.0; // deg spanned by the limbus points on the fit
    constexpr double kRounder = 0.1;       // the least gain in axis ratio
    constexpr double kLeastRatio = 0.6;    // the concentric fit's least axis ratio
    // Fits whose visible outline is less supported seldom win, and the search and the fit cost
    // (bench, hard preset, before the search and fit were made cheaper: 1216 fps without the
    // refit, 1062 refitting every flat fit, 1067 from this support up, 1108 from 0.7, which
    // found 30 frames fewer on the twelve wild development seeds that gain most).
    constexpr double kLeastSupport = 0.6;
    const cv::RotatedRect& e = fit.ellipse;
    const double major = 0.5 * std::max(e.size.width, e.size.height);
    const double minor = 0.5 * std::min(e.size.width, e.size.height);
    if (minor >= kFlat * major) {
        return std::nullopt;
    }
    if (outlineSupport(grey, e, lv).visible < kLeastSupport) {
        return std::nullopt;
    }
    // The visible arc: edge points on the fit whose gradient points out of it and not up.
    const double th = e.angle * std::numbers::pi / 180.0, ct = std::cos(th), st = std::sin(th);
    const double ea = 0.5 * e.size.width, eb = 0.5 * e.size.height;
    std::vector<cv::Point2d> arc;
    for (std::size_t i = 0; i < mEdgePoints.size(); ++i) {
        const cv::Point2d q = mEdgePoints[i], g = mEdgeGradients[i];
        if (g.y < kFacingUp) {
            continue;
        }
        const double dx = q.x - e.center.x, dy = q.y - e.center.y;
        const double u = dx * ct + dy * st, w = -dx * st + dy * ct;
        const double rho = std::sqrt(u * u / (ea * ea) + w * w / (eb * eb));
        const double len = std::sqrt(u * u + w * w);
        // On the fit, and its gradient pointing out of it.
        if (rho > 1e-9 && std::abs(len * (1.0 - 1.0 / rho)) <= kOnFit &&
            g.x * dx + g.y * dy >= 0.5 * len) {
            arc.push_back(q);
        }
    }
    if (arc.size() < static_cast<std::size_t>(kLeastPoints)) {
        return std::nullopt;
    }
    LimbusSearch search;
    search.irisLevel = lv.surround;
    search.glintLevel = lv.glint;
    std::vector<cv::Point2d> limbus;
    findLimbusPoints(mSmooth, e, search, limbus);
    if (limbus.size() < static_cast<std::size_t>(kLeastPoints)) {
        return std::nullopt;
    }
    const auto placed = fitConcentric(arc, limbus, e, kLeastRatio);
    if (!placed || placed->pupilInliers < std::max<double>(kLeastPoints, kKeptPupil * arc.size()) ||
        placed->limbusInliers < std::max<double>(kLeastPoints, kKeptLimbus * limbus.size()) ||
        placed->limbusSpreadDeg < kLeastSpread) {
        return std::nullopt;
    }
    const cv::RotatedRect& p = placed->pupil;
    const double ratio = std::min(p.size.width, p.size.height) /
                         std::max(1e-6F, std::max(p.size.width, p.size.height));
    if (p.center.y >= e.center.y - 0.5 || ratio - minor / major < kRounder) {
        return std::nullopt;
    }
    // What it adds must be no darker than the iris next to the pupil: a whole pupil seen from a
    // steep angle is flat too, and a limbus found a little rounder than it would lift its top
    // into the iris (wild seed 63: 85 % of its right answers kept by the gate, 90 % without the
    // refit and with this test). Not the refits' test above (brighter than the iris by a quarter
    // of the pupil's contrast): lashes along the lid darken what a pupil under it adds (seed
    // 87, 1560-1859 at the detector's threshold: 94.9 % within 5 px with no test, 87.6 % with
    // this one, 55 % with that). Development seeds without this test: 96.89 / 95.84 %.
    if (medianBeyond(grey, p, e, lv.glint) < lv.surround) {
        return std::nullopt;
    }
    EllipseFit out;
    out.ellipse = p;
    return out;
}

std::optional<EllipseFit> StarburstDetector::fitToEyeShape(const cv::Mat& grey,
                                                           const EllipseFit& fit,
                                                           const RansacEllipseParams& rp,
                                                           const Levels& lv) const {
    // What the refits above cannot place: an arc too short to fix an ellipse's five parameters,
    // where no lid line, learnt size or limbus gives the missing one, lets the fit flatten
    // against the lid with its centre low (wild seeds 36 and 189: pupils 0.9 and 0.56 visible
    // fitted at axis ratios 0.74 and 0.45 for 0.83 and 0.67, 6-9 px low). Where the pupil is
    // seen decides its shape (pupil_shape_model.hpp), so once the eye's whole pupils have taught
    // that, only the centre and the size are left to fit (fitEllipseOfShapeRansac): a fit whose
    // ratio is off the prediction by more than the model's scatter, or whose axis is turned away
    // from it, is refitted that way. The refit must keep most of the inliers and the visible
    // outline's support: a pupil that has not the shape the model expects (a model learnt from
    // few directions, refraction) keeps its own fit, as its points do not lie on the other.
    constexpr double kRatioBand = 0.08;  // axis ratio off the prediction by more: refitted
    constexpr double kAngleBand = 20.0;  // major axis turned from the predicted by more, deg
    constexpr double kRound = 0.92;      // both rounder: the axis's direction means nothing
    constexpr double kKeptInliers = 0.6; // of the fit's
    constexpr double kSupportMargin = 0.1;
    constexpr int kDraws = 60;
    constexpr double kSameRatio = 0.01; // a shape this close to the first needs no second refit
    constexpr double kSameAngle = 2.0;  // deg
    const cv::RotatedRect& e = fit.ellipse;
    const auto shape = mShape.predict({e.center.x, e.center.y});
    if (!shape) {
        return std::nullopt;
    }
    const PupilShape own = shapeOf(e);
    const bool round = shape->axisRatio > kRound && own.axisRatio > kRound;
    if (std::abs(own.axisRatio - shape->axisRatio) < kRatioBand &&
        (round || axisTurnDeg(own.majorAngleDeg, shape->majorAngleDeg) < kAngleBand)) {
        return std::nullopt;
    }
    RansacEllipseParams shaped = rp;
    shaped.seed += 19;
    // A draw of three points is all inliers far more often than one of five: 60 draws find as
    // many pupils on the development seeds as 150. The whole refit costs 1.4 % of the hard
    // preset's instructions and 3.6 % of the clean preset's over a whole clip (callgrind, seed 5,
    // 1,860 frames: the model is learnt during the calibration), nothing on hard's free viewing.
    shaped.iterations = kDraws;
    auto refit = fitEllipseOfShapeRansac(mEdgePoints, shape->axisRatio, shape->majorAngleDeg,
                                         shaped, mEdgeGradients);
    if (!refit) {
        return std::nullopt;
    }
    // The shape where the refit is, once more, when it differs there.
    const auto there = mShape.predict({refit->ellipse.center.x, refit->ellipse.center.y});
    if (there && (std::abs(there->axisRatio - shape->axisRatio) > kSameRatio ||
                  axisTurnDeg(there->majorAngleDeg, shape->majorAngleDeg) > kSameAngle)) {
        if (auto again = fitEllipseOfShapeRansac(mEdgePoints, there->axisRatio,
                                                 there->majorAngleDeg, shaped, mEdgeGradients)) {
            refit = again;
        }
    }
    if (static_cast<double>(refit->inliers.size()) <
            kKeptInliers * static_cast<double>(fit.inliers.size()) ||
        outlineSupport(grey, refit->ellipse, lv).visible <
            outlineSupport(grey, e, lv).visible - kSupportMargin) {
        return std::nullopt;
    }
    return refit;
}

StarburstDetector::Refined StarburstDetector::refine(const cv::Mat& grey, const Candidate& c,
                                                     double minR, double maxR,
                                                     double surroundHint) {
    Refined refined;
    PupilResult& result = refined.result;
    Levels lv;
    if (!measureLevels(grey, c, lv)) return refined;
    if (surroundHint > 0.0 && surroundHint < lv.surround) {
        // A pupil inside a dark iris: the ring around the seed reaches the sclera, but what
        // borders the pupil is the iris.
        lv.surround = surroundHint;
        if (lv.surround - lv.pupil < 0.5 * mConfig.minContrast) return refined;
        lv.threshold = 0.5 * (lv.pupil + lv.surround);
    }
    RansacEllipseParams rp;
    rp.iterations = mConfig.ransacIterations;
    rp.inlierDistance = mConfig.inlierDistance;
    rp.minAxis = 2.0 * minR * 0.7;
    rp.maxAxis = 2.0 * maxR * 1.3;
    rp.seed = mFrame * 7919u + 1u;

    castRays(mSmooth, mSmoothRange, c.centre, 2.5 * c.radius, lv, false,
             mConfig.rays / mConfig.seedRays);
    auto fit = fitEllipseRansac(mEdgePoints, rp, mEdgeGradients);
    if (!fit) return refined;
    // Candidates on the same blob (the last frame's pupil and the search's, a blob found at
    // two scales) reach the same first fit; what follows would only repeat that candidate's.
    // Not across a surround hint: a pupil in a dark iris, looked for with the iris's level,
    // can have the same first fit as the same blob found by the search without it, but the
    // hinted second pass thresholds at the iris's level and can find an outline the other
    // did not (once the fallback round below tries more blobs, more of them are repeats).
    // eyescore, development seeds, wild 1-150 / 151-300, with the fallback round: 96.15 /
    // 94.57 -> 96.17 / 94.61 % within 5 px.
    const cv::RotatedRect& first = fit->ellipse;
    const bool hinted = surroundHint > 0.0;
    const bool seen = std::any_of(mFirstFits.begin(), mFirstFits.end(), [&](const FirstFit& o) {
        const cv::RotatedRect& e = o.ellipse;
        return o.hinted == hinted &&
               std::hypot(e.center.x - first.center.x, e.center.y - first.center.y) < 1.0 &&
               std::abs(e.size.width - first.size.width) < 1.0 &&
               std::abs(e.size.height - first.size.height) < 1.0;
    });
    if (seen) {
        return refined;
    }
    mFirstFits.push_back({first, hinted});
    // Second pass from the fitted centre: rays now meet the boundary at even spacing.
    const cv::Point2d centre(fit->ellipse.center.x, fit->ellipse.center.y);
    const double major = 0.5 * std::max(fit->ellipse.size.width, fit->ellipse.size.height);
    bool irisMeasured = false;
    if (const double outside = outsideLevel(grey, fit->ellipse, lv);
        outside > lv.pupil + mConfig.minContrast) {
        lv.surround = outside;
        lv.threshold = 0.5 * (lv.pupil + outside);
        irisMeasured = true;
    }
    castRays(mSmooth, mSmoothRange, centre, 1.6 * major + 3.0, lv, irisMeasured);
    rp.seed += 1;
    if (auto second = fitEllipseRansac(mEdgePoints, rp, mEdgeGradients)) fit = second;
    // A lid over the pupil's top whose margin is lined with lashes as dark as the iris passes
    // the test above: its edge points would make the fit hug the lid, centre low.
    if (auto withoutLid = fitBesideLid(fit->ellipse, rp)) fit = withoutLid;
    // What the edge points chose before any pull towards the recent size: the confidence is
    // judged on it (below), so a fit held to the prior is not made surer by the prior.
    refined.fittedSemiMajor = 0.5 * std::max(fit->ellipse.size.width, fit->ellipse.size.height);
    if (auto sized = fitAtRecentSize(grey, *fit, rp, lv)) {
        fit = sized;
    } else if (auto fuller = fitUnderLid(grey, *fit, rp, lv)) {
        fit = fuller;
    } else if (auto rounder = fitRounderUnderLid(grey, *fit, rp, lv)) {
        fit = rounder;
    }
    if (auto shaped = fitToEyeShape(grey, *fit, rp, lv)) {
        fit = shaped;
    }
    if (auto placed = fitWithLimbus(grey, *fit, lv)) {
        fit = placed;
    }

    result.ellipse = fit->ellipse;
    const Support support = outlineSupport(grey, fit->ellipse, lv);
    const auto [fill, interior, interiorHigh] = interiorFill(grey, fit->ellipse, lv);
    // What makes a dark ellipse a pupil besides its outline: a crisp edge (not a shadow or a
    // smudge of make-up) and a filled dark inside (not a cluster of lashes with bright gaps).
    const double sharp = smoothstep(0.3, 0.55, support.sharpness);
    refined.quality = sharp * smoothstep(0.35, 0.75, fill);
    refined.interior = interior;
    refined.interiorHigh = interiorHigh;
    refined.outside = outsideLevel(grey, fit->ellipse, lv);
    // The visible outline's support in full, times the whole outline's to the power 1/4: a lid
    // over part of a well-fitted pupil still lowers the confidence, but less than the even
    // geometric mean did, which put 48-91 % of the right answers on pupils 50-80 % visible below
    // the gaze filter's gate. The inside's share of dark samples ramps over 0.3-0.7 (was
    // 0.5-0.85): the wrong answers that pass the gate are irises and slivers of a covered pupil,
    // dark throughout (median fill 0.98), while a right answer on a pupil whose top is under
    // the lid has lid skin in its upper samples (median 0.78 among those below the gate).
    // eyescore, development seeds, ROC area of the confidence, visible^3/4 and 0.5-0.85 ->
    // this: wild 1-150 0.9718 -> 0.9725, 151-300 0.9682 -> 0.9732, hard 1-100 0.9985 ->
    // 0.9995, 101-200 0.9989 -> 0.9998; right answers kept by the gate +0.3 / +1.1 / +0.4 /
    // +0.4 points, wrong ones rejected -0.4 / +0.5 / -0.3 / -1.1; detection within 0.05 points.
    result.confidence =
        std::pow(support.all, 0.25) * support.visible * sharp * smoothstep(0.3, 0.7, fill);
    // A plausible shape for the camera (StarburstConfig::flattestAxisRatio): the wrong answers
    // that passed the gate were mostly slivers, the visible part of a pupil under the lid fitted
    // as a flat ellipse (axis ratio 0.4-0.6; the pupils in view: 0.75 or rounder in 94 % of
    // frames). At first only the confidence: as a selection factor too it found 0.1-0.3 points
    // more pupils but let more confident slivers and specks through (its square root is one now,
    // with the answer's probability judged apart: detect() below). eyescore, development seeds,
    // wild 1-150 / 151-300, with the size prior's learning below: ROC area 0.9713 / 0.9725 ->
    // 0.9861 / 0.9837; detection 95.73 / 93.81 -> 95.78 / 93.86 %; hard 1-100 / 101-200: ROC
    // area 0.9992 / 0.9997 -> 0.9998 / 0.9999.
    const cv::Size2f axes = fit->ellipse.size;
    const double axisRatio =
        std::min(axes.width, axes.height) / std::max(1e-6F, std::max(axes.width, axes.height));
    // The ramp's round end follows this eye's own pupil (StarburstConfig::eyeRatioMargin): in
    // wild, a camera at a steep angle sees every pupil flat (34 % of the right answers on pupils
    // with a true axis ratio under 0.75 fell below the gate, against 4 % of all right answers).
    // eyescore, development seeds, wild 1-150 / 151-300: ROC area 0.9866 / 0.9846 -> 0.9872 /
    // 0.9860; with the gate at 0.6 (was 0.58), wrong answers rejected 90.9 / 92.4 -> 91.4 /
    // 92.5 %, right ones kept 96.2 / 95.2 -> 96.5 / 95.4 %; seed 63: right kept 58 -> 93 %.
    double roundRatio = mConfig.roundAxisRatio;
    if (mConfig.eyeRatioMargin > 0.0 && mEyeRatio > 0.0) {
        // Never rounder than the configured end, nor within 0.1 of the flat one (a min/max, not
        // std::clamp: a configuration may set the two ends closer than that).
        roundRatio = std::max(mConfig.flattestAxisRatio + 0.1,
                              std::min(roundRatio, mEyeRatio - mConfig.eyeRatioMargin));
    }
    refined.shapeFactor = smoothstep(mConfig.flattestAxisRatio, roundRatio, axisRatio);
    result.confidence *= refined.shapeFactor;
    refined.supportAll = support.all;
    refined.visibleSupport = support.visible;
    refined.fill = fill;
    refined.axisRatio = axisRatio;
    return refined;
}

StarburstDetector::Interior StarburstDetector::interiorFill(const cv::Mat& grey,
                                                            const cv::RotatedRect& e,
                                                            const Levels& lv) const {
    const double th = e.angle * std::numbers::pi / 180.0;
    const cv::Point2d u(std::cos(th), std::sin(th)), v(-std::sin(th), std::cos(th));
    const double a = 0.5 * e.size.width, b = 0.5 * e.size.height;
    const cv::Point2d c(e.center.x, e.center.y);
    std::array<double, 49> values{};
    int n = 0, dark = 0;
    auto add = [&](cv::Point2d p) {
        const double g = sample(grey, p.x, p.y);
        if (g < 0.0 || g >= lv.glint) return; // off the image, or a glint
        values[static_cast<std::size_t>(n++)] = g;
        if (g < lv.threshold) ++dark;
    };
    add(c);
    for (const double r : {0.3, 0.55, 0.8}) {
        for (int k = 0; k < 16; ++k) {
            const double phi = (k + 0.5 * r) * 2.0 * std::numbers::pi / 16.0;
            add(c + u * (r * a * std::cos(phi)) + v * (r * b * std::sin(phi)));
        }
    }
    if (n == 0) return {0.0, 255.0, 255.0};
    std::sort(values.begin(), values.begin() + n);
    return {static_cast<double>(dark) / n, values[static_cast<std::size_t>(n / 2)],
            values[static_cast<std::size_t>(3 * n / 4)]};
}

double StarburstDetector::sizeConsistency(double semiMajor) const {
    if (mRecentRadius <= 0.0) return 1.0;
    const double l = std::log(semiMajor / mRecentRadius);
    constexpr double kSigma = 0.35; // a 1.4x size change keeps 60 % of the confidence
    return std::exp(-0.5 * l * l / (kSigma * kSigma));
}

std::optional<StarburstDetector::Candidate>
StarburstDetector::innerCandidate(cv::Point2d outerCentre, double outerSemiMinor,
                                  double outerInterior, double minR) {
    // The same centre-surround feature as findCandidates, on the coarse image around the outer
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
                if (response < 0.5 * mConfig.minContrast) continue;
                if (!best || response > best->response)
                    best = Candidate{{(x + roi.x + 0.5) * f - 0.5, (y + roi.y + 0.5) * f - 0.5},
                                     r * f,
                                     response};
            }
        }
    }
    return best;
}

PupilResult StarburstDetector::detect(const cv::Mat& grey, double /*tMs*/) {
    if (grey.empty() || grey.type() != CV_8UC1)
        throw EyetrackError("pupil detector: expected an 8-bit greyscale image");
    ++mFrame;
    mBlobsRefined = 0;
    const double side = std::min(grey.rows, grey.cols);
    const double minR = mConfig.minRadius > 0.0 ? mConfig.minRadius : 0.03 * side;
    const double maxR = mConfig.maxRadius > 0.0 ? mConfig.maxRadius : 0.25 * side;
    cv::integral(grey, mFullIntegral, CV_32S);
    mCandidates.clear();
    // With the closing, the fallback round's blobs are searched for only when it runs.
    const int plainBlobs =
        mConfig.candidates + (mConfig.fallbackClosing > 0.0 ? 0 : mConfig.fallbackCandidates);
    findCandidates(grey, mFullIntegral, minR, maxR, mSmall, mIntegral, mCandidates,
                   static_cast<std::size_t>(plainBlobs));
    mFirstFits.clear();
    // Rays walk a 3x3 box-filtered copy: sensor noise would otherwise end a ray at the first
    // noisy pixel above the threshold when the pupil is only a little darker than its iris. The
    // filter is symmetric, so the half-way crossing of an edge stays where it was.
    boxBlur3x3(grey, mSmooth);
    mNoise = noiseSigma(grey, mSmooth);
    mSmoothRange.build(mSmooth);
    // Temporal prior (after PuReST, Santini et al. 2018): last frame's pupil is also a candidate,
    // and a result close to it is preferred. Pupils move little between frames except in
    // saccades, where the coarse search still finds them.
    const bool haveLast = mLast.found && mLast.confidence >= 0.6;
    if (haveLast) mCandidates.insert(mCandidates.begin(), {mLast.centre(), mLast.semiMajor(), 0.0});
    // A refined candidate (its confidence with the size prior and the fallback scale applied)
    // and how it was ranked.
    struct Scored : Refined {
        double score = 0.0;
        double consistency = 1.0; // the size prior's factor in score and confidence
        double sizeFactor = 1.0;  // the size prior's factor in the confidence alone
    };
    std::vector<Scored> scored;
    // confidenceScale: StarburstConfig::fallbackConfidence for the fallback round's blobs.
    auto consider = [&](const Candidate& c, double surroundHint, double confidenceScale = 1.0) {
        ++mBlobsRefined;
        auto refined = refine(grey, c, minR, maxR, surroundHint);
        PupilResult& r = refined.result;
        if (r.confidence <= 0.0 && refined.visibleSupport <= 0.0) return;
        // Size consistency (PuReST): the pupil's size changes slowly, so an ellipse far from the
        // recent pupil size (a gap between lashes during a blink) loses confidence.
        const double consistency = sizeConsistency(r.semiMajor());
        const double sizeFactor = sizeConsistency(refined.fittedSemiMajor);
        r.confidence *= sizeFactor;
        r.confidence *= confidenceScale;
        // Selection score: support of the visible outline and how pupil-like the ellipse is,
        // weighed towards pupil-sized ellipses (dark gaps between lashes make small,
        // high-contrast ellipses), towards a shape the camera can see a pupil at (the square
        // root of the confidence's axis-ratio ramp: a flat lash loop or a sliver of the lid's
        // margin must not outscore a rounder pupil of a little less support) and towards last
        // frame's pupil. The ramp in full, or with the whole confidence, in place of its root:
        // eyescore, development seeds, wild 1-150 / 151-300, within 5 px 96.94 / 95.81 % without
        // it; root 97.17 / 96.04 % (seeds 210 +37 frames, 126 +24, 298 +20; 274 -40, a pupil half
        // under the lid); full ramp 97.16 / 96.02 %; the confidence^0.5 95.77 / 94.35 %. Gate
        // 0.6: wrong answers rejected 93.2 / 93.6 -> 93.0 / 93.7 %, right kept 98.1 / 97.8 ->
        // 98.0 / 97.4 %; hard 1-100 / 101-200 99.82 / 99.86 -> 99.84 / 99.88 %.
        double score = refined.visibleSupport * refined.quality * consistency *
                       std::sqrt(refined.shapeFactor) *
                       (0.6 + 0.4 * std::min(1.0, r.semiMinor() / (0.06 * side)));
        if (haveLast &&
            cv::norm(r.centre() - mLast.centre()) < std::max(5.0, 0.5 * mLast.semiMajor()))
            score *= 1.2;
        if (score > 0.0) {
            scored.push_back({refined, score, consistency, sizeFactor});
        }
    };
    // The fallback round (StarburstConfig::fallbackCandidates): further blobs, from the image
    // with lashes closed away (findFallbackCandidates), when the first round found nothing as
    // confident as a prior. What follows measured it with the plain search's next five blobs. In
    // the wild preset, blurred shadows and lash clusters outside the eye (darker than the pupil, so
    // stronger blobs) took all five places while a low-contrast pupil was plainly visible (wild
    // seed 178, the pupil the ninth blob). eyescore, development seeds, wild 1-150 / 151-300: 95.89
    // / 94.05 -> 96.17 / 94.61 % within 5 px (seeds 178: 60 -> 73 %, 71: 78 -> 91 %, 267: 6 -> 75
    // %; 287: 90 -> 73 %: a fallback blob outscored the first round's winner, inside which a faint
    // pupil had been found; searching inside both winners won that back but let 0.2 / 0.5 points
    // more wrong answers through the gate). Without the confidence scale (and a 0.5 trigger)
    // the gate kept 1.4 points more wrong answers (specks and lash loops answered while the
    // pupil was hidden), with it 90.8 / 92.3 -> 90.9 / 92.4 % rejected; hard 1-100 / 101-200
    // 99.79 / 99.81 -> 99.77 / 99.80 %. Ten more blobs instead of five: +0.13 / +0.29 points,
    // but the hard preset 10 % slower (five: 3 %).
    // The strongest iris-sized candidate that yields no fit (a dark iris cut by the lid, its
    // outline broken by glints and lashes): its pupil is a weak blob inside a dark surround
    // that the search ranks below lash clusters, so it is looked for inside that candidate too.
    std::optional<Candidate> unfitted;
    const std::size_t firstRound = std::min(
        mCandidates.size(), static_cast<std::size_t>(mConfig.candidates) + (haveLast ? 1U : 0U));
    for (std::size_t i = 0; i <= mCandidates.size(); ++i) {
        if (i == firstRound && mConfig.fallbackCandidates > 0) {
            if (std::any_of(scored.begin(), scored.end(), [&](const Scored& s) {
                    return s.result.confidence >= mConfig.fallbackBelow;
                })) {
                break;
            }
            findFallbackCandidates(grey, minR, maxR, firstRound);
        }
        if (i == mCandidates.size()) {
            break;
        }
        const Candidate& c = mCandidates[i];
        const std::size_t before = scored.size();
        consider(c, 0.0, i < firstRound ? 1.0 : mConfig.fallbackConfidence);
        // Tracking (as PuReST tracks before it searches): when last frame's pupil, refined
        // first, is found again where it was with a confident, well-outlined, uniformly dark
        // fit, the other blobs are not refined — in such frames they almost never win, and they
        // were two thirds of the work. The inner-blob searches below still run on it.
        if (i == 0 && haveLast && mConfig.trackingConfidence > 0.0 && scored.size() > before) {
            const Scored& prior = scored.back();
            if (prior.result.confidence >= mConfig.trackingConfidence &&
                prior.visibleSupport >= mConfig.trackingSupport &&
                prior.interiorHigh - prior.interior < 0.5 * mConfig.minContrast &&
                cv::norm(prior.result.centre() - mLast.centre()) <
                    std::max(5.0, 0.5 * mLast.semiMajor())) {
                break;
            }
        }
        if (scored.size() == before && !unfitted && c.radius >= kIrisSized * minR) {
            unfitted = c;
        }
    }
    if (unfitted) {
        // The iris's level: the upper quartile of its inner box (the pupil and glints aside).
        const double level =
            percentile(grey, boxAround(unfitted->centre, 0.7 * unfitted->radius), cv::Rect(), 0.75);
        if (level > 0.0) {
            if (const auto inner =
                    innerCandidate(unfitted->centre, unfitted->radius, level, minR)) {
                consider(*inner, level);
            }
        }
    }
    const auto byScore = [](const Scored& a, const Scored& b) { return a.score > b.score; };
    std::sort(scored.begin(), scored.end(), byScore);
    // The search keeps the strongest blobs, and a dark iris's contrast with the sclera can crowd
    // the pupil inside it out: look for the darkest blob inside the winner too, with the
    // winner's inside as the level around it.
    // The same for the best blob by its own evidence, without the size prior: an iris whose
    // pupil was too faint to be a candidate loses to smaller blobs once the prior holds the
    // pupil's size, and its pupil would not be looked for at all.
    bool blobInsideTop = false; // the inner search found a clearly darker blob in the winner
    cv::Point2d searchedTop;
    if (!scored.empty()) {
        const Scored top = scored.front();
        searchedTop = top.result.centre();
        const auto unscaled =
            std::max_element(scored.begin(), scored.end(), [](const Scored& a, const Scored& b) {
                return a.score / a.consistency < b.score / b.consistency;
            });
        const std::optional<Scored> ownBest =
            unscaled->consistency < 1.0 && unscaled != scored.begin()
                ? std::optional<Scored>(*unscaled)
                : std::nullopt;
        if (const auto inner = innerCandidate(top.result.centre(), top.result.semiMinor(),
                                              top.interiorHigh, minR)) {
            // A blob clearly darker than what surrounds it inside the winner: the winner is not
            // uniformly dark, whatever its inside's quartiles say (a small pupil covers too few
            // of their samples to move them).
            blobInsideTop = inner->response >= mConfig.minContrast;
            consider(*inner, top.interiorHigh);
        }
        if (ownBest) {
            if (const auto inner =
                    innerCandidate(ownBest->result.centre(), ownBest->result.semiMinor(),
                                   ownBest->interiorHigh, minR)) {
                consider(*inner, ownBest->interiorHigh);
            }
        }
        std::sort(scored.begin(), scored.end(), byScore);
    }
    // The pick with what was measured on it; when nothing was scored, a default (no pupil, the
    // priors learn nothing).
    const Scored none{};
    const Scored* picked = &none;
    bool darkerInside = false; // a darker, outlined blob inside the pick that lost to it
    if (!scored.empty()) {
        const Scored* pick = &scored.front();
        // The pupil is the darkest blob: a clearly darker, well-outlined ellipse inside the
        // winner (a pupil only slightly darker than its dark iris, which outscores it on
        // contrast with the sclera) takes its place.
        // Inside: within 0.7 of the way from the outer ellipse's centre to its outline (a lash
        // cluster on the rim of a dark iris is not a pupil in it).
        const cv::RotatedRect& oe = pick->result.ellipse;
        const double th = oe.angle * std::numbers::pi / 180.0;
        const double ca = std::cos(th), sa = std::sin(th);
        const double oa = 0.5 * oe.size.width, ob = 0.5 * oe.size.height;
        // One that loses only on its score still shows the pick to be an iris around a pupil:
        // the size prior must not learn the pick's size (below).
        const Scored* outer = pick;
        for (const Scored& s : scored) {
            if (&s == outer) {
                continue;
            }
            const cv::Point2d d = s.result.centre() - outer->result.centre();
            const double u = (d.x * ca + d.y * sa) / oa, v = (-d.x * sa + d.y * ca) / ob;
            const bool inside = u * u + v * v < 0.49;
            const bool smaller = s.result.semiMajor() < 0.75 * outer->result.semiMajor();
            // Its outline must be a step of the full contrast, not a ripple inside a pupil
            // (a glint's halo lifts the outer blob's brightest quarter).
            if (!inside || !smaller ||
                s.interior >= outer->interiorHigh - 0.5 * mConfig.minContrast ||
                s.outside < s.interior + mConfig.minContrast || s.visibleSupport < 0.5) {
                continue;
            }
            // What rings it must be what fills the winner (a pupil's iris), not something
            // brighter: a small fit at the rim of a plainly seen pupil, its outside half iris and
            // half glint halo, otherwise passed as a darker blob inside and took the winner's
            // place, and tracking held it (hard seed 4027, four glints in a square inside the
            // pupil: 0.3 % found with 128 rays, 100 % with this test; a held-out seed, looked at
            // after that run). Development seeds within 6 frames a seed either way.
            if (s.outside > outer->interiorHigh + 0.5 * mConfig.minContrast) {
                continue;
            }
            // Lid skin inside a pupil whose top is under the lid lifts its upper quartile as an
            // iris would; a part of that pupil is no darker than most of it, though, while a
            // pupil in its iris is (it fills less than half the iris's inside) or, when it is
            // large, is ringed by the iris and so mostly seen. Visible support 0.7 alone (was
            // 0.5), eyescore dev seeds 1-100: wild 94.9 -> 95.1 %, but it kept a small pupil
            // whose glints broke up its outline out of its iris on hard held-out seed 7029.
            const bool darkerThanMost = s.interior < outer->interior - 0.5 * mConfig.minContrast;
            if ((darkerThanMost || s.visibleSupport >= 0.7) && s.result.confidence >= 0.5 &&
                s.score >= 0.5 * outer->score) {
                pick = &s;
                break;
            }
            darkerInside = true;
        }
        // The winner kept with a clearly darker blob inside it may be an iris around a pupil the
        // fits did not outline well enough to take its place: its size must not become the
        // pupil's. Once learnt, the prior vetoes the pupil's own later, good fits as too small
        // (wild seed 153: a pupil 15 grey levels darker than its iris, 21 % of frames right).
        if (blobInsideTop && cv::norm(pick->result.centre() - searchedTop) < 0.5) {
            darkerInside = true;
        }
        picked = pick;
    }
    PupilResult best = picked->result;
    best.found = best.confidence >= mConfig.minConfidence;
    // What is reported is the probability that the answer is right (answer_confidence.hpp); the
    // detector's own product of factors stays what its priors and the next frame's search go by
    // (they were designed on its scale).
    mEvidence =
        AnswerEvidence{.confidence = best.confidence,
                       .visibleSupport = picked->visibleSupport,
                       .fill = picked->fill,
                       .axisRatio = mEyeRatio > 0.0 ? std::min(1.0, picked->axisRatio / mEyeRatio)
                                                    : picked->axisRatio,
                       .sizeFactor = picked->sizeFactor,
                       .sizeKnown = mRecentRadius > 0.0,
                       .score = picked->score,
                       .semiMajor = best.semiMajor()};
    // A rival: the best candidate at another place (not the same blob found twice).
    for (const Scored& s : scored) {
        if (&s != picked &&
            cv::norm(s.result.centre() - best.centre()) >= std::max(5.0, 0.5 * best.semiMajor())) {
            mEvidence.rivalScore = std::max(mEvidence.rivalScore, s.score);
        }
    }
    if (mLast.found) {
        mEvidence.lastDistance = cv::norm(best.centre() - mLast.centre());
    }
    if (mRecentLevel >= 0.0 && picked->outside >= 0.0) {
        mEvidence.levelExcess = std::clamp((picked->interior - mRecentLevel) /
                                               std::max(mConfig.minContrast, mRecentContrast),
                                           0.0, 3.0);
    }
    PupilResult reported = best;
    reported.confidence = answerProbability(mEvidence);
    reported.found = reported.confidence >= mConfig.minConfidence;
    mLast = best;
    ++mFramesSinceSize;
    // The size prior learns only from a uniformly dark inside: an iris with its pupil in it
    // (picked while the pupil was hard to see) must not teach it the iris's size, or the pupil
    // would be held too small to be the pupil from then on.
    const bool uniform =
        picked->interiorHigh - picked->interior < 0.5 * mConfig.minContrast && !darkerInside;
    // It learns from the evidence, the size prior's own factor left out: with it, a pupil that
    // shrank or grew by a third while its confidence was low (a blink, a lid) was held at its
    // old size, its right answers scored under the gate, and the prior never caught up (wild
    // seed 22: a pupil constricting from 45 to 29 px, confidence 0.38-0.65 for 200 frames).
    // eyescore, development seeds, with the shape factor above, wild 1-150 / 151-300: right
    // answers kept by a 0.7 gate 91.0 / 89.5 -> 92.0 / 90.6 %, wrong ones rejected within 0.1
    // point, detection +0.13 / +0.14 points. Without the shape factor, learning from slivers
    // cost 2.3-2.4 points of wrong answers rejected.
    const double evidence = best.confidence / std::max(1e-6, picked->sizeFactor);
    if (evidence >= 0.75 && uniform) {
        learn(mRecentRadius, best.semiMajor(), mRecentRadius > 0.0);
        learn(mRecentMinor, best.semiMinor(), mRecentMinor > 0.0);
        if (picked->outside >= 0.0) {
            learn(mRecentContrast, picked->outside - picked->interior, mRecentContrast > 0.0);
            learn(mRecentLevel, picked->interior, mRecentLevel >= 0.0);
        }
        mFramesSinceSize = 0;
    } else if (mFramesSinceSize > 300) {
        mRecentRadius = 0.0; // lost for long: forget the size
        mRecentMinor = 0.0;
        mRecentLevel = -1.0;
        mRecentContrast = 0.0;
    }
    // The eye's own pupil shape (StarburstConfig::eyeRatioMargin) is learnt only from a pupil
    // seen whole (nine-tenths of its outline supported: a sliver under the lid is flat because
    // it is covered, not because of the camera's angle), judged without the ramp's own factor
    // (or a flat eye's pupils could never teach it). Whole-pupil fits are 0.02-0.1 off the
    // true ratio in a 300-frame window (the ratio also changes as the eye turns), which the
    // 0.1 margin absorbs.
    if (mConfig.eyeRatioMargin > 0.0 && uniform && picked->supportAll >= 0.9 &&
        evidence / std::max(1e-6, picked->shapeFactor) >= 0.75) {
        const double ratio = best.semiMinor() / std::max(1e-6, best.semiMajor());
        learn(mEyeRatio, ratio, mEyeRatio > 0.0);
        mShape.add(best.ellipse);
    }
    return reported;
}

} // namespace gt::eyetrack
