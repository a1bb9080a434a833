// Pass `tonemap`: linear radiance -> display-referred sRGB 8-bit.
#ifndef TONEMAP_SHARED_H
#define TONEMAP_SHARED_H
#include "gt_shared.h"

GT_NAMESPACE_BEGIN(tonemap)

GT_CONST kBindingInput = 0;  // image2D rgba32f
GT_CONST kBindingOutput = 1; // image2D rgba8
GT_CONST kGroupSizeX = 8;
GT_CONST kGroupSizeY = 8;

struct TonemapPush {
    vec4 params; // x = exposure
};

GT_NAMESPACE_END
#endif
