#version 460
// Pass `point_denoise` (passes/point_denoise): the path tracer's few paths per point filtered on
// the points themselves, before interpolation. A sparse point's sample stands for every pixel
// its Voronoi cell covers, so its noise is a blotch of that size in the image; a filter on the
// image sees neighbouring pixels that share one sample, takes the blotch for detail and keeps
// it. On the points each sample's neighbours are independent paths.
//
// The filter is SVGF's (Schied et al. 2017) on the set's neighbour graph instead of the pixel
// grid: each step blends a point with its k nearest (the neighbour index's lists) by a Gaussian
// in their distance relative to the point's spacing, times SVGF's edge-stopping weights on the
// first hit's normal (eq. 4), on its distance off the point's surface plane (eq. 3, from the
// normal), and on luminance against the point's standard deviation (eq. 5). The variance is
// each point's own, from its paths (point_sample), blurred over its neighbours first and
// carried through the steps by the squared weights (SVGF 4.3). The filter works on the light
// with the first hit's albedo divided out, and multiplies it back at the end, so texture
// detail is never averaged. Repeated steps widen the reach by the square root of their number.
// As the image denoiser, each step blends in the filtered value by eccentricity: the fovea's
// samples stay as traced.
#extension GL_GOOGLE_include_directive : require
#include "point_denoise_shared.h"
#include "panel_warp.glsl"
#include "point_guide.glsl"
#include "point_site.glsl"

layout(local_size_x = kGroupSize) in;
layout(set = 0, binding = kBindingPoints) uniform samplerBuffer uPoints;
layout(set = 0, binding = kBindingNeighbours) uniform usamplerBuffer uNeighbours;
layout(std430, set = 0, binding = kBindingSamples) readonly buffer Samples { vec4 samples[]; };
layout(std430, set = 0, binding = kBindingGuide) readonly buffer Guide { vec4 guide[]; };
layout(std430, set = 0, binding = kBindingInput) readonly buffer Input { vec4 light[]; };
layout(std430, set = 0, binding = kBindingOutput) writeonly buffer Output { vec4 outputs[]; };
layout(push_constant) uniform Push { PointDenoisePush pc; };

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// Point i's site this frame on screen, its spacing, and whether point_sample traced it.
bool siteOf(uint i, out vec2 site, out float spacing) {
    vec4 p = texelFetch(uPoints, int(i));
    spacing = p.z;
    return pointSite(i, p, pc.offset, vec2(pc.params.xy), site);
}

// The direction of screen position s in the camera's frame (x right, y up, z forward), through
// the panel warp when the set is laid on a panel, as point_sample's rays leave.
vec3 tangentOf(vec2 s) {
    vec2 size = vec2(pc.params.xy);
    return imageTangent(panelToImage(s, size, pc.lens, pc.lensCoeffs), size, pc.frustum);
}

// How much of the filtered value point i takes: 0 within the fovea, 1 past sigmas.w.
float strengthAt(vec3 dir) { return filterStrength(dir, tangentOf(pc.gaze.xy), pc.sigmas.zw); }

// SVGF's geometry weights between point i (hit at hitI with normal nI, distance dI) and
// neighbour j: j's hit must lie on i's surface plane within sigma of i's distance and face
// the same way. Two sky points are alike; a sky point and a surface are not.
float geometryWeight(vec3 hitI, vec3 nI, float dI, vec3 hitJ, vec3 nJ, float dJ) {
    bool skyI = isSky(dI), skyJ = isSky(dJ);
    if (skyI || skyJ) return skyI == skyJ ? 1.0 : 0.0;
    bool known = dot(nI, nI) > 0.0 && dot(nJ, nJ) > 0.0;
    float normal = known ? pow(max(dot(nI, nJ), 0.0), pc.gaze.z) : 1.0;
    float offPlane = known ? abs(dot(nI, hitJ - hitI)) : abs(dJ - dI);
    return normal * exp(-offPlane / (pc.sigmas.y * dI + 1e-6));
}

struct Tap {
    bool traced;
    vec2 site;
    vec3 hit, normal;
    float depth;
};

Tap tapOf(uint i) {
    Tap t;
    float spacing;
    t.traced = i < pc.params.z && siteOf(i, t.site, spacing);
    if (!t.traced) return t;
    t.depth = samples[i].w;
    t.hit = isSky(t.depth) ? vec3(0.0) : tangentOf(t.site) * t.depth;
    t.normal = decodePointGuide(guide[i]).normal;
    return t;
}

uint neighbourOf(uint i, uint j) { return texelFetch(uNeighbours, int(i * pc.params.w + j)).r; }

// Point n's light with its first hit's albedo divided out, and the variance of its luminance
// (< 0: unknown): from its samples, or as point_temporal accumulated them over frames.
vec4 lightOf(uint n) {
    if (pc.step.z == kInputTemporal) return light[n];
    PointGuide g = decodePointGuide(guide[n]);
    float scale = luminance(g.albedo);
    return vec4(samples[n].rgb / g.albedo, g.variance / (scale * scale));
}

// The demodulated light and its luminance variance: the point's own, or where that is unknown
// (one ray, no history), its neighbours' spread (SVGF's spatial fallback); then blurred over
// the neighbours on the same surface.
vec4 demodulated(uint i, Tap self) {
    vec4 own = lightOf(i);
    float sumVar = own.a, sumW = 1.0;
    float sum = luminance(own.rgb), sumSq = sum * sum, count = 1.0;
    for (uint j = 0u; j < pc.step.x; ++j) {
        uint n = neighbourOf(i, j);
        Tap t = tapOf(n);
        if (!t.traced) continue;
        vec4 other = lightOf(n);
        float w = geometryWeight(self.hit, self.normal, self.depth, t.hit, t.normal, t.depth);
        sumVar += w * other.a;
        sumW += w;
        float l = luminance(other.rgb);
        sum += l;
        sumSq += l * l;
        count += 1.0;
    }
    float spread = max(sumSq / count - (sum / count) * (sum / count), 0.0);
    return vec4(own.rgb, own.a < 0.0 ? spread : max(sumVar / sumW, 0.0));
}

// One step over the neighbour graph (see the top).
vec4 filtered(uint i, Tap self, float spacing) {
    vec4 centre = light[i];
    float lumScale = pc.sigmas.x * sqrt(centre.a) + 1e-4;
    float lc = luminance(centre.rgb);
    float sigma = pc.gaze.w * spacing;
    vec3 sum = centre.rgb;
    float sumW = 1.0, sumVar = centre.a;
    for (uint j = 0u; j < pc.step.x; ++j) {
        uint n = neighbourOf(i, j);
        Tap t = tapOf(n);
        if (!t.traced) continue;
        vec4 c = light[n];
        vec2 d = t.site - self.site;
        float w = exp(-dot(d, d) / (2.0 * sigma * sigma)) *
                  geometryWeight(self.hit, self.normal, self.depth, t.hit, t.normal, t.depth) *
                  exp(-abs(lc - luminance(c.rgb)) / lumScale);
        sum += w * c.rgb;
        sumW += w;
        sumVar += w * w * c.a;
    }
    return vec4(sum / sumW, sumVar / (sumW * sumW));
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.params.z) return;
    vec2 site;
    float spacing;
    if (!siteOf(i, site, spacing)) return; // point_sample did not trace it either
    Tap self = tapOf(i);
    if (pc.step.y == kStepDemodulate) {
        outputs[i] = demodulated(i, self);
        return;
    }
    float s = strengthAt(tangentOf(site));
    if (pc.step.y == kStepLast && s <= 0.0) {
        outputs[i] = samples[i]; // exactly as traced, not divided and multiplied back
        return;
    }
    vec4 own = light[i];
    vec4 f = s > 0.0 ? filtered(i, self, spacing) : own;
    vec4 blended = vec4(mix(own.rgb, f.rgb, s), mix(own.a, f.a, s * s));
    if (pc.step.y == kStepLast) {
        blended = vec4(blended.rgb * decodePointGuide(guide[i]).albedo, self.depth);
    }
    outputs[i] = blended;
}
