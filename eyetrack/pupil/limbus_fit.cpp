#include "pupil/limbus_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include <opencv2/core.hpp>

#include "pupil/bilinear.hpp"

namespace gt::eyetrack {

namespace {

// Signed distance from p to the ellipse along the ray from its centre (negative inside).
double radialResidual(cv::Point2d p, double cx, double cy, double a, double b, double c, double s) {
    const double dx = p.x - cx, dy = p.y - cy;
    const double u = dx * c + dy * s, w = -dx * s + dy * c;
    const double rho = std::sqrt(u * u / (a * a) + w * w / (b * b));
    return rho > 1e-9 ? std::sqrt(u * u + w * w) * (1.0 - 1.0 / rho) : -b;
}

// The concentric model: parameters (cx, cy, a, ratio, angle, scale), the pupil an ellipse of
// semi-axes a and a ratio turned by `angle`, the limbus the same ellipse `scale` times larger.
using ConcentricParams = std::array<double, 6>;
constexpr double kConcentricSigma = 1.5; // px: the Cauchy weights' scale, and the inlier band

class ConcentricModel {
public:
    ConcentricModel(std::span<const cv::Point2d> pupilPoints,
                    std::span<const cv::Point2d> limbusPoints, double minRatio)
        : mPupil(pupilPoints), mLimbus(limbusPoints), mMinRatio(minRatio), np(pupilPoints.size()),
          nl(limbusPoints.size()), n(np + nl) {}

    void project(ConcentricParams& x) const {
        x[2] = std::max(2.0, x[2]);
        x[3] = std::clamp(x[3], mMinRatio, 1.0);
        x[5] = std::clamp(x[5], 1.2, 10.0);
    }

    void residuals(const ConcentricParams& x, std::vector<double>& r) const {
        r.resize(n);
        const double c = std::cos(x[4]), s = std::sin(x[4]);
        for (std::size_t i = 0; i < np; ++i) {
            r[i] = radialResidual(mPupil[i], x[0], x[1], x[2], x[2] * x[3], c, s);
        }
        for (std::size_t i = 0; i < nl; ++i) {
            r[np + i] =
                radialResidual(mLimbus[i], x[0], x[1], x[2] * x[5], x[2] * x[3] * x[5], c, s);
        }
    }

    // d r / d (cx, cy, a, ratio, angle, scale) for r = L (1 - 1 / rho), L the distance from the
    // centre and rho the ellipse's normalised radius there (A, B its semi-axes).
    void jacobian(const ConcentricParams& x, std::vector<std::array<double, 6>>& jac) const {
        jac.resize(n);
        const double c = std::cos(x[4]), s = std::sin(x[4]);
        for (std::size_t i = 0; i < n; ++i) {
            const bool onLimbus = i >= np;
            const cv::Point2d p = onLimbus ? mLimbus[i - np] : mPupil[i];
            const double ke = onLimbus ? x[5] : 1.0;
            const double A = x[2] * ke, B = x[2] * x[3] * ke;
            const double dx = p.x - x[0], dy = p.y - x[1];
            const double u = dx * c + dy * s, w = -dx * s + dy * c;
            const double L = std::max(1e-9, std::sqrt(u * u + w * w));
            const double rho = std::max(1e-9, std::sqrt(u * u / (A * A) + w * w / (B * B)));
            const double k = L / (rho * rho); // d r / d rho
            const double drdu = u / L * (1.0 - 1.0 / rho) + k * u / (A * A * rho);
            const double drdw = w / L * (1.0 - 1.0 / rho) + k * w / (B * B * rho);
            const double drdA = -k * u * u / (A * A * A * rho);
            const double drdB = -k * w * w / (B * B * B * rho);
            std::array<double, 6>& j = jac[i];
            j[0] = -drdu * c + drdw * s;
            j[1] = -drdu * s - drdw * c;
            j[2] = (drdA + drdB * x[3]) * ke;
            j[3] = drdB * x[2] * ke;
            j[4] = drdu * w - drdw * u;
            j[5] = onLimbus ? (drdA + drdB * x[3]) * x[2] : 0.0;
        }
    }

    [[nodiscard]] static double robustCost(const std::vector<double>& r) {
        double sum = 0.0;
        for (const double v : r) {
            sum += std::log1p(v * v / (kConcentricSigma * kConcentricSigma));
        }
        return sum;
    }

    // Levenberg-Marquardt on the Cauchy-weighted residuals from x (cost: its robustCost, r: its
    // residuals; on return, the result's).
    [[nodiscard]] ConcentricParams descend(ConcentricParams x, double cost,
                                           std::vector<double>& r) const;
    // The two ellipses, the inliers and the limbus points' spread, at x (r: its residuals).
    [[nodiscard]] ConcentricFit describe(const ConcentricParams& x,
                                         const std::vector<double>& r) const;

private:
    // The normal equations J^T W J and J^T W r, W the Cauchy weights 1 / (1 + (r / sigma)^2).
    void normalEquations(const std::vector<std::array<double, 6>>& jac,
                         const std::vector<double>& r, cv::Matx<double, 6, 6>& jtj,
                         cv::Vec<double, 6>& jtr) const;

    std::span<const cv::Point2d> mPupil, mLimbus;
    double mMinRatio;
    std::size_t np, nl, n;
};

void ConcentricModel::normalEquations(const std::vector<std::array<double, 6>>& jac,
                                      const std::vector<double>& r, cv::Matx<double, 6, 6>& jtj,
                                      cv::Vec<double, 6>& jtr) const {
    constexpr double kSigma = kConcentricSigma;
    jtj = cv::Matx<double, 6, 6>::zeros();
    jtr = cv::Vec<double, 6>();
    for (std::size_t i = 0; i < n; ++i) {
        const double w = 1.0 / (1.0 + r[i] * r[i] / (kSigma * kSigma));
        for (int p = 0; p < 6; ++p) {
            const double wj = w * jac[i][static_cast<std::size_t>(p)];
            jtr[p] += wj * r[i];
            for (int q = p; q < 6; ++q) {
                jtj(p, q) += wj * jac[i][static_cast<std::size_t>(q)];
            }
        }
    }
    for (int p = 0; p < 6; ++p) {
        for (int q = 0; q < p; ++q) {
            jtj(p, q) = jtj(q, p);
        }
    }
}

ConcentricParams ConcentricModel::descend(ConcentricParams x, double cost,
                                          std::vector<double>& r) const {
    constexpr int kIterations = 15;
    constexpr double kConverged = 1e-4; // relative fall of the cost that ends the descent
    double current = cost, lambda = 1e-2;
    std::vector<std::array<double, 6>> jac(n);
    std::vector<double> rh;
    for (int it = 0; it < kIterations; ++it) {
        jacobian(x, jac);
        cv::Matx<double, 6, 6> jtj;
        cv::Vec<double, 6> jtr;
        normalEquations(jac, r, jtj, jtr);
        double gain = 0.0;
        for (int tries = 0; tries < 4 && gain <= 0.0; ++tries) {
            cv::Matx<double, 6, 6> m = jtj;
            for (int p = 0; p < 6; ++p) {
                m(p, p) += lambda * (jtj(p, p) + 1e-9);
            }
            cv::Vec<double, 6> step;
            if (!cv::solve(m, -jtr, step, cv::DECOMP_CHOLESKY)) {
                lambda *= 10.0;
                continue;
            }
            ConcentricParams xn = x;
            for (int p = 0; p < 6; ++p) {
                xn[static_cast<std::size_t>(p)] += step[p];
            }
            project(xn);
            residuals(xn, rh);
            const double next = robustCost(rh);
            if (next < current) {
                gain = (current - next) / std::max(1e-12, current);
                x = xn;
                r.swap(rh);
                current = next;
                lambda = std::max(1e-7, 0.3 * lambda);
            } else {
                lambda *= 10.0;
            }
        }
        if (gain < kConverged) {
            break;
        }
    }
    return x;
}

ConcentricFit ConcentricModel::describe(const ConcentricParams& x,
                                        const std::vector<double>& r) const {
    ConcentricFit fit;
    const float deg = static_cast<float>(x[4] * 180.0 / std::numbers::pi);
    const cv::Point2f centre(static_cast<float>(x[0]), static_cast<float>(x[1]));
    fit.pupil = cv::RotatedRect(
        centre, cv::Size2f(static_cast<float>(2.0 * x[2]), static_cast<float>(2.0 * x[2] * x[3])),
        deg);
    fit.limbus = cv::RotatedRect(centre,
                                 cv::Size2f(static_cast<float>(2.0 * x[2] * x[5]),
                                            static_cast<float>(2.0 * x[2] * x[3] * x[5])),
                                 deg);
    double lo = 1e9, hi = -1e9;
    for (std::size_t i = 0; i < n; ++i) {
        if (std::abs(r[i]) > kConcentricSigma) {
            continue;
        }
        if (i < np) {
            ++fit.pupilInliers;
        } else {
            ++fit.limbusInliers;
            const cv::Point2d p = mLimbus[i - np];
            const double ang = std::atan2(p.y - x[1], p.x - x[0]) * 180.0 / std::numbers::pi;
            // Rays run from -20 to 200 deg: unwrap the few above the horizontal on the left.
            const double unwrapped = ang < -90.0 ? ang + 360.0 : ang;
            lo = std::min(lo, unwrapped);
            hi = std::max(hi, unwrapped);
        }
    }
    fit.limbusSpreadDeg = hi > lo ? hi - lo : 0.0;
    return fit;
}

} // namespace

void findLimbusPoints(const cv::Mat& smooth, const cv::RotatedRect& pupil, const LimbusSearch& s,
                      std::vector<cv::Point2d>& points) {
    points.clear();
    const cv::Point2d c(pupil.center.x, pupil.center.y);
    const double a = 0.5 * pupil.size.width, b = 0.5 * pupil.size.height;
    const double th = pupil.angle * std::numbers::pi / 180.0;
    const cv::Point2d e1(std::cos(th), std::sin(th)), e2(-std::sin(th), std::cos(th));
    const double major = std::max(a, b);
    constexpr int kPlateau = 4; // px the sclera must stay bright (a glint or a lash gap does not)
    std::vector<double> profile;
    const Bilinear bilinear(smooth);
    for (int i = 0; i < s.rays; ++i) {
        // From 20 deg above the horizontal on one side, through straight down, to the other.
        const double phi = (-20.0 + 220.0 * i / (s.rays - 1)) * std::numbers::pi / 180.0;
        const cv::Point2d d(std::cos(phi), std::sin(phi));
        const double edge = 1.0 / std::hypot(d.dot(e1) / a, d.dot(e2) / b);
        const int t0 = static_cast<int>(std::ceil(edge + 2.0));
        const int t1 = static_cast<int>(s.maxReach * major);
        // Sampled as far as the search needs it (most rays end at the first plateau).
        profile.clear();
        bool ended = false;
        const auto reach = [&](int k) {
            while (!ended && static_cast<int>(profile.size()) <= k) {
                const int t = t0 + static_cast<int>(profile.size());
                const double v = t <= t1 ? bilinear(c.x + t * d.x, c.y + t * d.y) : -1.0;
                if (v < 0.0) {
                    ended = true;
                } else {
                    profile.push_back(v);
                }
            }
            return static_cast<int>(profile.size()) > k;
        };
        if (!reach(7)) {
            continue;
        }
        // The iris's own level on this ray, just outside the pupil (the level measured around the
        // pupil can be the sclera's when the iris is a thin ring).
        std::array<double, 3> first{profile[0], profile[1], profile[2]};
        std::sort(first.begin(), first.end());
        const double bright = std::min(first[1], s.irisLevel) + s.minStep;
        for (int k = 1; reach(k + kPlateau); ++k) {
            if (profile[static_cast<std::size_t>(k)] < bright) {
                continue;
            }
            bool plateau = true;
            for (int j = k; j < k + kPlateau && plateau; ++j) {
                const double v = profile[static_cast<std::size_t>(j)];
                plateau = v >= bright && v < s.glintLevel;
            }
            if (!plateau) {
                continue;
            }
            // Half-way between the darkest level just before (the limbus ring) and the plateau.
            double low = profile[static_cast<std::size_t>(k)];
            int lowAt = k;
            for (int j = k - 1; j >= std::max(0, k - 6); --j) {
                if (profile[static_cast<std::size_t>(j)] < low) {
                    low = profile[static_cast<std::size_t>(j)];
                    lowAt = j;
                }
            }
            double high = 0.0;
            for (int j = k; j < k + kPlateau; ++j) {
                high += profile[static_cast<std::size_t>(j)];
            }
            high /= kPlateau;
            const double half = 0.5 * (low + high);
            double at = k;
            for (int j = lowAt; j < k + kPlateau - 1; ++j) {
                const double v0 = profile[static_cast<std::size_t>(j)];
                const double v1 = profile[static_cast<std::size_t>(j) + 1];
                if (v0 < half && v1 >= half) {
                    at = j + (half - v0) / (v1 - v0);
                    break;
                }
            }
            const double t = t0 + at;
            points.emplace_back(c.x + t * d.x, c.y + t * d.y);
            break;
        }
    }
}

std::optional<ConcentricFit> fitConcentric(std::span<const cv::Point2d> pupilPoints,
                                           std::span<const cv::Point2d> limbusPoints,
                                           const cv::RotatedRect& start, double minRatio) {
    if (pupilPoints.size() < 6 || limbusPoints.size() < 6) {
        return std::nullopt;
    }
    double a0 = 0.5 * start.size.width, b0 = 0.5 * start.size.height;
    double th0 = start.angle * std::numbers::pi / 180.0;
    if (b0 > a0) {
        std::swap(a0, b0);
        th0 += 0.5 * std::numbers::pi;
    }
    const cv::Point2d c0(start.center.x, start.center.y);
    std::vector<double> dist;
    for (const cv::Point2d& p : limbusPoints) {
        dist.push_back(cv::norm(p - c0));
    }
    std::nth_element(dist.begin(), dist.begin() + static_cast<std::ptrdiff_t>(dist.size() / 2),
                     dist.end());
    const double k0 = std::max(1.3, dist[dist.size() / 2] / a0);
    const ConcentricModel model(pupilPoints, limbusPoints, minRatio);
    // The start: the ratio (0.7, 0.85 or 1, the centre raised so the lowest point stays) whose
    // ellipses explain the points best; one descent from there (a descent from each start finds
    // little more for three times the cost).
    std::optional<ConcentricParams> best;
    double bestCost = 0.0;
    std::vector<double> r;
    for (const double ratio0 : {0.7, 0.85, 1.0}) {
        if (ratio0 < minRatio) {
            continue;
        }
        ConcentricParams x{c0.x, c0.y, a0, ratio0, th0, k0};
        x[1] -= std::max(0.0, ratio0 * a0 - b0) * std::abs(std::cos(th0));
        model.project(x);
        model.residuals(x, r);
        const double cost = ConcentricModel::robustCost(r);
        if (!best || cost < bestCost) {
            best = x;
            bestCost = cost;
        }
    }
    if (!best) {
        return std::nullopt;
    }
    model.residuals(*best, r);
    const ConcentricParams x = model.descend(*best, bestCost, r);
    model.residuals(x, r);
    return model.describe(x, r);
}

} // namespace gt::eyetrack
