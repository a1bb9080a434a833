// Pass `taa`: temporal anti-aliasing of the rebuilt image (thesis, 4.3 and 3.1).
#ifndef TAA_SHARED_H
#define TAA_SHARED_H
#include "gt_shared.h"

GT_NAMESPACE_BEGIN(taa)

GT_CONST kBindingCurrent = 0; // image2D rgba32f: radiance, a = first-hit distance
GT_CONST kBindingHistory = 1; // image2D rgba32f: last frame's output, same layout
GT_CONST kBindingOutput = 2;  // image2D rgba32f
// image2D r32f (taa_support.comp): per pixel the distance to the sample the frame took most
// from, in units of the sample spacing (interpolate's kBindingInterpSupport)
GT_CONST kBindingSupport = 3;
GT_CONST kBindingWeightHistory = 4; // image2D r32f (taa_support.comp): last frame's weight sum
GT_CONST kBindingWeightOutput = 5;  // image2D r32f: this frame's
// A scene that moves (taa_motion.comp, taa_support_motion.comp): per pixel the first hit's
// motion (motion.glsl: xyz = world position one frame ago minus now, w = its signature code),
// and the history of the signatures the output pixels show, each with the number of frames its
// pixel's history gathered since it was last rejected (kHistoryFramesShift).
GT_CONST kBindingMotion = 6;           // image2D rgba32f
GT_CONST kBindingSignatureHistory = 7; // uimage2D r32ui: last frame's
GT_CONST kBindingSignatureOutput = 8;  // uimage2D r32ui: this frame's
// A signature history texel: the signature code (motion.glsl's signatureCode, 24 bits) in the
// low bits, the history's frame count (at most kMaxHistoryFrames) above them, and in the top
// bit (kEdgeMixBit) whether it holds a moving edge's mix of surfaces.
GT_CONST kHistoryFramesShift = 24;
GT_CONST kMaxHistoryFrames = 127;
GT_CONST kEdgeMixBit = 31;
GT_CONST kGroupX = 8;
GT_CONST kGroupY = 8;

// Cameras as pinholes (see trace::CameraPush); up = cross(right, forward). 128 bytes, the
// smallest push-constant limit Vulkan allows.
struct TaaPush {
    vec4 currentOrigin;  // xyz, w = tan(yfov / 2)
    vec4 currentForward; // xyz, w = aspect
    vec4 currentRight;   // xyz, w = the gaze in pixels as two halves (packHalf2x16's bits)
    vec4 previousOrigin;
    vec4 previousForward;
    vec4 previousRight; // xyz, w = eccentric radius r in pixels (0: off): beyond |r| from the
                        // gaze the current weight is divided and the clip box multiplied by
                        // d / |r| (camera still), sqrt(d / |r|) (r < 0: the camera moved)
    vec4 params;  // x = blend weight of the current frame, y = clip gamma, z = -1: reset, else
                  // the exposure of display-referred blending (0: linear), w = depth tolerance
    vec4 centres; // off-axis frustum centres as tangents: xy current, zw previous (0: symmetric)
};

GT_NAMESPACE_END
#endif
