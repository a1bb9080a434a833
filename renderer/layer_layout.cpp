#include "layer_layout.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace gt::render {

uint64_t LayerLayout::pixels() const {
    uint64_t n = 0;
    for (const LayerGrid& g : grids) {
        n += static_cast<uint64_t>(g.width) * g.height;
    }
    return n;
}

foveation::LayerDisplay viewDisplay(uint32_t width, uint32_t height,
                                    const trace::FrustumTangents& t) {
    if (width == 0 || height == 0 || !t.valid()) {
        throw ArgumentError("eccentricity layers: a view without size or frustum");
    }
    // Portrait views take the long vertical axis (Guenter et al. 2012, footnote 8).
    const bool portrait = height > width;
    return foveation::LayerDisplay::fromTangents(portrait ? height : width,
                                                 portrait ? width : height,
                                                 portrait ? t.up - t.down : t.right - t.left);
}

namespace {

void checkView(uint32_t width, uint32_t height, const foveation::LayerDisplay& display) {
    if (width == 0 || height == 0) {
        throw ArgumentError("eccentricity layers: a view of no size");
    }
    if (std::abs(display.resolution - std::max(width, height)) > 0.5) {
        throw ArgumentError("eccentricity layers: the display's " +
                            std::to_string(display.resolution) + " px do not match the view's " +
                            std::to_string(std::max(width, height)));
    }
}

LayerLayout gridsOf(uint32_t width, uint32_t height, const foveation::LayerDisplay& display,
                    foveation::LayerPlan plan) {
    LayerLayout layout;
    layout.plan = std::move(plan);
    const double perTangent = display.pixelsPerTangent();
    for (std::size_t i = 0; i < layout.plan.layers.size(); ++i) {
        const foveation::Layer& l = layout.plan.layers[i];
        LayerGrid g;
        g.pitch = static_cast<float>(l.samplingFactor);
        g.outer = i + 1 == layout.plan.layers.size();
        double coverX = width, coverY = height; // display pixels the grid spans
        if (!g.outer) {
            g.radiusPx =
                static_cast<float>(std::tan(l.radiusDeg * std::numbers::pi / 180.0) * perTangent);
            coverX = std::min<double>(2.0 * g.radiusPx, width);
            coverY = std::min<double>(2.0 * g.radiusPx, height);
        }
        g.width = std::max(1u, static_cast<uint32_t>(std::ceil(coverX / g.pitch - 1e-6)));
        g.height = std::max(1u, static_cast<uint32_t>(std::ceil(coverY / g.pitch - 1e-6)));
        layout.grids.push_back(g);
    }
    return layout;
}

} // namespace

LayerLayout layoutLayers(uint32_t width, uint32_t height, const foveation::LayerDisplay& display,
                         const foveation::MarModel& mar, uint32_t count, uint32_t steps) {
    checkView(width, height, display);
    return gridsOf(width, height, display,
                   foveation::optimiseLayers(display, mar, count, {}, steps));
}

LayerLayout layoutLayers(uint32_t width, uint32_t height, const foveation::LayerDisplay& display,
                         const foveation::MarModel& mar, std::span<const double> radiiDeg) {
    checkView(width, height, display);
    if (radiiDeg.size() + 1 > 4) {
        throw ArgumentError("eccentricity layers: at most 3 inner radii");
    }
    return gridsOf(width, height, display, foveation::planLayers(display, mar, radiiDeg));
}

LayerRect placeLayer(const LayerGrid& g, uint32_t width, uint32_t height, glm::vec2 gaze) {
    const glm::vec2 display(static_cast<float>(width), static_cast<float>(height));
    const glm::vec2 size =
        glm::vec2(static_cast<float>(g.width), static_cast<float>(g.height)) * g.pitch;
    if (g.outer) {
        return {(display - size) * 0.5f, size};
    }
    const glm::vec2 half = size * 0.5f;
    glm::vec2 centre = gaze + 0.5f; // pixel centres at integers -> pixel edges
    for (int a = 0; a < 2; ++a) {
        centre[a] = half[a] >= display[a] * 0.5f
                        ? display[a] * 0.5f
                        : std::clamp(centre[a], half[a], display[a] - half[a]);
    }
    return {glm::round((centre - half) / g.pitch) * g.pitch, size};
}

LayerRect jittered(const LayerRect& rect, float pitch, glm::vec2 jitter) {
    return {rect.origin + jitter * pitch, rect.size};
}

trace::FrustumTangents subFrustum(const trace::FrustumTangents& v, uint32_t width, uint32_t height,
                                  const LayerRect& r) {
    auto tx = [&](float x) { return v.left + (v.right - v.left) * x / static_cast<float>(width); };
    auto ty = [&](float y) { return v.up - (v.up - v.down) * y / static_cast<float>(height); };
    return {tx(r.origin.x), tx(r.origin.x + r.size.x), ty(r.origin.y), ty(r.origin.y + r.size.y)};
}

float radicalInverse(uint64_t index, uint32_t base) {
    double inv = 1.0 / base, f = inv, r = 0.0;
    while (index > 0) {
        r += f * static_cast<double>(index % base);
        index /= base;
        f *= inv;
    }
    return static_cast<float>(r);
}

glm::vec2 layerJitter(uint64_t frame) {
    // Index 1 onwards: index 0 would put frame 0 at the corner, (0, 0) -> (-0.5, -0.5).
    return glm::vec2(radicalInverse(frame + 1, 2), radicalInverse(frame + 1, 3)) - 0.5f;
}

trace::FrustumTangents tangentsOf(const shaders::trace::CameraPush& c) {
    const float halfH = c.origin.w, halfW = c.origin.w * c.forward.w;
    return {c.right.w - halfW, c.right.w + halfW, c.up.w + halfH, c.up.w - halfH};
}

} // namespace gt::render
