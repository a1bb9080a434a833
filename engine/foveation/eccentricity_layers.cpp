#include "foveation/eccentricity_layers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.hpp"
#include "core/progress.hpp"

namespace gt::foveation {

namespace {

double radians(double deg) {
    return deg * std::numbers::pi / 180.0;
}
double degrees(double rad) {
    return rad * 180.0 / std::numbers::pi;
}

std::vector<double> checkedWeights(std::span<const double> weights, std::size_t layers) {
    if (weights.empty()) {
        return std::vector<double>(layers, 1.0);
    }
    if (weights.size() != layers) {
        throw ArgumentError("layer weights: " + std::to_string(weights.size()) + " for " +
                            std::to_string(layers) + " layers");
    }
    for (const double w : weights) {
        if (!(w > 0.0) || !std::isfinite(w)) {
            throw ArgumentError("layer weights must be positive");
        }
    }
    return {weights.begin(), weights.end()};
}

// eq. (2), never finer than the display: "we cannot exceed native display resolution" (4.3).
double samplingFactor(const MarModel& mar, double innerRadiusDeg, double sharpnessDeg) {
    return std::max(1.0, mar.marDeg(innerRadiusDeg) / sharpnessDeg);
}

} // namespace

LayerDisplay LayerDisplay::paperMonitor() {
    return {1920.0, 51.0, 59.0, 9.0 / 16.0};
}

LayerDisplay LayerDisplay::fromProfile(const DisplayProfile& p) {
    if (p.width == 0 || p.height == 0 || !(p.viewingDistance > 0.0)) {
        throw ArgumentError("display profile '" + p.name + "' has no size or distance");
    }
    // Widths are the unit of v; pixels are square, so the height is height / width widths.
    const double w = p.width, h = p.height;
    if (h > w) {
        return {h, h / w, p.viewingDistance, w / h}; // portrait: the long axis is y
    }
    return {w, 1.0, p.viewingDistance, h / w};
}

LayerDisplay LayerDisplay::fromTangents(double longPixels, double shortPixels,
                                        double tangentExtent) {
    if (!(longPixels > 0.0) || !(shortPixels > 0.0) || shortPixels > longPixels ||
        !(tangentExtent > 0.0) || !std::isfinite(tangentExtent)) {
        throw ArgumentError("eccentricity layers: a view of " + std::to_string(longPixels) + " x " +
                            std::to_string(shortPixels) + " px and tangent extent " +
                            std::to_string(tangentExtent));
    }
    return {longPixels, tangentExtent, 1.0, shortPixels / longPixels};
}

LayerDisplay LayerDisplay::acuityMatched(double fieldOfViewDeg, double aspect, double omega0Deg) {
    const double tanE = std::tan(radians(fieldOfViewDeg / 2.0));
    // eq. (9) with V* = 1, W* = 2 tan(e*) (eq. 6).
    return {4.0 * tanE / std::tan(radians(omega0Deg)), 2.0 * tanE, 1.0, aspect};
}

double LayerDisplay::radiusDeg() const {
    return degrees(std::atan(width / (2.0 * distance)));
}

double LayerDisplay::sharpnessDeg() const {
    return degrees(std::atan(2.0 * width / (distance * resolution)));
}

double LayerDisplay::pixels() const {
    return aspect * resolution * resolution;
}

LayerPlan planLayers(const LayerDisplay& display, const MarModel& mar,
                     std::span<const double> radiiDeg, std::span<const double> weights) {
    const std::size_t n = radiiDeg.size() + 1;
    const std::vector<double> w = checkedWeights(weights, n);
    const double eStar = display.radiusDeg(), omegaStar = display.sharpnessDeg();
    double previous = 0.0;
    for (const double e : radiiDeg) {
        if (!(e > previous) || !(e < eStar)) {
            throw ArgumentError("layer radii must rise strictly inside (0, e* = " +
                                std::to_string(eStar) + " deg)");
        }
        previous = e;
    }
    LayerPlan plan;
    plan.displayPixels = display.pixels();
    for (std::size_t i = 0; i < n; ++i) {
        Layer l;
        l.weight = w[i];
        l.samplingFactor = i == 0 ? 1.0 : samplingFactor(mar, radiiDeg[i - 1], omegaStar);
        if (i + 1 < n) {
            l.radiusDeg = radiiDeg[i];
            l.diameter = 2.0 * display.distance * std::tan(radians(l.radiusDeg)) *
                         display.resolution / (l.samplingFactor * display.width); // eq. (3)
            l.pixels = l.diameter * l.diameter;                                   // eq. (4)
        } else {
            l.radiusDeg = eStar;
            l.diameter = display.resolution / l.samplingFactor;  // eq. (3), i = n
            l.pixels = display.aspect * l.diameter * l.diameter; // eq. (4), i = n
        }
        plan.work += l.weight * l.pixels; // eq. (5)
        plan.layers.push_back(l);
    }
    return plan;
}

LayerPlan optimiseLayers(const LayerDisplay& display, const MarModel& mar, uint32_t layerCount,
                         std::span<const double> weights, uint32_t steps) {
    if (layerCount < 1 || layerCount > 4) {
        throw ArgumentError("layer count " + std::to_string(layerCount) + " is outside 1..4");
    }
    if (steps < layerCount) {
        throw ArgumentError("layer optimisation needs more grid steps");
    }
    const std::vector<double> w = checkedWeights(weights, layerCount);
    if (layerCount == 1) {
        return planLayers(display, mar, {}, w);
    }
    const double eStar = display.radiusDeg(), omegaStar = display.sharpnessDeg();
    // Grid radii e = k e* / steps, k = 1 .. steps - 1, and what each layer's pixels need of them.
    std::vector<double> e(steps), tanE(steps), s(steps);
    for (uint32_t k = 1; k < steps; ++k) {
        e[k] = eStar * k / steps;
        tanE[k] = std::tan(radians(e[k]));
        s[k] = samplingFactor(mar, e[k], omegaStar); // s of the layer outside radius e[k]
    }
    const double perTangent = 2.0 * display.distance * display.resolution / display.width;
    // Inner layer i (< n) between grid radii `in` (0: the centre) and `out`, weighted.
    auto inner = [&](std::size_t i, uint32_t in, uint32_t out) {
        const double si = in == 0 ? 1.0 : s[in];
        const double d = perTangent * tanE[out] / si;
        return w[i] * d * d;
    };
    auto outer = [&](uint32_t in) {
        const double d = display.resolution / s[in];
        return w[layerCount - 1] * display.aspect * d * d;
    };
    double best = std::numeric_limits<double>::infinity();
    std::vector<uint32_t> arg(layerCount - 1), cur(layerCount - 1);
    // Depth-first over every rising choice of radii on the grid: the plain brute force of
    // section 4.3 (no pruning: the outer layer's pixels fall as the inner radii grow).
    // Four layers on a fine grid take minutes: progress over the innermost radius, each of its
    // choices weighed by the choices beyond it, (steps - k)^(layers - 2).
    auto beyond = [&](uint32_t k) {
        std::uint64_t n = 1;
        for (uint32_t i = 2; i < layerCount; ++i)
            n *= steps - k;
        return n;
    };
    std::uint64_t choices = 0;
    for (uint32_t k = 1; k < steps; ++k)
        choices += beyond(k);
    progress::Step step("optimising the layer radii", choices);
    auto search = [&](auto& self, std::size_t depth, uint32_t in, double sum) -> void {
        if (depth == layerCount - 1) {
            const double total = sum + outer(in);
            if (total < best) {
                best = total;
                arg = cur;
            }
            return;
        }
        for (uint32_t k = in + 1; k + (layerCount - 2 - depth) < steps; ++k) {
            cur[depth] = k;
            self(self, depth + 1, k, sum + inner(depth, in, k));
            if (depth == 0) (void)step.advance(beyond(k));
        }
    };
    search(search, 0, 0, 0.0);
    std::vector<double> radii(arg.size());
    std::transform(arg.begin(), arg.end(), radii.begin(), [&](uint32_t k) { return e[k]; });
    return planLayers(display, mar, radii, w);
}

std::vector<double> halfRateWeights(uint32_t layerCount) {
    std::vector<double> w(layerCount, 0.5);
    if (!w.empty()) {
        w[0] = 1.0;
    }
    return w;
}

} // namespace gt::foveation
