#version 460
// Pass `point_denoise`, its temporal step (passes/point_denoise): each point's demodulated light
// blended with the history of the surface it hits, before the spatial steps filter it. SVGF
// (Schied et al. 2017, section 4.1) does this on the pixel grid. Without it, the spatial filter
// smooths each frame's few paths into a different low-frequency pattern every frame: the
// periphery flickers in a moving view, and TAA, which clips its history to the current frame's
// neighbourhood, cannot hold a smooth pattern that moves.
//
// The points move with the gaze and their sites jitter, so there is no history per point
// index. The point's first hit is carried into last frame's camera and projected onto last
// frame's screen, and the history there belongs to the point of last frame's set nearest that
// position (the set's nearest-point table, through last frame's gaze offset). It is accepted
// when that point's hit lies on this point's surface plane (within the spatial steps' depth
// tolerance), no more than a few spacings away, and faces the same way (SVGF's consistency
// tests). The blend is the running mean until 1 / alpha frames have gathered, then an
// exponential average of weight alpha; the variance of the accumulated luminance follows from
// the per-frame variance of the point's paths and the blend weights (the sum of their
// squares), so the spatial steps filter less where the history has already averaged.
// Within the fovea nothing is blended: its samples stay as traced (TAA keeps its history).
#extension GL_GOOGLE_include_directive : require
#include "point_denoise_shared.h"
#include "point_guide.glsl"
#include "point_site.glsl"

layout(local_size_x = kGroupSize) in;
layout(set = 0, binding = kBindingPoints) uniform samplerBuffer uPoints;
layout(set = 0, binding = kBindingTemporalNearest) uniform usamplerBuffer uNearest;
layout(set = 0, binding = kBindingTemporalNeighbours) uniform usamplerBuffer uNeighbours;
layout(std430, set = 0, binding = kBindingSamples) readonly buffer Samples { vec4 samples[]; };
layout(std430, set = 0, binding = kBindingGuide) readonly buffer Guide { vec4 guide[]; };
layout(std430, set = 0, binding = kBindingTemporalOutput) writeonly buffer Output { vec4 outputs[]; };
layout(set = 0, binding = kBindingHistoryLight, rgba32f) uniform readonly image2D uHistoryLight;
layout(set = 0, binding = kBindingHistoryHit, rgba32ui) uniform readonly uimage2D uHistoryHit;
layout(set = 0, binding = kBindingNextLight, rgba32f) uniform writeonly image2D uNextLight;
layout(set = 0, binding = kBindingNextHit, rgba32ui) uniform writeonly uimage2D uNextHit;
layout(set = 0, binding = kBindingHistoryAlbedo, r32ui) uniform readonly uimage2D uHistoryAlbedo;
layout(set = 0, binding = kBindingNextAlbedo, r32ui) uniform writeonly uimage2D uNextAlbedo;
layout(std430, set = 0, binding = kBindingTemporalGuide) writeonly buffer GuideOut { vec4 guideOut[]; };
layout(push_constant) uniform Push { PointTemporalPush pc; };

const float kDepthSigma = 0.05;     // PointDenoiseSettings::sigmaDepth's default
const float kMinNormalCos = 0.9;   // about 25 degrees
const float kReachSpacings = 3.0;   // how far the history's hit may lie, in spacings
const uint kHistoryCandidates = 6u; // the nearest point's neighbours read beside it

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

ivec2 historyTexel(uint i) { return ivec2(i % kHistoryWidth, i / kHistoryWidth); }

// The normal (octahedral, 12 bits an axis) and the frame count in one word.
uint packNormalCount(vec3 n, uint count) {
    vec2 e = clamp(octEncode(n) * 0.5 + 0.5, 0.0, 1.0); // the sky's (2, 2) clamps to (1, 1)
    uvec2 q = uvec2(round(e * 4095.0));
    return (q.x << 20u) | (q.y << 8u) | min(count, kHistoryMaxFrames);
}

vec3 unpackNormal(uint w) {
    vec2 e = vec2(uvec2(w >> 20u, (w >> 8u) & 4095u)) / 4095.0 * 2.0 - 1.0;
    return octDecode(e);
}

// The accumulated albedo at 10 bits a channel: at 8, a blend of weight alpha stops short of a
// new value within 2.5 / 255 of it.
uint packAlbedo(vec3 a) {
    uvec3 q = uvec3(round(clamp(a, 0.0, 1.0) * 1023.0));
    return q.r | (q.g << 10u) | (q.b << 20u);
}

vec3 unpackAlbedo(uint w) { return vec3(w & 1023u, (w >> 10u) & 1023u, w >> 20u) / 1023.0; }

vec3 toPrevious(vec3 p, float w) {
    vec4 q = vec4(p, w);
    return vec3(dot(pc.toPrevious0, q), dot(pc.toPrevious1, q), dot(pc.toPrevious2, q));
}

// One of last frame's points as a candidate for the history of the surface at hitThen (last
// frame's camera frame, normal nThen): its weight, 0 where it fails SVGF's consistency tests.
float candidateWeight(uint j, vec3 hitThen, vec3 nThen, float depth, float spacing, float pixel,
                      out uvec4 h) {
    h = imageLoad(uHistoryHit, historyTexel(j));
    if ((h.w & 255u) == 0u) return 0.0;
    vec3 hitJ = uintBitsToFloat(h.xyz);
    float d = distance(hitJ, hitThen) / pixel; // pixels
    bool near = d <= kReachSpacings * spacing;
    bool onPlane = abs(dot(nThen, hitJ - hitThen)) <= kDepthSigma * depth;
    bool facing = dot(nThen, unpackNormal(h.w)) >= kMinNormalCos;
    if (!near || !onPlane || !facing) return 0.0;
    float sigma = 0.35 * spacing;
    return exp(-d * d / (2.0 * sigma * sigma));
}

// Last frame's history of the surface at `hit` (this camera's frame, normal n, spacing in
// pixels): over the point of last frame's set nearest where the hit was seen and that point's
// stored neighbours, those that pass the consistency tests, weighted by a Gaussian of their
// hits' distance (half a spacing). One point alone would hand each point the history of
// whichever was nearest, and as the set shifts with the gaze that choice jumps. count 0
// where none passes.
void historyOf(vec3 hit, vec3 n, float depth, float spacing, out vec4 prevLight,
               out vec3 prevAlbedo, out uint prevCount) {
    prevCount = 0u;
    vec3 hitThen = toPrevious(hit, 1.0), nThen = toPrevious(n, 0.0);
    if (hitThen.z <= 0.0) return;
    vec2 size = vec2(pc.params.xy);
    ivec2 c = ivec2(floor(imageOf(hitThen, size, pc.frustum) - pc.previous.xy));
    ivec2 canvas = ivec2(pc.params.w & 0xffffu, pc.params.w >> 16u);
    if (any(lessThan(c, ivec2(0))) || any(greaterThanEqual(c, canvas))) return;
    uint nearest = texelFetch(uNearest, c.y * canvas.x + c.x).r;
    if (nearest >= pc.params.z) return;
    // The footprint of a pixel at this distance, along the view axis (enough for a bound).
    float pixel = depth * 2.0 * pc.frustum.x / size.y;
    spacing = max(spacing, 1.0);
    uint stored = uint(pc.previous.w) - 1u;
    vec4 light = vec4(0.0);
    vec3 albedo = vec3(0.0);
    float count = 0.0, sumW = 0.0;
    bool unknown = false;
    for (uint k = 0u; k <= min(stored, kHistoryCandidates); ++k) {
        uint j = k == 0u ? nearest : texelFetch(uNeighbours, int(nearest * stored + k - 1u)).r;
        uvec4 h;
        float w = candidateWeight(j, hitThen, nThen, depth, spacing, pixel, h);
        if (w <= 0.0) continue;
        vec4 l = imageLoad(uHistoryLight, historyTexel(j));
        unknown = unknown || l.a < 0.0;
        light += w * l;
        albedo += w * unpackAlbedo(imageLoad(uHistoryAlbedo, historyTexel(j)).r);
        count += w * float(h.w & 255u);
        sumW += w;
    }
    if (sumW <= 1e-6) return;
    prevLight = vec4(light.rgb / sumW, unknown ? -1.0 : light.a / sumW);
    prevAlbedo = albedo / sumW;
    prevCount = max(uint(count / sumW + 0.5), 1u);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.params.z) return;
    vec4 p = texelFetch(uPoints, int(i));
    vec2 site;
    if (!pointSite(i, p, pc.offset, vec2(pc.params.xy), site)) {
        imageStore(uNextHit, historyTexel(i), uvec4(0u)); // nothing of it survives a frame off
        return;
    }
    PointGuide g = decodePointGuide(guide[i]);
    float scale = luminance(g.albedo);
    vec3 light = samples[i].rgb / g.albedo;
    float variance = g.variance / (scale * scale); // < 0: unknown (one ray)
    float depth = samples[i].w;
    vec2 size = vec2(pc.params.xy);
    vec3 dir = imageTangent(site, size, pc.frustum);
    float strength = filterStrength(dir, imageTangent(pc.gaze.xy, size, pc.frustum), pc.gaze.zw);
    vec4 prevLight;
    vec3 prevAlbedo;
    uint prevCount = 0u;
    bool surface = !isSky(depth) && dot(g.normal, g.normal) > 0.0;
    if (surface && strength > 0.0 && pc.previous.w > 0.0) { // w: stored neighbours + 1
        historyOf(dir * depth, g.normal, depth, p.z, prevLight, prevAlbedo, prevCount);
    }
    uint count = prevCount + 1u;
    // The running mean, then the exponential average, by eccentricity: the fovea takes none.
    float alpha = mix(1.0, max(1.0 / float(count), pc.previous.z), strength);
    vec3 accumulated = prevCount > 0u ? mix(prevLight.rgb, light, alpha) : light;
    // The albedo too: a sparse point's jittered hit lands on another texel of a texture every
    // frame, and remodulated by each frame's own it would flicker with the texture's contrast.
    vec3 albedo = prevCount > 0u ? mix(prevAlbedo, g.albedo, alpha) : g.albedo;
    vec4 ownGuide = guide[i];
    guideOut[i] = vec4(ownGuide.xy,
                       prevCount > 0u ? uintBitsToFloat(packUnorm4x8(vec4(albedo, 0.0))) : ownGuide.z,
                       ownGuide.w);
    imageStore(uNextAlbedo, historyTexel(i), uvec4(packAlbedo(albedo)));
    // Unknown for a point of one ray; a history without it restarts from this frame's.
    bool known = variance >= 0.0;
    float frameVariance =
        known && prevCount > 0u && prevLight.a >= 0.0 ? mix(prevLight.a, variance, alpha) : variance;
    // The accumulated estimate's variance: the sum of the squared frame weights (1 / n for the
    // running mean, alpha / (2 - alpha) for the exponential average).
    float weights = max(1.0 / float(count), alpha / (2.0 - alpha));
    outputs[i] = vec4(accumulated, known ? frameVariance * weights : -1.0);
    imageStore(uNextLight, historyTexel(i), vec4(accumulated, known ? frameVariance : -1.0));
    imageStore(uNextHit, historyTexel(i),
               surface ? uvec4(floatBitsToUint(dir * depth), packNormalCount(g.normal, count))
                       : uvec4(0u));
}
