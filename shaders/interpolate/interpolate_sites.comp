#version 460
// Pass `interpolate.sites`: where every point of the set sits on the screen this frame, its
// canvas position plus the gaze offset plus its move (site_jitter.glsl). interpolate weighs up
// to k + 1 candidates per pixel, so computing the move there cost every pixel k + 1 hashes, a
// square root, a sine and a cosine; here each point pays once. The expression is the one
// interpolate evaluated, so the sites are the same floats.
#extension GL_GOOGLE_include_directive : require
#include "foveated_shared.h"
#include "site_jitter.glsl"

layout(local_size_x = kSitesGroup) in;
layout(set = 0, binding = kBindingSitesPoints) uniform samplerBuffer uPoints;
layout(std430, set = 0, binding = kBindingSitesOut) writeonly buffer Sites { vec4 sites[]; };
layout(push_constant) uniform Push { SitesPush pc; };

void main() {
    // Groups in two dimensions: a set may hold more points than 65,535 groups in x cover.
    uint i = (gl_WorkGroupID.y * pc.params.z + gl_WorkGroupID.x) * kSitesGroup +
             gl_LocalInvocationID.x;
    if (i >= pc.params.x) return;
    vec4 pt = texelFetch(uPoints, int(i));
    vec2 s = pt.xy + pc.offset.xy + siteJitter(i, pc.params.y, pt.z, pc.offset.z);
    sites[i] = vec4(s, pt.z, 0.0);
}
