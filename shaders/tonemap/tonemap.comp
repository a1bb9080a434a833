#version 460
// Pass `tonemap`: exposure, the ACES filmic fit of Narkowicz (2015), then the sRGB transfer
// function, into an 8-bit image for display or PNG.
#extension GL_GOOGLE_include_directive : require
#include "tonemap_shared.h"

layout(local_size_x = kGroupSizeX, local_size_y = kGroupSizeY) in;
layout(set = 0, binding = kBindingInput, rgba32f) uniform readonly image2D uInput;
layout(set = 0, binding = kBindingOutput, rgba8) uniform writeonly image2D uOutput;
layout(push_constant) uniform Push { TonemapPush pc; };

vec3 acesFit(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 linearToSrgb(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(uOutput)))) return;
    vec3 c = max(imageLoad(uInput, p).rgb, vec3(0.0)) * pc.params.x;
    imageStore(uOutput, p, vec4(linearToSrgb(acesFit(c)), 1.0));
}
