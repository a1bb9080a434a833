// Pass `lens`: barrel pre-distortion with chromatic aberration for an HMD eye
// (engine/display/hmd_profile.hpp, LensModel).
#ifndef LENS_SHARED_H
#define LENS_SHARED_H
#include "gt_shared.h"

GT_NAMESPACE_BEGIN(lens)

GT_CONST kBindingInput = 0;  // image2D rgba8: the eye's finished image (sRGB-encoded)
GT_CONST kBindingOutput = 1; // image2D rgba8: what the eye's half of the panel shows
GT_CONST kGroupX = 8;
GT_CONST kGroupY = 8;

struct LensPush {
    vec4 centre; // xy: lens centre (normalised, y down); z: aspect (width / height); w: rMax
    vec4 coeffs; // x = k1, y = k2, z = 1 / (1 + k1 + k2), w = 1: clamp to the edge, 0: black
    vec4 chroma; // radial scale per channel: red, green, blue
};

GT_NAMESPACE_END
#endif
