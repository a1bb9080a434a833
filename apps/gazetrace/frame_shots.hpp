#pragma once
// One view of a renderer rendered and read back, frame by frame: what the picture-quality
// measurements (`eval`, `bench --suite layers`) compare.
#include <cstdint>
#include <string>
#include <vector>

#include "output_target.hpp"
#include "render_graph/render_graph.hpp"
#include "renderer.hpp"
#include "view.hpp"

namespace gt::app {

class FrameShots {
public:
    explicit FrameShots(render::Renderer& r) : mRenderer(r), mReadback(r.context()) {}
    // Renders `v` with `m` (at the scene's exposure); RGBA8 sRGB, rows top first. `rays`, if
    // given, receives the primary rays traced.
    std::vector<uint8_t> shot(render::View v, render::FoveationMethod& m, uint64_t* rays = nullptr);
    // GPU ms of the last frame's passes whose names contain `part` ("trace", "point_sample").
    [[nodiscard]] double lastPassMs(const std::string& part) const;

private:
    rg::FrameTimings mLast;
    render::Renderer& mRenderer;
    render::ReadbackTarget mReadback;
};

} // namespace gt::app
