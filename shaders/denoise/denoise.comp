#version 460
// Pass `denoise` (passes/denoise): the edge-avoiding a-trous wavelet transform of Dammertz et
// al. 2010 ("Edge-Avoiding A-Trous Wavelet Transform for fast Global Illumination Filtering"),
// with the luminance edge-stopping function scaled by the local standard deviation, as SVGF
// does (Schied et al. 2017, eqs. 3-5). The guides are the first hit's distance (the radiance's alpha), the normal
// derived from it, and luminance; the tracing passes write no normals or albedo. Each level blends the filtered colour with
// the pixel's own by its eccentricity from the gaze: nothing changes within the fovea, so
// its texture detail stays, and the periphery, where the points are sparse and the eye
// resolves little, is smoothed.
#extension GL_GOOGLE_include_directive : require
#include "denoise_shared.h"

layout(local_size_x = kGroupSizeX, local_size_y = kGroupSizeY) in;
layout(set = 0, binding = kBindingRadiance, rgba32f) uniform readonly image2D uRadiance;
layout(set = 0, binding = kBindingInput, rgba32f) uniform readonly image2D uInput;
layout(set = 0, binding = kBindingOutput, rgba32f) uniform writeonly image2D uOutput;
layout(set = 0, binding = kBindingGuide, rgba32f) uniform image2D uGuide;
layout(push_constant) uniform Push { DenoisePush pc; };

const float kDegrees = 57.29577951;

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// The direction of pixel p in the camera's frame, as trace.glsl's cameraRay builds it.
vec3 tangentOf(vec2 p) {
    float sx = (2.0 * p.x / pc.view.x - 1.0) * pc.frustum.x * pc.frustum.y + pc.frustum.z;
    float sy = (1.0 - 2.0 * p.y / pc.view.y) * pc.frustum.x + pc.frustum.w;
    return normalize(vec3(sx, sy, 1.0));
}

// How much of the filtered colour pixel p takes: 0 within the fovea, 1 past sigmas.w.
float strengthAt(ivec2 p) {
    vec3 d = tangentOf(vec2(p) + 0.5), g = tangentOf(pc.view.zw + 0.5);
    float ecc = acos(clamp(dot(d, g), -1.0, 1.0)) * kDegrees;
    return smoothstep(pc.sigmas.z, max(pc.sigmas.w, pc.sigmas.z + 1e-3), ecc);
}

// Where pixel p's first hit lies in the camera's frame (0 for the sky and past the edges).
vec3 positionOf(ivec2 p, ivec2 size) {
    if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))) return vec3(0.0);
    float z = imageLoad(uRadiance, p).a;
    return isinf(z) || z <= 0.0 ? vec3(0.0) : tangentOf(vec2(p) + 0.5) * z;
}

// The surface normal from the positions of the neighbours, each axis from the side whose depth
// is the closer, so that a silhouette does not tilt it (0 for the sky, or where a pixel has
// no neighbour hit along an axis: then the normal term does not apply).
vec3 normalOf(ivec2 p, ivec2 size) {
    vec3 c = positionOf(p, size);
    if (c == vec3(0.0)) return vec3(0.0);
    vec3 l = positionOf(p - ivec2(1, 0), size), r = positionOf(p + ivec2(1, 0), size);
    vec3 u = positionOf(p - ivec2(0, 1), size), d = positionOf(p + ivec2(0, 1), size);
    if ((l == vec3(0.0) && r == vec3(0.0)) || (u == vec3(0.0) && d == vec3(0.0))) return vec3(0.0);
    vec3 dx = (r == vec3(0.0) || (l != vec3(0.0) && abs(l.z - c.z) < abs(r.z - c.z))) ? c - l : r - c;
    vec3 dy = (d == vec3(0.0) || (u != vec3(0.0) && abs(u.z - c.z) < abs(d.z - c.z))) ? c - u : d - c;
    vec3 n = cross(dx, dy);
    return dot(n, n) > 0.0 ? normalize(n) : vec3(0.0);
}

// The first level's input: the colour and the variance of luminance over its 3x3 neighbours
// (SVGF's spatial estimate, for frames without a temporal history of moments).
vec4 withVariance(ivec2 p, ivec2 size) {
    float sum = 0.0, sumSq = 0.0;
    for (int y = -1; y <= 1; ++y) {
        for (int x = -1; x <= 1; ++x) {
            float l = luminance(imageLoad(uInput, clamp(p + ivec2(x, y), ivec2(0), size - 1)).rgb);
            sum += l;
            sumSq += l * l;
        }
    }
    float mean = sum / 9.0;
    return vec4(imageLoad(uInput, p).rgb, max(sumSq / 9.0 - mean * mean, 0.0));
}

// The geometry term: q lies on p's surface when its distance is the one q's ray would have to
// the plane through p's hit with p's normal (within sigma of p's distance: SVGF eq. 3 compares
// against the depth gradient, which this plane is, exact on a flat surface at any spacing),
// and it faces the same way (SVGF eq. 4's normal term, here from the depth image). Two sky
// pixels (no hit) are alike, a sky pixel and a surface are not.
float geometryWeight(vec4 gp, vec4 gq, vec3 hitP, vec3 rayQ) {
    bool skyP = isinf(gp.w) || gp.w <= 0.0, skyQ = isinf(gq.w) || gq.w <= 0.0;
    if (skyP || skyQ) return skyP == skyQ ? 1.0 : 0.0;
    bool known = dot(gp.xyz, gp.xyz) > 0.0 && dot(gq.xyz, gq.xyz) > 0.0;
    float normal = known ? pow(max(dot(gp.xyz, gq.xyz), 0.0), uintBitsToFloat(pc.step.z)) : 1.0;
    float facing = known ? dot(gp.xyz, rayQ) : 0.0;
    float expected = abs(facing) > 1e-3 ? dot(gp.xyz, hitP) / facing : gp.w;
    return normal * exp(-abs(gq.w - expected) / (pc.sigmas.y * gp.w + 1e-6));
}

// A tap past the image's edge, mirrored back into it (a skipped tap would leave the rows along
// the edge with fewer neighbours than the rest at the coarse levels).
ivec2 mirrored(ivec2 q, ivec2 size) {
    q = abs(q);
    return min(q, 2 * (size - 1) - q);
}

// One a-trous level: the 5x5 B3-spline kernel (1/16, 1/4, 3/8) at the level's spacing,
// weighted by geometry and by luminance against the pixel's standard deviation (its variance
// blurred over 3x3 first, SVGF eq. 5). The variance is the first level's at every level:
// SVGF filters it along with the colour, which assumes a temporally accumulated input; from
// a frame's few paths alone the filtered variance collapses after a level or two and the
// coarse levels would stop filtering in patches.
vec4 filterLevel(ivec2 p, ivec2 size, int spacing) {
    const float kernel[3] = float[3](3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0);
    vec4 centre = imageLoad(uInput, p), gp = imageLoad(uGuide, p);
    float lp = luminance(centre.rgb);
    vec3 hitP = tangentOf(vec2(p) + 0.5) * gp.w;
    float varBlur = 0.0;
    for (int y = -1; y <= 1; ++y) {
        for (int x = -1; x <= 1; ++x) {
            float g = (x == 0 ? 0.5 : 0.25) * (y == 0 ? 0.5 : 0.25);
            varBlur += g * imageLoad(uInput, clamp(p + ivec2(x, y), ivec2(0), size - 1)).a;
        }
    }
    float lumScale = pc.sigmas.x * sqrt(max(varBlur, 0.0)) + 1e-4;
    vec3 sum = vec3(0.0);
    float sumW = 0.0;
    for (int y = -2; y <= 2; ++y) {
        for (int x = -2; x <= 2; ++x) {
            ivec2 q = mirrored(p + ivec2(x, y) * spacing, size);
            vec4 c = imageLoad(uInput, q);
            float w = kernel[abs(x)] * kernel[abs(y)] *
                      geometryWeight(gp, imageLoad(uGuide, q), hitP, tangentOf(vec2(q) + 0.5)) *
                      exp(-abs(lp - luminance(c.rgb)) / lumScale);
            sum += w * c.rgb;
            sumW += w;
        }
    }
    // The centre's own weight is positive (its geometry and luminance terms are 1).
    return vec4(sum / sumW, centre.a);
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(pc.view.xy);
    if (any(greaterThanEqual(p, size))) return;
    if (pc.step.y == kStepVariance) {
        imageStore(uOutput, p, withVariance(p, size));
        imageStore(uGuide, p, vec4(normalOf(p, size), imageLoad(uRadiance, p).a));
        return;
    }
    vec4 own = imageLoad(uInput, p);
    vec4 filtered = filterLevel(p, size, int(pc.step.x));
    vec4 blended = mix(own, filtered, strengthAt(p));
    if (pc.step.y == kStepLast) blended.a = imageLoad(uRadiance, p).a;
    imageStore(uOutput, p, blended);
}
