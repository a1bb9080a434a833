#version 460
// Pass `rbf_solve` (thesis, eqs. 7-8): lambda = inverse(phi(|x_a - x_b|)) f for every sampled
// point q, over q and its k-1 nearest neighbours, with the inverse precomputed once per point
// set (engine/foveation/rbf_inverse.cpp): k^2 multiply-adds per point and frame. Neighbours
// that point_sample skipped (beyond the screen margin) take q's colour. The interpolate pass
// then evaluates s(x) = sum lambda_i phi(|x - x_i|) for every pixel in q's cell.
#extension GL_GOOGLE_include_directive : require
#include "foveated_shared.h"
#include "rbf.glsl"

layout(local_size_x = kSolveGroupSize) in;
layout(set = 0, binding = kBindingSolvePoints) uniform samplerBuffer uPoints;
layout(std430, set = 0, binding = kBindingSolveSamples) readonly buffer Samples { vec4 samples[]; };
layout(set = 0, binding = kBindingSolveNeighbours) uniform usamplerBuffer uNeighbours;
layout(std430, set = 0, binding = kBindingSolveLambdaR) writeonly buffer LambdaR { float lambdaR[]; };
layout(std430, set = 0, binding = kBindingSolveLambdaG) writeonly buffer LambdaG { float lambdaG[]; };
layout(std430, set = 0, binding = kBindingSolveLambdaB) writeonly buffer LambdaB { float lambdaB[]; };
layout(set = 0, binding = kBindingSolveInverse) uniform samplerBuffer uInverse;
layout(push_constant) uniform Push { RbfSolvePush pc; };

void main() {
    uint q = gl_GlobalInvocationID.x;
    if (q >= pc.counts.x) return;
    vec2 size = vec2(pc.params.xy);
    if (!isSampled(texelFetch(uPoints, int(q)).xy, pc.offset.xy, size, pc.offset.z)) return;
    uint k = min(pc.params.z, kMaxK);
    uint stored = pc.counts.y;
    vec3 f[kMaxK];
    vec3 own = samples[q].rgb;
    for (uint j = 0u; j < k; ++j) {
        uint i = j == 0u ? q : texelFetch(uNeighbours, int(q * stored + j - 1u)).r;
        f[j] = isSampled(texelFetch(uPoints, int(i)).xy, pc.offset.xy, size, pc.offset.z) ? samples[i].rgb : own;
    }
    int base = int(q * pc.counts.z);
    for (uint r = 0u; r < k; ++r) {
        vec3 l = vec3(0.0);
        for (uint c = 0u; c < k; ++c) {
            uint e = r * k + c;
            l += texelFetch(uInverse, base + int(e >> 2u))[e & 3u] * f[c];
        }
        lambdaR[q * k + r] = l.r;
        lambdaG[q * k + r] = l.g;
        lambdaB[q * k + r] = l.b;
    }
}
