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
layout(set = 0, binding = kBindingOutput, rgba32f) uniform writeonly image2D uOutput;
layout(set = 0, binding = kBindingMotionOutput, rgba32f) uniform writeonly image2D uMotion;
layout(push_constant) uniform Push { ReferencePush pc; };

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    uint width = pc.params.x, height = pc.params.y, spp = pc.params.z;
    if (pixel.x >= width || pixel.y >= height) return;
    CameraPush cam = CameraPush(pc.origin, pc.forward, pc.right, pc.up);
    uint pixelIndex = pixel.y * width + pixel.x;
    vec3 sum = vec3(0.0);
    float firstDepth = 0.0; // first-hit distance of the first ray, for TAA
    vec4 firstMotion = vec4(0.0); // and its motion, in a scene that moves
    for (uint i = 0u; i < spp; ++i) {
        vec2 o = sampleOffset(pixelIndex, i, spp, pc.params.w);
        vec3 dir = cameraRay(cam, vec2(pixel) + o, vec2(width, height));
        float depth;
        sum += traceIntegrator(pc.origin.xyz, dir, pixelIndex, i, pc.params.w, depth);
        if (i == 0u) {
            firstDepth = depth;
            if (kDynamic) firstMotion = storedMotion();
        }
    }
    imageStore(uOutput, ivec2(pixel), vec4(sum / float(spp), firstDepth));
    if (kDynamic) imageStore(uMotion, ivec2(pixel), firstMotion);
}
