#pragma once
// A view: one image the renderer makes per frame — the desktop window, one eye of an HMD, one
// OpenXR view. Every view of a frame is rendered in the same render graph, each under its own
// name scope, with its own camera, size, gaze, foveation method and temporal history.
#include <cstdint>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "denoise/denoise.hpp"
#include "display/hmd_profile.hpp"
#include "scene/scene.hpp"
#include "taa/taa.hpp"
#include "trace/gpu_scene.hpp"

namespace gt::render {

class FoveationMethod;

// An HMD eye's lens: pass `lens` pre-distorts the tone-mapped image (engine/display).
struct LensSettings {
    display::LensModel model;
    glm::vec2 centre{0.5f}; // where the optical axis meets the image, normalised, y down
};

// The chain after the method: (denoise) -> taa -> tonemap -> (lens) -> the view's output target.
struct PostSettings {
    // The spatial denoiser for few paths per pixel or point (pass `denoise`); none: off. Not
    // on a panel-space image (a lens method's), whose pixels are not the view's.
    std::optional<passes::DenoiseSettings> denoise;
    bool taa = true; // temporal anti-aliasing (thesis, 4.3: the thesis used it throughout)
    passes::TaaSettings taaSettings;
    std::optional<LensSettings> lens;
};

struct View {
    // Graph scope of the view's passes and resources ("left" -> "left.taa"); empty for a lone
    // view, whose passes keep their plain names. Also the key of its history.
    std::string name;
    scene::Camera camera; // pose; camera.yfov is the vertical field of view when symmetric
    // An off-axis frustum (an HMD eye, an OpenXR view's XrFovf); empty: symmetric, from
    // camera.yfov and the view's aspect.
    std::optional<trace::FrustumTangents> frustum;
    uint32_t width = 0, height = 0;
    glm::vec2 gaze{};     // pixels, origin top-left, pixel centres at integers
    bool saccade = false; // the eye tracker saw a saccade since the last frame: drop history
    FoveationMethod* method = nullptr;
    PostSettings post;
    float exposure = 1.0f;

    // The camera as the tracing passes take it.
    [[nodiscard]] shaders::trace::CameraPush cameraPush() const;
};

} // namespace gt::render
