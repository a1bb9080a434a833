#version 460
// Pass `point_sample` (seed 000, 4.2): the point set shifted to the gaze; every point on screen
// or within the margin is traced with R rays through random positions inside its disc of radius
// p. The positions come from the point's index and the ray's number alone, so they are the same
// every frame and whichever thread traces them.
//
// kLanes threads share a point and trace its rays side by side (lane l takes rays l, l + kLanes,
// ...), summed in shared memory. On a GPU the lanes of a subgroup then follow nearly the same
// path through the BVH, and a frame has up to R times as many threads to fill the machine
// with. With kLanes = 1 a thread traces all R rays of its point, which suits a CPU driver
// (PointSamplePass picks). The group stays 1-D either way: lavapipe packs its SIMD lanes along
// local_size_x only.
#extension GL_GOOGLE_include_directive : require
#include "foveated_shared.h"
#include "random.glsl"
#include "trace.glsl"

layout(local_size_x = kSampleGroupSize) in;
layout(constant_id = 1) const uint kLanes = 1u; // a power of two up to kSampleGroupSize / 2
layout(set = 0, binding = kBindingPoints) uniform samplerBuffer uPoints;
layout(std430, set = 0, binding = kBindingSamples) writeonly buffer Samples { vec4 samples[]; };
layout(push_constant) uniform Push { PointSamplePush pc; };

shared vec3 partial[kSampleGroupSize];

// Panel pixel -> image pixel through the lens (green), when the set is laid on the panel.
vec2 toImage(vec2 panel, vec2 size) {
    if (pc.lens.w <= 0.0) return panel;
    vec2 d = panel / size - pc.lens.xy;
    float r = length(d * vec2(pc.lens.z, 1.0)) / pc.lens.w;
    float r2 = r * r;
    float f = (1.0 + pc.lensCoeffs.x * r2 + pc.lensCoeffs.y * r2 * r2) * pc.lensCoeffs.z;
    return (pc.lens.xy + d * f) * size;
}

void main() {
    const uint i = gl_GlobalInvocationID.x / kLanes;
    const uint lane = gl_LocalInvocationIndex % kLanes;
    const uint rays = pc.params.z;
    const vec2 size = vec2(pc.params.xy);
    const float margin = pc.offset.z;
    vec4 p = vec4(0.0);
    vec2 s = vec2(0.0);
    bool onScreen = false;
    if (i < pc.params.w) {
        p = texelFetch(uPoints, int(i));
        s = p.xy + pc.offset.xy;
        onScreen = all(greaterThanEqual(s, vec2(-margin))) && all(lessThan(s, size + margin));
    }
    if (kLanes == 1u && !onScreen) return; // a specialisation constant: no barrier follows
    const CameraPush cam = CameraPush(pc.origin, pc.forward, pc.right, pc.up);
    // Geometric LOD (seed 002, 6, here for the point set): a point whose neighbours lie p pixels
    // apart resolves no detail finer than that, so it traces the scene's subdivision cages
    // one level coarser per doubling past 4 px (scene::lodForPitch). Each point keeps its level
    // as the set follows the gaze.
    if (pc.offset.w > 1.5 && p.z >= 4.0) {
        selectLod(min(uint(floor(log2(p.z * 0.5))), uint(pc.offset.w) - 1u));
    }
    vec3 sum = vec3(0.0);
    float firstDepth = 0.0; // first-hit distance of ray 0 (always lane 0's), for TAA
    for (uint r = lane; onScreen && r < rays; r += kLanes) {
        vec2 pos = s;
        if (rays > 1u) {
            uint h = pcgHash(i * 0x9E3779B9u ^ pcgHash(r + 0x51ED27u));
            float angle = 6.28318531 * hashToFloat(h);
            float radius = p.z * sqrt(hashToFloat(pcgHash(h)));
            pos += radius * vec2(cos(angle), sin(angle));
        }
        float depth;
        sum += traceRadiance(pc.origin.xyz, cameraRay(cam, toImage(pos, size), size), depth);
        if (r == 0u) firstDepth = depth;
    }
    if (kLanes > 1u) {
        partial[gl_LocalInvocationIndex] = sum;
        barrier(); // every thread of the group reaches it: off-screen ones only skip the tracing
        if (lane != 0u || !onScreen) return;
        for (uint l = 1u; l < kLanes; ++l) sum += partial[gl_LocalInvocationIndex + l];
    }
    samples[i] = vec4(sum / float(rays), firstDepth);
}
