// Pass `reference`: full-resolution ray tracing, N stratified jittered rays per pixel.
#ifndef REFERENCE_SHARED_H
#define REFERENCE_SHARED_H
#include "trace_shared.h"

GT_NAMESPACE_BEGIN(reference)

GT_CONST kBindingOutput = 9; // image2D rgba32f, linear radiance (after the 9 scene bindings)
// image2D rgba32f, in a scene that moves: the first hit's motion of each pixel's first ray
// (shaders/common/motion.glsl); unwritten otherwise
GT_CONST kBindingMotionOutput = 10;
GT_CONST kGroupSizeX = 8;
GT_CONST kGroupSizeY = 8;

struct ReferencePush {
    vec4 origin; // camera, as trace::CameraPush
    vec4 forward;
    vec4 right;
    vec4 up;
    uvec4 params; // x = width, y = height, z = rays per pixel, w = frame seed
};

GT_NAMESPACE_END
#endif
