// What the point denoiser's steps (point_denoise.comp, point_temporal.comp) share: where
// point_sample placed a point this frame, the ray through a screen position, and how much a
// point is filtered at its eccentricity.
#ifndef POINT_SITE_GLSL
#define POINT_SITE_GLSL
#include "site_jitter.glsl"

const float kDegrees = 57.29577951;

// Point i (p: canvas x, y, spacing) on screen this frame, jitter included (offset as
// PointDenoisePush::offset), and whether point_sample traced it: the same test, so a point it
// skipped is never read.
bool pointSite(uint i, vec4 p, vec4 offset, vec2 size, out vec2 site) {
    float field = floor(offset.w);
    site = p.xy + offset.xy + siteJitter(i, uint(field), p.z, 2.0 * (offset.w - field));
    return all(greaterThanEqual(site, vec2(-offset.z))) && all(lessThan(site, size + offset.z));
}

// The direction through image position q in the camera's frame (x right, y up, z forward), as
// trace.glsl's cameraRay builds it (frustum as trace::CameraPush's w components).
vec3 imageTangent(vec2 q, vec2 size, vec4 frustum) {
    float sx = (2.0 * q.x / size.x - 1.0) * frustum.x * frustum.y + frustum.z;
    float sy = (1.0 - 2.0 * q.y / size.y) * frustum.x + frustum.w;
    return normalize(vec3(sx, sy, 1.0));
}

// The image position a direction in the camera's frame passes through (imageTangent's inverse).
vec2 imageOf(vec3 d, vec2 size, vec4 frustum) {
    vec2 t = d.xy / d.z;
    return vec2(((t.x - frustum.z) / (frustum.x * frustum.y) + 1.0) * 0.5 * size.x,
                (1.0 - (t.y - frustum.w) / frustum.x) * 0.5 * size.y);
}

// How much of the filtered value a point in direction `dir` takes when the gaze lies along
// `gazeDir`: 0 below degrees.x, 1 from degrees.y, a smooth ramp between.
float filterStrength(vec3 dir, vec3 gazeDir, vec2 degrees) {
    float ecc = acos(clamp(dot(dir, gazeDir), -1.0, 1.0)) * kDegrees;
    return smoothstep(degrees.x, max(degrees.y, degrees.x + 1e-3), ecc);
}

bool isSky(float depth) { return isinf(depth) || depth <= 0.0; }

#endif
