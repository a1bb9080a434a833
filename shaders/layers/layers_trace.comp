#version 460
// Pass `layers`, trace: one eccentricity layer as a pinhole grid over its sub-frustum. The grid
// as a whole is jittered every frame by moving the frustum (Guenter et al. 2012, 4.2, "whole frame jitter");
// several rays per layer pixel take fixed stratified positions inside it, the ray-tracing
// counterpart of the paper's MSAA.
#extension GL_GOOGLE_include_directive : require
#include "layers_shared.h"
#include "trace.glsl"
#include "motion.glsl"

layout(local_size_x = kGroupSizeX, local_size_y = kGroupSizeY) in;
layout(set = 0, binding = kBindingTraceOutput, rgba32f) uniform writeonly image2D uOutput;
layout(set = 0, binding = kBindingTraceMotion, rgba32f) uniform writeonly image2D uMotion;
layout(push_constant) uniform Push { LayerTracePush pc; };

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    uint width = pc.params.x, height = pc.params.y, rays = pc.params.z;
    if (pixel.x >= width || pixel.y >= height) return;
    CameraPush cam = CameraPush(pc.origin, pc.forward, pc.right, pc.up);
    selectLod(pc.params.w); // coarser layers traverse coarser refinements (Guenter et al. 2012, 6)
    uint nx = 1u;
    while (nx * nx < rays) nx++;
    uint ny = (rays + nx - 1u) / nx;
    vec3 sum = vec3(0.0);
    float firstDepth = 0.0;
    vec4 firstMotion = vec4(0.0);
    for (uint i = 0u; i < rays; ++i) {
        vec2 o = vec2((float(i % nx) + 0.5) / float(nx), (float(i / nx) + 0.5) / float(ny));
        vec3 dir = cameraRay(cam, vec2(pixel) + o, vec2(width, height));
        float depth;
        sum += traceRadiance(pc.origin.xyz, dir, depth);
        if (i == 0u) {
            firstDepth = depth;
            if (kDynamic) firstMotion = storedMotion();
        }
    }
    imageStore(uOutput, ivec2(pixel), vec4(sum / float(rays), firstDepth));
    if (kDynamic) imageStore(uMotion, ivec2(pixel), firstMotion);
}
