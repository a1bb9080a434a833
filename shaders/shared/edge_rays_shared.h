// Pass `edge_rays`: a ray traced in each pixel at a moving edge of a reconstructed image.
#ifndef EDGE_RAYS_SHARED_H
#define EDGE_RAYS_SHARED_H
#include "trace_shared.h"

GT_NAMESPACE_BEGIN(edge_rays)

// After the 9 scene bindings: the reconstruction's radiance (a = first-hit distance), motion
// (motion.glsl) and support (taa.glsl's TAA_SUPPORT), each read, and their refined copies.
GT_CONST kBindingRadiance = 9;        // image2D rgba32f
GT_CONST kBindingMotion = 10;         // image2D rgba32f
GT_CONST kBindingSupport = 11;        // image2D r32f (edge_rays_support.comp)
GT_CONST kBindingRadianceOutput = 12; // image2D rgba32f
GT_CONST kBindingMotionOutput = 13;   // image2D rgba32f
GT_CONST kBindingSupportOutput = 14;  // image2D r32f (edge_rays_support.comp)
GT_CONST kGroupSizeX = 8;
GT_CONST kGroupSizeY = 8;

struct EdgeRaysPush {
    vec4 origin; // camera, as trace::CameraPush
    vec4 forward;
    vec4 right;
    vec4 up;
    uvec4 params; // x = width, y = height, z unused, w = frame seed
};

GT_NAMESPACE_END
#endif
