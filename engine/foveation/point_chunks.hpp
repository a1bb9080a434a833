#pragma once
// The point set cut into chunks of consecutive points, each with its canvas bounds, so that
// point_sample dispatches only the chunks that can land on screen. The set is stored in Morton
// order of its points' pixels (point_set.hpp), so consecutive points are neighbours on the
// canvas and a chunk covers a compact patch: the invocations of one workgroup trace neighbouring
// rays, and a chunk far off screen is skipped whole instead of idling its SIMD lanes. Only the
// dispatch changes: a point keeps its index, and with it its rays (point_sample.comp).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "foveation/point_set.hpp"

namespace gt::foveation {

class PointChunks {
public:
    // Points per chunk: point_sample's workgroup size (foveated_shared.h, kSampleGroupSize).
    static constexpr uint32_t kPoints = 64;

    explicit PointChunks(const PointSet& set);

    // The chunks, in index order, holding a point that may land inside the screen (W x H) plus
    // `margin` once shifted by the canvas -> screen `offset` (sample_canvas.hpp) and moved by
    // up to `siteMove` times its spacing (site_jitter.glsl). Conservative: a chunk is kept when
    // its bounds reach the screen, and one more pixel absorbs the shader's float rounding.
    [[nodiscard]] std::vector<uint32_t> onScreen(glm::vec2 offset, uint32_t width, uint32_t height,
                                                 float margin, float siteMove) const;

    [[nodiscard]] uint32_t count() const noexcept { return static_cast<uint32_t>(mBounds.size()); }

private:
    struct Bounds {
        glm::vec2 lo, hi; // canvas pixels
        float maxSpacing; // the largest p in the chunk
    };
    std::vector<Bounds> mBounds;
};

} // namespace gt::foveation
