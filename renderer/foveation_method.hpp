#pragma once
// How a view's radiance is made: every pixel traced (full resolution), a perceptual point set
// traced and interpolated (the thesis), or nested eccentricity layers (Guenter et al. 2012). The
// renderer adds a method's passes per view and runs the post chain on what it returns.
#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>

#include "render_graph/render_graph.hpp"

namespace gt::vk {
class Context;
}
namespace gt::trace {
class GpuScene;
}

namespace gt::render {

struct View;

// What a method needs from the renderer: the device, the scene on it, and the renderer's
// history pool for what a method keeps from frame to frame itself (its names live in the view's
// scope, so Renderer::resetHistory(view) drops them too).
struct MethodContext {
    vk::Context& ctx;
    const trace::GpuScene& scene;
    rg::HistoryPool& history;
};

// An untimed frame through the pipelines a timed frame will use: lavapipe compiles a pipeline at
// its first dispatch (14-147 ms), which must not land in a measured frame.
struct WarmUp {
    uint32_t width = 0, height = 0;
    std::function<rg::TextureId(rg::RenderGraph&)> addRadiance;
};

// A method's frame: the linear radiance (rgb; a = first-hit distance, which TAA reprojects
// with) and, from a method that rebuilds the image from sparse samples, per pixel the distance
// to the sample it took most from in units of the sample spacing (passes::InterpolatedImage):
// on a still view TAA then counts each frame most where that frame's samples fell. In a scene
// that moves (trace::GpuScene::dynamic()), per pixel the first hit's motion (rgba32f, xyz =
// world position one frame ago minus now, w = the signature code of shaders/common/motion.glsl),
// which TAA reprojects with and rejects history by.
struct MethodImage {
    MethodImage(rg::TextureId r, std::optional<rg::TextureId> s = std::nullopt, // NOLINT
                std::optional<rg::TextureId> m = std::nullopt)
        : radiance(r), support(s), motion(m) {}
    rg::TextureId radiance;
    std::optional<rg::TextureId> support;
    std::optional<rg::TextureId> motion;
};

class FoveationMethod {
public:
    virtual ~FoveationMethod() = default;
    [[nodiscard]] virtual std::string_view name() const = 0;
    // Adds the passes that make the view's image (MethodImage) at the view's size, and returns
    // it.
    [[nodiscard]] virtual MethodImage addRadiance(rg::RenderGraph& graph, const View& view) = 0;
    // Primary rays traced for the view this frame.
    [[nodiscard]] virtual uint64_t rays(const View& view) const = 0;
    // Once per pipeline variant: the frame that compiles it. Empty when this view's variant has
    // run before. Called before the frame is recorded; also builds what the settings need.
    [[nodiscard]] virtual std::optional<WarmUp> warmUp(const View& view) = 0;
    // The radiance is already what the view's HMD panel shows (the point set laid on the panel,
    // display_space.hpp): the post chain applies only the residual chromatic shift of the lens,
    // and no TAA (its reprojection assumes the image's pinhole projection).
    [[nodiscard]] virtual bool rendersPanel(const View& view) const {
        (void)view;
        return false;
    }
    // Where the method traces follows the gaze (a point set shifted to it): with the camera
    // still and the gaze moving, TAA then leans on the history away from the gaze.
    [[nodiscard]] virtual bool gazeDependent() const { return false; }
    // The method blends its own temporal history (eccentricity layers, one per layer): the post
    // chain then runs no TAA of its own.
    [[nodiscard]] virtual bool accumulates() const { return false; }
    // The method filtered its own samples for `view`'s denoiser (DenoisePlacement::Points or
    // Both): with Points the post chain then skips the image denoiser.
    [[nodiscard]] virtual bool denoisesPoints(const View& view) const {
        (void)view;
        return false;
    }
    // The frame last recorded was submitted: what the method kept for the next frame is now
    // what the history holds. (A frame that fails before its submit does not call this.)
    virtual void frameSubmitted() {}
};

} // namespace gt::render
