#version 460
// Pass `layers`, compose: every layer resampled bilinearly to the display grid (seed 002,
// Figure 6) and blended outer to inner with circular smoothstep masks around the gaze: a layer
// weighs 1 inside (1 - t) r and 0 beyond r, its radius, with the transition t = 40 % of the
// radius (Figure 3).
#extension GL_GOOGLE_include_directive : require
#include "layers_shared.h"

layout(local_size_x = 8, local_size_y = 8) in;
// Sampled with a bilinear, clamp-to-edge sampler: one filtered fetch per layer instead of four
// image loads (the compose was a third of a layers frame on lavapipe at 1920 x 1080).
layout(set = 0, binding = 0) uniform sampler2D uLayer0;
layout(set = 0, binding = 1) uniform sampler2D uLayer1;
layout(set = 0, binding = 2) uniform sampler2D uLayer2;
layout(set = 0, binding = 3) uniform sampler2D uLayer3;
layout(set = 0, binding = kBindingComposeOutput, rgba32f) uniform writeonly image2D uOutput;
layout(push_constant) uniform Push { LayerComposePush pc; };

ivec2 layerSize(int layer) {
    if (layer == 0) return textureSize(uLayer0, 0);
    if (layer == 1) return textureSize(uLayer1, 0);
    if (layer == 2) return textureSize(uLayer2, 0);
    return textureSize(uLayer3, 0);
}

// Bilinear at `u`, in layer pixels measured from the grid's corner (pixel edges).
vec4 bilinear(int layer, vec2 u, ivec2 size) {
    vec2 uv = u / vec2(size);
    if (layer == 0) return textureLod(uLayer0, uv, 0.0);
    if (layer == 1) return textureLod(uLayer1, uv, 0.0);
    if (layer == 2) return textureLod(uLayer2, uv, 0.0);
    return textureLod(uLayer3, uv, 0.0);
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(uOutput);
    if (any(greaterThanEqual(px, size))) return;
    int count = int(pc.gaze.z + 0.5);
    vec2 p = vec2(px) + 0.5; // the pixel's centre, in pixel edges
    float d = length(vec2(px) - pc.gaze.xy);
    int outer = count - 1;
    vec4 result = bilinear(outer, (p - pc.layer[outer].xy) / pc.layer[outer].z, layerSize(outer));
    for (int i = outer - 1; i >= 0; --i) {
        float r = pc.layer[i].w;
        float w = 1.0 - smoothstep((1.0 - pc.gaze.w) * r, r, d);
        if (w <= 0.0) continue;
        ivec2 ls = layerSize(i);
        vec2 u = (p - pc.layer[i].xy) / pc.layer[i].z;
        // A half-rate layer traced around last frame's gaze may not reach this pixel yet: the
        // layer outside it shows there instead.
        if (any(lessThan(u, vec2(0.0))) || any(greaterThan(u, vec2(ls)))) continue;
        result = mix(result, bilinear(i, u, ls), w);
    }
    imageStore(uOutput, px, result);
}
