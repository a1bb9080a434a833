// Pass `denoise`: an edge-avoiding a-trous wavelet filter on linear radiance whose alpha is the
// first hit's distance, its strength rising with eccentricity from the gaze.
#ifndef DENOISE_SHARED_H
#define DENOISE_SHARED_H
#include "gt_shared.h"

GT_NAMESPACE_BEGIN(denoise)

GT_CONST kBindingRadiance = 0; // image2D rgba32f: the method's radiance, a = first-hit distance
GT_CONST kBindingInput = 1;    // image2D rgba32f: rgb and the luminance variance (a)
GT_CONST kBindingOutput = 2;   // image2D rgba32f: the same after this step
// image2D rgba32f: xyz = the surface normal from the depth image, w = the first-hit distance;
// written by the variance step, read by the levels
GT_CONST kBindingGuide = 3;
GT_CONST kGroupSizeX = 8;
GT_CONST kGroupSizeY = 8;

// Which step a dispatch runs (DenoisePush::step.y).
GT_CONST kStepVariance = 0; // the input's rgb with its 3x3 luminance variance
GT_CONST kStepFilter = 1;   // one a-trous level
GT_CONST kStepLast = 2;     // the last level: rgb and the radiance's own alpha (the depth)

struct DenoisePush {
    // x = width, y = height, z = gaze x, w = gaze y (pixels)
    vec4 view;
    // The camera's tangent plane (trace::CameraPush): x = tan(yfov / 2), y = aspect,
    // z = frustum centre x, w = centre y (tangents)
    vec4 frustum;
    // x = luminance sigma (in standard deviations), y = depth sigma (a neighbour's distance
    // off the pixel's surface plane, relative to the pixel's), z = eccentricity (degrees) below
    // which nothing is filtered, w = eccentricity from which the filter has its full strength
    vec4 sigmas;
    // x = the level's spacing in pixels (1, 2, 4, ...), y = kStep*, z = the normal term's
    // exponent (bits of a float)
    uvec4 step;
};

GT_NAMESPACE_END
#endif
