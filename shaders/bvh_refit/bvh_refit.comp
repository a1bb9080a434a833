#version 460
// Pass `bvh_refit`: one level of a BVH refit, the GPU twin of scene::Bvh::refit. Each
// invocation takes one node of the level: a leaf's box grows over its triangles' corners
// (v0, v0 + e1, v0 + e2, as the CPU forms them), an interior node's is the union of its two
// children's unpadded boxes, which the level below wrote. The stored bounds are padded as
// storePadded() does; the unpadded box goes to the scratch buffer so the padding never compounds
// up the tree.
#extension GL_GOOGLE_include_directive : require
#include "bvh_refit_shared.h"

struct BvhNode {
    vec3 boundsMin;
    uint leftFirst; // interior: left child (the right one follows it); leaf: first triangle
    vec3 boundsMax;
    uint count; // 0 for interior nodes
};

layout(local_size_x = kRefitGroupSize) in;
layout(std430, set = 0, binding = kBindingRefitTriangles) readonly buffer Triangles { float tri[]; };
layout(std430, set = 0, binding = kBindingRefitOrder) readonly buffer Order { uint order[]; };
layout(std430, set = 0, binding = kBindingRefitNodes) buffer Nodes { BvhNode nodes[]; };
layout(std430, set = 0, binding = kBindingRefitBoxes) buffer Boxes { vec4 boxes[]; };
layout(push_constant) uniform Push { BvhRefitPush pc; };

vec3 corner(uint base) {
    return vec3(tri[base], tri[base + 1u], tri[base + 2u]);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.level.y) return;
    uint n = order[pc.level.x + i];
    uint first = nodes[n].leftFirst;
    uint count = nodes[n].count;
    vec3 lo = vec3(3.402823466e38);
    vec3 hi = vec3(-3.402823466e38);
    if (count > 0u) {
        for (uint k = first; k < first + count; ++k) {
            uint b = 9u * k;
            precise vec3 v0 = corner(b);
            precise vec3 v1 = v0 + corner(b + 3u);
            precise vec3 v2 = v0 + corner(b + 6u);
            lo = min(lo, min(v0, min(v1, v2)));
            hi = max(hi, max(v0, max(v1, v2)));
        }
    } else {
        lo = min(boxes[2u * first].xyz, boxes[2u * first + 2u].xyz);
        hi = max(boxes[2u * first + 1u].xyz, boxes[2u * first + 3u].xyz);
    }
    boxes[2u * n] = vec4(lo, 0.0);
    boxes[2u * n + 1u] = vec4(hi, 0.0);
    precise vec3 pad = 4e-6 * (abs(lo) + abs(hi)) + 1e-30;
    nodes[n].boundsMin = lo - pad;
    nodes[n].boundsMax = hi + pad;
}
