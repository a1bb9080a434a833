#version 460
// Pass `lens`: each panel pixel samples the eye's image where the lens model says
// (engine/display/hmd_profile.hpp): src = c + (q - c) f(r) chroma[channel], with
// f(r) = (1 + k1 r^2 + k2 r^4) / (1 + k1 + k2). Samples are filtered in linear light (the input
// is sRGB-encoded) and land outside the image as black.
#extension GL_GOOGLE_include_directive : require
#include "lens_shared.h"

layout(local_size_x = kGroupX, local_size_y = kGroupY) in;
layout(set = 0, binding = kBindingInput, rgba8) uniform readonly image2D uInput;
layout(set = 0, binding = kBindingOutput, rgba8) uniform writeonly image2D uOutput;
layout(push_constant) uniform Push { LensPush pc; };

vec3 toLinear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}
vec3 toSrgb(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

// Bilinear in linear light at normalised position uv (pixel centres at (i + 0.5) / size).
vec3 fetch(vec2 uv, ivec2 size) {
    if (pc.coeffs.w > 0.5) {
        uv = clamp(uv, vec2(0.0), vec2(1.0)); // the input is already the panel: hold its edge
    } else if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
        return vec3(0.0);
    }
    vec2 p = uv * vec2(size) - 0.5;
    ivec2 i = ivec2(floor(p));
    vec2 f = p - vec2(i);
    vec3 a = toLinear(imageLoad(uInput, clamp(i, ivec2(0), size - 1)).rgb);
    vec3 b = toLinear(imageLoad(uInput, clamp(i + ivec2(1, 0), ivec2(0), size - 1)).rgb);
    vec3 c = toLinear(imageLoad(uInput, clamp(i + ivec2(0, 1), ivec2(0), size - 1)).rgb);
    vec3 d = toLinear(imageLoad(uInput, clamp(i + ivec2(1, 1), ivec2(0), size - 1)).rgb);
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(uOutput);
    if (any(greaterThanEqual(px, size))) return;
    vec2 q = (vec2(px) + 0.5) / vec2(size);
    vec2 d = q - pc.centre.xy;
    float r = length(d * vec2(pc.centre.z, 1.0)) / pc.centre.w;
    float r2 = r * r;
    float f = (1.0 + pc.coeffs.x * r2 + pc.coeffs.y * r2 * r2) * pc.coeffs.z;
    ivec2 inSize = imageSize(uInput);
    vec3 colour;
    colour.r = fetch(pc.centre.xy + d * f * pc.chroma.r, inSize).r;
    colour.g = fetch(pc.centre.xy + d * f * pc.chroma.g, inSize).g;
    colour.b = fetch(pc.centre.xy + d * f * pc.chroma.b, inSize).b;
    imageStore(uOutput, px, vec4(toSrgb(colour), 1.0));
}
