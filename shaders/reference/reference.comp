#version 460
// Pass `reference`: every pixel ray traced with N stratified jittered rays; the baseline every
// foveated method is measured against (thesis, section 5: "ground truth").
#extension GL_GOOGLE_include_directive : require
#include "reference_shared.h"
#include "random.glsl"
#include "trace.glsl"
#include "path.glsl"
#include "motion.glsl"

layout(local_size_x = kGroupSizeX, local_size_y = kGroupSizeY) in;
layout(set = 0, binding = kBindingOutput, rgba32f) uniform image2D uOutput;
layout(set = 0, binding = kBindingMotionOutput, rgba32f) uniform writeonly image2D uMotion;
layout(push_constant) uniform Push { ReferencePush pc; };

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    uint width = pc.params.x, height = pc.params.y, spp = pc.params.z;
    if (pixel.x >= width || pixel.y >= height) return;
    CameraPush cam = CameraPush(pc.origin, pc.forward, pc.right, pc.up);
    uint pixelIndex = pixel.y * width + pixel.x;
    gPixelSpread = 2.0 * cam.origin.w / float(height); // a pixel's angle: the ray cone's spread
    uint first = pc.range.x, last = pc.range.x + pc.range.y;
    vec3 sum = vec3(0.0);
    float firstDepth = 0.0; // first-hit distance of the first ray, for TAA
    vec4 firstMotion = vec4(0.0); // and its motion, in a scene that moves
    for (uint i = first; i < last; ++i) {
        vec2 o = pixelOffset(pixelIndex, i, spp, pc.params.w,
                             sampleOffset(pixelIndex, i, spp, pc.params.w));
        vec3 dir = cameraRay(cam, vec2(pixel) + o, vec2(width, height));
        float depth;
        sum += traceIntegrator(pc.origin.xyz, dir, pixelIndex, i, spp, pc.params.w, depth);
        if (i == 0u) { // only in the first share
            firstDepth = depth;
            if (kDynamic) firstMotion = storedMotion();
        }
    }
    if (first > 0u) { // a later share: add to the earlier ones, keep ray 0's depth and motion
        vec4 earlier = imageLoad(uOutput, ivec2(pixel));
        imageStore(uOutput, ivec2(pixel), vec4(earlier.rgb + sum / float(spp), earlier.a));
        return;
    }
    imageStore(uOutput, ivec2(pixel), vec4(sum / float(spp), firstDepth));
    if (kDynamic) imageStore(uMotion, ivec2(pixel), firstMotion);
}
