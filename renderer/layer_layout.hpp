#pragma once
// Where the eccentricity layers (Guenter et al. 2012) of a view go: their grids in layer pixels,
// where each lies on the display this frame, and the sub-frustum each is traced through. Pure CPU
// maths, kept apart from the method so it is tested without a device.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "foveation/eccentricity_layers.hpp"
#include "trace/gpu_scene.hpp"

namespace gt::render {

struct LayerGrid {
    uint32_t width = 0, height = 0; // layer pixels
    float pitch = 1.0f;             // display pixels per layer pixel (s_i, eq. 2)
    float radiusPx = 0.0f;          // e_i as display pixels from the gaze (0 for the outer layer)
    bool outer = false;             // covers the whole display, centred on it
};

struct LayerLayout {
    foveation::LayerPlan plan;
    std::vector<LayerGrid> grids; // inner first
    [[nodiscard]] uint64_t pixels() const;
};

// The layers of a `width` x `height` view seen as `display` (its long axis the view's, see
// viewDisplay), for `mar` and `count` layers, optimised with unit weights as the paper designs its
// layers. Inner layers are squares of 2 tan(e_i) times the display's pixels per tangent (eq. 3),
// clipped to the display, so a layer never traces rays off screen; the outer layer covers the
// display at pitch s_n.
[[nodiscard]] LayerLayout layoutLayers(uint32_t width, uint32_t height,
                                       const foveation::LayerDisplay& display,
                                       const foveation::MarModel& mar, uint32_t count,
                                       uint32_t steps = 400);
// The same with the inner layers' radii given (degrees, rising, count - 1 of them) instead of
// optimised: eq. (2) still sets each layer's pitch.
[[nodiscard]] LayerLayout layoutLayers(uint32_t width, uint32_t height,
                                       const foveation::LayerDisplay& display,
                                       const foveation::MarModel& mar,
                                       std::span<const double> radiiDeg);

// How the eye sees a view: through its frustum (an HMD eye, an OpenXR view: the image fills the
// field of view the frustum spans).
[[nodiscard]] foveation::LayerDisplay viewDisplay(uint32_t width, uint32_t height,
                                                  const trace::FrustumTangents& tangents);

// The display rectangle (pixel edges) a layer grid covers this frame: centred on the gaze (pixel
// centres at integers) and moved inside the display — which keeps everything within its radius
// of the gaze covered — with its corner on a multiple of the layer's pitch, so that as the gaze
// moves the grid moves by whole layer pixels and its history is reprojected without resampling
// blur. The outer layer is centred on the display.
struct LayerRect {
    glm::vec2 origin{}; // top-left corner, display pixel edges
    glm::vec2 size{};   // grid size times pitch
};
[[nodiscard]] LayerRect placeLayer(const LayerGrid& grid, uint32_t width, uint32_t height,
                                   glm::vec2 gaze);
// `rect` shifted by `jitter` layer pixels (each in [-0.5, 0.5], Guenter et al. 2012 4.2): where
// this frame's rays go. The history stays on the unjittered grid, so a still view accumulates the
// jittered samples of each layer pixel (a box-filtered, supersampled layer) instead of blurring
// them.
[[nodiscard]] LayerRect jittered(const LayerRect& rect, float pitch, glm::vec2 jitter);

// The frustum through `rect` of a view of `width` x `height` pixels spanning `view`.
[[nodiscard]] trace::FrustumTangents subFrustum(const trace::FrustumTangents& view, uint32_t width,
                                                uint32_t height, const LayerRect& rect);

// Frame `frame`'s whole-grid jitter in layer pixels, in [-0.5, 0.5)^2: the Halton (2, 3)
// sequence, a low-discrepancy sequence that covers the pixel evenly over frames.
[[nodiscard]] glm::vec2 layerJitter(uint64_t frame);
[[nodiscard]] float radicalInverse(uint64_t index, uint32_t base);

// The view's frustum as tangents (its off-axis frustum, or the symmetric one of its camera).
[[nodiscard]] trace::FrustumTangents tangentsOf(const shaders::trace::CameraPush& camera);

} // namespace gt::render
