#pragma once
// A CPU implementation of the tracer's shading, written independently of the GLSL but to the
// same rules, so the GPU output can be checked against it (tests/gpu/tracer_test.cpp):
// - camera rays through stratified jittered positions in each pixel (`sampleOffset`),
// - closest hit through the BVH, passing through alpha-masked texels, two-sided shading normals,
// - base colour (factor x bilinear sRGB texture), emissive; an unlit material shows its base
//   colour only,
// - direct light from punctual lights with shadow rays (KHR_lights_punctual falloff),
// - ambient light from the sky, one mirror bounce weighted by metallic,
// - the sky gradient for rays that miss.
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "scene/bvh.hpp"
#include "scene/scene.hpp"
#include "trace/gpu_scene.hpp"

namespace gt::trace {

struct TraceSettings {
    uint32_t width = 0;
    uint32_t height = 0;
    uint32_t raysPerPixel = 1;
    uint32_t frameSeed = 0;
    // Off-axis frustum (an HMD eye); empty: the scene camera's symmetric one.
    std::optional<FrustumTangents> frustum;
};

[[nodiscard]] uint32_t pcgHash(uint32_t v) noexcept;
// Offset in [0,1)^2 of ray `sample` of `count` inside a pixel: a sx x sy grid of strata
// (sx = ceil(sqrt(count))) with one jittered position in each.
[[nodiscard]] glm::vec2 sampleOffset(uint32_t pixelIndex, uint32_t sample, uint32_t count,
                                     uint32_t frameSeed) noexcept;

class CpuTracer {
public:
    CpuTracer(const scene::Scene& scene, const scene::Bvh& bvh);
    // The alpha test refers to this tracer, so a copy would point back at the original.
    CpuTracer(const CpuTracer&) = delete;
    CpuTracer& operator=(const CpuTracer&) = delete;
    [[nodiscard]] glm::vec3 radiance(const scene::Ray& ray) const;
    [[nodiscard]] glm::vec3 sky(glm::vec3 direction) const;
    // Linear radiance per pixel, row-major, top row first.
    [[nodiscard]] std::vector<glm::vec4> render(const TraceSettings& settings) const;

private:
    [[nodiscard]] glm::vec4 baseColor(uint32_t material, glm::vec2 uv) const;
    const scene::Scene& mScene;
    const scene::Bvh& mBvh;
    scene::Bvh::HitFilter mAlphaTest; // empty when no material is alpha-masked
};

} // namespace gt::trace
