// Pass `point_denoise`: an edge-avoiding filter over the point set's neighbour graph, on the
// path tracer's samples before interpolation, its strength rising with eccentricity.
#ifndef POINT_DENOISE_SHARED_H
#define POINT_DENOISE_SHARED_H
#include "gt_shared.h"

GT_NAMESPACE_BEGIN(point_denoise)

GT_CONST kBindingPoints = 0;     // samplerBuffer RGBA32F: canvas x, y, spacing p, 0
GT_CONST kBindingNeighbours = 1; // usamplerBuffer R32UI: the stored neighbours of every point
GT_CONST kBindingSamples = 2;    // buffer of vec4: point_sample's mean radiance, first-hit distance
GT_CONST kBindingGuide = 3;      // buffer of vec4: point_sample's guides (point_guide.glsl)
GT_CONST kBindingInput = 4;      // buffer of vec4: demodulated light rgb, its luminance variance
GT_CONST kBindingOutput = 5;     // buffer of vec4: the same after this step; the last step
                                 // writes samples (rgb remodulated, first-hit distance)
GT_CONST kGroupSize = 64;

// The temporal step (point_temporal.comp), its own pipeline: the samples' light demodulated and
// blended with the history of the surface each point hits, found where that hit was seen last
// frame. kBindingPoints, kBindingSamples and kBindingGuide as above.
GT_CONST kBindingTemporalNearest = 1; // usamplerBuffer R32UI: the nearest point per canvas pixel
GT_CONST kBindingTemporalOutput = 4;  // buffer of vec4: accumulated light rgb, its variance
GT_CONST kBindingHistoryLight = 5;    // rgba32f: last frame's accumulated light, frame variance
GT_CONST kBindingHistoryHit = 6; // rgba32ui: last frame's hit (its camera frame), normal, count
GT_CONST kBindingNextLight = 7;  // the same, written for the next frame
GT_CONST kBindingNextHit = 8;
GT_CONST kBindingHistoryAlbedo =
    9; // r32ui: last frame's accumulated albedo (10 bits an rgb channel)
GT_CONST kBindingNextAlbedo = 10;
GT_CONST kBindingTemporalGuide = 11;      // buffer of vec4: the guides, the albedo accumulated
GT_CONST kBindingTemporalNeighbours = 12; // as kBindingNeighbours
// Point i's history lives at texel (i % kHistoryWidth, i / kHistoryWidth).
GT_CONST kHistoryWidth = 4096;
GT_CONST kHistoryMaxFrames = 255; // the count's 8 bits

// Which step a dispatch runs (PointDenoisePush::step.y).
GT_CONST kStepDemodulate = 0; // the samples' light without the albedo, and its variance
GT_CONST kStepFilter = 1;     // one pass over every point's neighbours
GT_CONST kStepLast = 2;       // the same, written back as samples
// PointDenoisePush::step.z: the input of kStepDemodulate is point_temporal's (demodulated light
// and its variance) rather than the samples themselves.
GT_CONST kInputTemporal = 1;

struct PointDenoisePush {
    // xy: canvas -> screen offset (point_sample's); z: the sampling margin (pixels); w: the
    // frame and half the sites' jitter scale, as point_sample's lensCoeffs.w
    vec4 offset;
    // x = width, y = height, z = point count, w = neighbours stored per point
    uvec4 params;
    // The camera's tangent plane (trace::CameraPush): x = tan(yfov / 2), y = aspect,
    // z = frustum centre x, w = centre y (tangents)
    vec4 frustum;
    // x = luminance sigma (in standard deviations), y = depth sigma (relative to the point's
    // distance), z = eccentricity (degrees) below which nothing is filtered, w = eccentricity
    // from which the filter has its full strength
    vec4 sigmas;
    vec4 lens;       // the panel warp, as point_sample's (w = 0: none)
    vec4 lensCoeffs; // x = k1, y = k2, z = 1 / (1 + k1 + k2)
    // x, y: the gaze (screen pixels); z = the normal term's exponent; w = the spatial kernel's
    // standard deviation in units of the point's spacing
    vec4 gaze;
    // x = neighbours read per point (at most params.w), y = kStep*
    uvec4 step;
};

struct PointTemporalPush {
    vec4 offset; // as PointDenoisePush::offset
    // x = width, y = height, z = point count, w = canvas width | canvas height << 16
    uvec4 params;
    vec4 frustum; // as PointDenoisePush::frustum, the same for both frames
    // Rows of the 3x4 transform from this frame's camera frame (x right, y up, z forward) into
    // last frame's: p' = (dot(r0.xyz, p) + r0.w, ...)
    vec4 toPrevious0;
    vec4 toPrevious1;
    vec4 toPrevious2;
    // xy: last frame's canvas -> screen offset; z = the blend weight alpha of this frame once a
    // history holds enough frames; w = the neighbours stored per point + 1 when the history
    // holds last frame, else 0
    vec4 previous;
    // xy: the gaze (screen pixels); z, w: the fovea's eccentricities as PointDenoisePush::sigmas
    vec4 gaze;
};

GT_NAMESPACE_END
#endif
