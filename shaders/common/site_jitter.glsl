// Where point i of the set sits in frame f (point_sample traces around it, interpolate blends
// from it): frame 0 at the point itself (the thesis's fixed set); later frames at a position
// inside the point's own disc of radius `scale` * p, different every frame (a per-point
// Cranley-Patterson shift of the R2 low-discrepancy sequence). The Voronoi boundaries of a
// sparse set then land somewhere else each frame, and TAA's average over a still view turns
// their jagged staircase into the edge's coverage — the anti-aliasing the fixed set cannot
// give, since there every frame samples the same sites. The method picks the scale
// (PointSetMethod: kSiteJitterMoving, kSiteJitterStill).
#ifndef SITE_JITTER_GLSL
#define SITE_JITTER_GLSL
#include "random.glsl"

vec2 siteJitter(uint i, uint frame, float p, float scale) {
    if (frame == 0u || scale <= 0.0) return vec2(0.0);
    uint h = pcgHash(i * 0x2545F491u + 0x6A09E667u);
    vec2 u = fract(vec2(hashToFloat(h), hashToFloat(pcgHash(h)))
                   + float(frame) * vec2(0.7548776662, 0.5698402910));
    float a = 6.28318531 * u.y;
    return scale * p * sqrt(u.x) * vec2(cos(a), sin(a));
}
#endif
