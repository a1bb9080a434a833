#version 460
// Pass `point_sample` (seed 000, 4.2): the point set shifted to the gaze; every point on screen
// or within the margin is traced with R rays through random positions inside its disc of radius
// p. The positions come from the point's index alone, so they are the same every frame.
#extension GL_GOOGLE_include_directive : require
#include "foveated_shared.h"
#include "random.glsl"
#include "trace.glsl"

layout(local_size_x = kSampleGroupSize) in;
layout(set = 0, binding = kBindingPoints) uniform samplerBuffer uPoints;
layout(std430, set = 0, binding = kBindingSamples) writeonly buffer Samples { vec4 samples[]; };
layout(push_constant) uniform Push { PointSamplePush pc; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.params.w) return;
    vec4 p = texelFetch(uPoints, int(i));
    vec2 s = p.xy + pc.offset.xy;
    float margin = pc.offset.z;
    vec2 size = vec2(pc.params.xy);
    if (any(lessThan(s, vec2(-margin))) || any(greaterThanEqual(s, size + margin))) return;
    CameraPush cam = CameraPush(pc.origin, pc.forward, pc.right, pc.up);
    uint rays = pc.params.z;
    vec3 sum = vec3(0.0);
    float firstDepth = 0.0;
    for (uint r = 0u; r < rays; ++r) {
        vec2 pos = s;
        if (rays > 1u) {
            uint h = pcgHash(i * 0x9E3779B9u ^ pcgHash(r + 0x51ED27u));
            float angle = 6.28318531 * hashToFloat(h);
            float radius = p.z * sqrt(hashToFloat(pcgHash(h)));
            pos += radius * vec2(cos(angle), sin(angle));
        }
        float depth;
        sum += traceRadiance(pc.origin.xyz, cameraRay(cam, pos, size), depth);
        if (r == 0u) firstDepth = depth;
    }
    samples[i] = vec4(sum / float(rays), firstDepth);
}
