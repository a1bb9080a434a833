#pragma once
// Guenter et al.'s method (Guenter et al. 2012): nested eccentricity layers at falling resolution
// around the gaze, sized by the linear MAR model and the layer optimisation of section 4.3
// (layer_layout), ray traced by pass `layers` as grids over their sub-frusta. As in section 4.2,
// each layer's grid is jittered every frame, blended with its own temporally reprojected history
// (pass `taa`, one history per layer), resampled bilinearly to the display and blended with
// smoothstep masks (Figure 3); the middle and outer layers are updated at half rate, staggered.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "foveation/eccentricity_layers.hpp"
#include "foveation_method.hpp"
#include "layer_layout.hpp"
#include "layers/layers.hpp"
#include "taa/taa.hpp"

namespace gt::render {

struct EccentricityLayerSettings {
    double slope = foveation::kSlopeA; // m of eq. (1): kSlopeA, kSlopeB or any positive value
    uint32_t layers = 3;               // n, 1..4 (the paper uses 3)
    // The inner layers' radii in degrees (n - 1, rising) instead of eq. (5)'s optimum; empty:
    // optimised. The pitch of each layer still follows eq. (2).
    std::vector<double> radiiDeg;
    uint32_t raysPerPixel = 1; // rays per layer pixel (the paper's MSAA)
    bool halfRate = true;      // layers 2.. at half the frame rate, staggered (section 4.3)
    bool jitter = true;        // whole-grid jitter by up to half a layer pixel (section 4.2)
    bool temporal = true;      // blend each layer with its reprojected history (section 4.2)
    float transition = 0.4f;   // smoothstep share of a layer's radius (Figure 3)
    // Geometric LOD (Guenter et al. 2012, 6): a layer sampled s display pixels apart traces the
    // scene's subdivision cages log2(s) refinement levels coarser (scene::lodForPitch); off: full
    // detail.
    bool lod = true;
    // The physical display the eye sees the view on (desktop: its size and viewing distance);
    // empty: the view's frustum is the eye's field of view (an HMD eye, an OpenXR view). A view
    // smaller than the profile is a window on that screen (windowProfile).
    std::optional<foveation::DisplayProfile> display;
    // The per-layer history blend while the layer moves (camera or gaze): reprojected, clipped
    // to the new frame's neighbourhood, the new frame weighing at least currentWeight. While a
    // layer's grid stays where it was, its history is exact: the new frame weighs 1 / (frames
    // averaged + 1), unclipped, so a still view averages every jittered sample evenly and
    // converges to the layer's box-filtered, supersampled image. The disocclusion tolerance
    // grows with the layer's pitch: the jitter moves a ray by up to half a layer pixel, along
    // which a grazing surface's distance changes that much.
    passes::TaaSettings taa{.currentWeight = 0.05f};
    uint32_t maxStillSamples = 256; // the still average's weight floor, 1 / 256
};

class EccentricityLayers final : public FoveationMethod {
public:
    explicit EccentricityLayers(const MethodContext& mc, EccentricityLayerSettings settings = {});
    [[nodiscard]] std::string_view name() const override { return "layers"; }
    [[nodiscard]] MethodImage addRadiance(rg::RenderGraph& graph, const View& view) override;
    [[nodiscard]] uint64_t rays(const View& view) const override;
    [[nodiscard]] std::optional<WarmUp> warmUp(const View& view) override;
    [[nodiscard]] bool accumulates() const override { return true; }
    void frameSubmitted() override;

    // The layers of `view` (computed once per view size and frustum).
    [[nodiscard]] const LayerLayout& layout(const View& view);
    // Which layers `view`'s last recorded frame traced (inner first).
    [[nodiscard]] std::vector<bool> tracedLastFrame(const View& view) const;

    [[nodiscard]] const EccentricityLayerSettings& settings() const noexcept { return mSettings; }

private:
    struct LayerState {
        LayerRect rect;
        shaders::trace::CameraPush camera{};
        bool valid = false;
        uint64_t traces = 0;  // frames this layer was traced: its own jitter index
        uint32_t samples = 0; // frames its history averages (see addRadiance)
    };
    struct ViewState {
        uint64_t frame = 0; // frames of this view committed so far
        glm::vec2 gaze{};
        bool known = false;
        std::vector<LayerState> layers;
    };
    struct Pending {
        ViewState state;
        std::vector<bool> traced;
        uint64_t rays = 0;
    };
    // Size and frustum tangents to 1e-4: a runtime's per-frame float noise in its field of view
    // must not re-optimise the layers every frame.
    using LayoutKey = std::tuple<uint32_t, uint32_t, long, long, long, long>;

    MethodContext mMc;
    EccentricityLayerSettings mSettings;
    passes::LayersPass mPass;
    passes::TaaPass mTaa;
    std::map<LayoutKey, LayerLayout> mLayouts;
    std::map<std::string, ViewState> mViews;
    std::map<std::string, Pending> mPending;
    std::map<std::string, Pending> mLast; // the last recorded frame's, for rays() and tests
    bool mWarm = false;
};

} // namespace gt::render
