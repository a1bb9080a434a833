// Pass `bvh_refit`: a BVH's node bounds refitted from its placed triangles, one dispatch per
// tree level from the deepest up.
#ifndef BVH_REFIT_SHARED_H
#define BVH_REFIT_SHARED_H
#include "gt_shared.h"

GT_NAMESPACE_BEGIN(bvh_refit)

GT_CONST kBindingRefitTriangles = 0; // float[9 * n]: v0, e1, e2 per triangle in BVH order
GT_CONST kBindingRefitOrder = 1;     // uint[]: node indices grouped by depth, deepest first
GT_CONST kBindingRefitNodes = 2;     // BvhNode[] (32 bytes each): bounds written, topology read
GT_CONST kBindingRefitBoxes = 3;     // vec4[2 * nodes]: unpadded lo, hi of every node
GT_CONST kRefitGroupSize = 64;

struct BvhRefitPush {
    uvec4 level; // x = first entry of the level in the order buffer, y = its node count
};

GT_NAMESPACE_END
#endif
