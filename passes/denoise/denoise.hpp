#pragma once
// Pass `denoise`: the edge-avoiding a-trous wavelet filter (Dammertz et al. 2010) with SVGF's
// variance-scaled luminance weights (Schied et al. 2017), guided by the first hit's distance,
// applied more the farther a pixel lies from the gaze (none within the fovea). For the path
// integrator's few paths per pixel or point; shaders/denoise/denoise.comp has the maths.
#include <cstdint>
#include <memory>

#include <glm/glm.hpp>

#include "render_graph/render_graph.hpp"
#include "trace_shared.h"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk

namespace gt::passes {

// Where the path tracer's noise is filtered: on the reconstructed image (this pass), on a point
// set's samples before interpolation (pass point_denoise), or both. Methods that trace no
// point set always filter their image.
enum class DenoisePlacement : uint8_t { Image, Points, Both };

struct DenoiseSettings {
    // A-trous levels, spacing 1, 2, 4, ...: 5 levels reach 2 * 16 = 32 pixels each way.
    uint32_t levels = 5;
    float sigmaLuminance = 4.0f; // luminance difference, in local standard deviations
    // A neighbour's first-hit distance off the plane of the pixel's surface, relative to the
    // pixel's distance.
    float sigmaDepth = 0.05f;
    float normalPower = 8.0f; // (n_p . n_q)^power, as SVGF's sigma_n (it uses 128)
    // No filtering below this eccentricity (degrees): the fovea keeps its detail.
    float foveaDeg = 5.0f;
    float fullDeg = 15.0f; // full strength from here (a smooth ramp between)
    // Read by the renderer and the point-set method, not by this pass. Both: the points with
    // their history, then the image, is the one placement that flickers less than the
    // full-resolution tracer in every band walking through the market and leaves a sharper
    // periphery than the image alone (docs/path-tracing.md, "Denoising on the points").
    DenoisePlacement placement = DenoisePlacement::Both;
    // The point filter's temporal step: the current frame's weight once a point's history
    // holds 1 / alpha frames (SVGF's 0.2); 0: each frame's points filtered on their own.
    float pointTemporalAlpha = 0.2f;

    friend bool operator==(const DenoiseSettings&, const DenoiseSettings&) = default;
};

class DenoisePass {
public:
    explicit DenoisePass(vk::Context& ctx);
    ~DenoisePass();
    // Adds "denoise.variance" and "denoise.level0".. reading `radiance` (rgb, a = first-hit
    // distance, as the methods make it) and returns a new texture of the same layout, the rgb
    // filtered. `camera` and `gaze` (pixels) place each pixel's eccentricity. Throws
    // gt::ArgumentError for 0 levels or a spacing past 2^15.
    rg::TextureId add(rg::RenderGraph& graph, rg::TextureId radiance,
                      const shaders::trace::CameraPush& camera, glm::vec2 gaze,
                      const DenoiseSettings& settings) const;

private:
    vk::Context& mCtx;
    std::unique_ptr<vk::ComputePipeline> mPipeline;
};

} // namespace gt::passes
