#version 460
// Pass `tonemap`: exposure, the ACES filmic fit of Narkowicz (2015), then the sRGB transfer
// function, into an 8-bit image for display or PNG.
#extension GL_GOOGLE_include_directive : require
#include "tonemap_shared.h"
#include "tonemap.glsl"

layout(local_size_x = kGroupSizeX, local_size_y = kGroupSizeY) in;
layout(set = 0, binding = kBindingInput, rgba32f) uniform readonly image2D uInput;
layout(set = 0, binding = kBindingOutput, rgba8) uniform writeonly image2D uOutput;
layout(push_constant) uniform Push { TonemapPush pc; };

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(uOutput)))) return;
    imageStore(uOutput, p, tonemapped(imageLoad(uInput, p).rgb, pc.params.x));
}
