#pragma once
// Everything one run of the renderer holds: the scene and its BVH on the GPU, the passes'
// pipelines, and (for the foveated method) the point set with its neighbour index. `render` and
// `bench` build frames through it, so both measure the same graphs.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "foveation/point_set.hpp"
#include "interpolate/interpolate.hpp"
#include "render_graph/render_graph.hpp"
#include "scene/bvh.hpp"
#include "scene/scene.hpp"

namespace gt::vk {
class Context;
}

namespace gt::app {

struct FrameResult {
    rg::FrameTimings timings;
    std::vector<uint8_t> pixels; // RGBA8 sRGB, empty unless asked for
    std::string dot;             // Graphviz of the compiled graph, when asked for
    double wallMs = 0.0;         // record + submit + wait (+ readback)
};

struct FoveatedSettings {
    glm::vec2 gaze{};
    uint32_t raysPerPoint = 32;
    passes::InterpolateSettings interpolation;
    bool taa = true;      // temporal anti-aliasing (the thesis used it in every setting)
    bool saccade = false; // the eye tracker reported a saccade: drop the TAA history
};

// The one-off cost of something built on the CPU for the interpolation settings (RBF's
// inverses, the per-pixel k-NN table) when they change.
struct Prepared {
    double ms = 0.0;
    double mb = 0.0;
};

class RenderSession {
public:
    RenderSession(const std::string& sceneSpec, bool validate);
    ~RenderSession();

    [[nodiscard]] vk::Context& context();
    [[nodiscard]] const scene::Scene& scene() const;
    // Replaces the scene's camera for the frames that follow (the TAA history assumes it stays).
    void setCamera(const scene::Camera& camera);
    [[nodiscard]] double loadMs() const noexcept { return mLoadMs; }
    [[nodiscard]] double bvhMs() const noexcept { return mBvhMs; }
    [[nodiscard]] const scene::BvhBuildStats& bvhStats() const;

    // Loads (or generates and caches) the point set and builds its neighbour index.
    void preparePointSet(const foveation::PointSetParams& params,
                         const std::filesystem::path& cacheDir);
    [[nodiscard]] const foveation::PointSet& pointSet() const;
    [[nodiscard]] double pointSetMs() const noexcept { return mPointSetMs; }
    [[nodiscard]] double neighbourIndexMs() const noexcept { return mNeighbourMs; }
    [[nodiscard]] double neighbourIndexMb() const noexcept { return mNeighbourMb; }
    [[nodiscard]] std::size_t pointsSampled(glm::vec2 gaze) const;

    // One frame: radiance -> tonemap (-> readback when `pixels`). Shaders are warmed up on
    // first use so no timed frame pays lavapipe's compile-at-first-dispatch.
    FrameResult reference(uint32_t w, uint32_t h, uint32_t spp, uint32_t seed, bool pixels,
                          bool dot = false);
    FrameResult foveated(const FoveatedSettings& s, bool pixels, bool dot = false);
    // For the RBF settings of the last foveated RBF frame.
    [[nodiscard]] Prepared rbfPrepared() const;
    // For the k of the last foveated frame that used the per-pixel k-NN table.
    [[nodiscard]] Prepared knnTablePrepared() const;

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
    double mLoadMs = 0.0, mBvhMs = 0.0, mPointSetMs = 0.0, mNeighbourMs = 0.0, mNeighbourMb = 0.0;
};

} // namespace gt::app
