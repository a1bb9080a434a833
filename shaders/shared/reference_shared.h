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
    // x = the first ray of this dispatch, y = its rays: a pixel's rays may come in several
    // dispatches, each adding its share to the output (x > 0 reads what the earlier wrote).
    uvec4 range;
};
// Paths per pixel in one dispatch of the path integrator: lavapipe ends a loop after 65,535
// iterations of one invocation, all its loops together, which a handful of multi-bounce paths
// through a deep BVH can reach. The direct integrator traces every ray in one dispatch.
GT_CONST kPathRaysPerDispatch = 4;

GT_NAMESPACE_END
#endif
