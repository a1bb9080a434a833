#version 460
// Pass `rbf_solve` (seed 000, eqs. 7-8): for every sampled point q, solve phi(|x_a - x_b|)
// lambda = f over q's neighbourhood (q and its k-1 nearest sampled neighbours) by Gaussian
// elimination with partial pivoting, for the three colour channels at once. The interpolate
// pass then evaluates s(x) = sum lambda_i phi(|x - x_i|) for every pixel in q's cell: one
// k x k solve per point instead of per pixel, and O(k) work per pixel, like Shepard's method.
// The kernel's shape c scales with the point's spacing p, so one c fits the fovea and the
// periphery alike.
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
layout(push_constant) uniform Push { RbfSolvePush pc; };

void main() {
    uint q = gl_GlobalInvocationID.x;
    if (q >= pc.counts.x) return;
    vec2 size = vec2(pc.params.xy);
    vec4 pq = texelFetch(uPoints, int(q));
    if (!isSampled(pq.xy, pc.offset.xy, size, pc.offset.z)) return;
    uint k = min(pc.params.z, kMaxK);
    uint stored = pc.counts.y;
    uint nb[kMaxK];
    vec2 pos[kMaxK];
    uint m = 0u;
    for (uint j = 0u; j <= stored && m < k; ++j) {
        uint i = j == 0u ? q : texelFetch(uNeighbours, int(q * stored + j - 1u)).r;
        vec2 p = texelFetch(uPoints, int(i)).xy;
        if (!isSampled(p, pc.offset.xy, size, pc.offset.z)) continue;
        nb[m] = i;
        pos[m] = p;
        ++m;
    }
    float c = max(pc.offset.w * pq.z, 1e-3);
    float a[kMaxK][kMaxK];
    vec3 f[kMaxK];
    for (uint r = 0u; r < m; ++r) {
        for (uint s = 0u; s < m; ++s) a[r][s] = rbfKernel(length(pos[r] - pos[s]), c, pc.params.w);
        a[r][r] += 1e-6; // a whisker of regularisation for nearly coincident points
        f[r] = samples[nb[r]].rgb;
    }
    // Gaussian elimination with partial pivoting.
    for (uint col = 0u; col < m; ++col) {
        uint piv = col;
        for (uint r = col + 1u; r < m; ++r) {
            if (abs(a[r][col]) > abs(a[piv][col])) piv = r;
        }
        if (piv != col) {
            for (uint s = 0u; s < m; ++s) {
                float t = a[col][s];
                a[col][s] = a[piv][s];
                a[piv][s] = t;
            }
            vec3 t = f[col];
            f[col] = f[piv];
            f[piv] = t;
        }
        float d = a[col][col];
        if (abs(d) < 1e-20) d = 1e-20;
        for (uint r = col + 1u; r < m; ++r) {
            float factor = a[r][col] / d;
            for (uint s = col; s < m; ++s) a[r][s] -= factor * a[col][s];
            f[r] -= factor * f[col];
        }
    }
    vec3 lambda[kMaxK];
    for (int r = int(m) - 1; r >= 0; --r) {
        vec3 sum = f[r];
        for (uint s = uint(r) + 1u; s < m; ++s) sum -= a[r][s] * lambda[s];
        float d = a[r][r];
        lambda[r] = sum / (abs(d) < 1e-20 ? 1e-20 : d);
    }
    for (uint j = 0u; j < k; ++j) {
        vec3 l = j < m ? lambda[j] : vec3(0.0);
        lambdaR[q * k + j] = l.r;
        lambdaG[q * k + j] = l.g;
        lambdaB[q * k + j] = l.b;
    }
}
