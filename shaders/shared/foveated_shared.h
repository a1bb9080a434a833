// Passes `point_sample` and `interpolate` (thesis, sections 4.2 and 4.3).
#ifndef FOVEATED_SHARED_H
#define FOVEATED_SHARED_H
#include "trace_shared.h"

GT_NAMESPACE_BEGIN(foveated)

// point_sample: the eight scene bindings (trace_shared.h), then:
GT_CONST kBindingPoints = 9;   // samplerBuffer RGBA32F: canvas x, y, spacing p, 0
GT_CONST kBindingSamples = 10; // buffer of vec4: mean radiance rgb, first-hit distance
// buffer of uint: the chunks of kSampleGroupSize points to trace this frame (point_chunks.hpp)
GT_CONST kBindingChunks = 11;
// buffer of vec4, in a scene that moves (trace::GpuScene::dynamic()): per point the first hit
// of its ray 0 as motion.glsl stores it (xyz: world position one frame ago minus now, w: the
// signature code); unwritten otherwise
GT_CONST kBindingSampleMotion = 12;
// buffer of vec4, from the path integrator: per point the point denoiser's guides
// (shaders/common/point_guide.glsl); unwritten otherwise
GT_CONST kBindingSampleGuide = 13;
GT_CONST kSampleGroupSize = 64;

// Specialisation constant of point_sample (ids 0-3 are trace.glsl's and its own, 4-7 the
// integrator's): the radius in canvas pixels around the centre of interest within which a point
// traces the fovea's rays (float bits; 0: every point traces the same).
GT_CONST kSpecFoveaRadius = 8;

struct PointSamplePush {
    vec4 origin; // camera, as trace::CameraPush
    vec4 forward;
    vec4 right;
    vec4 up;
    vec4 offset; // x, y: canvas -> screen offset (gaze - (W, H)); z: margin in pixels;
                 // |w|: geometric LOD levels to choose from by the point's spacing (<= 1.5:
                 // off); w < 0: rays anywhere in the point's disc (the thesis), else within
                 // kRayDiscMaxPx of the site
    // x = width, y = height, z = rays per point (low 16 bits) and rays per point within
    // kFoveaRadius (high 16 bits; 0: the same), w = point count
    uvec4 params;
    // The set laid on an HMD's panel (engine/display/display_space.hpp): each ray's panel
    // position goes through the lens model into the image before it is traced.
    vec4 lens;       // xy: lens centre (normalised), z: aspect, w: rMax (0: no warp)
    vec4 lensCoeffs; // x = k1, y = k2, z = 1 / (1 + k1 + k2), w = frame number (mod 2^16):
                     // rays rotate in their discs; plus half the scale s < 2 by which the sites
                     // move (site_jitter.glsl; 0: they stay put)
};

// interpolate:
GT_CONST kBindingInterpPoints = 0;  // samplerBuffer RGBA32F (as kBindingPoints)
GT_CONST kBindingInterpSamples = 1; // buffer of vec4 (as kBindingSamples)
GT_CONST kBindingNearest = 2;       // usamplerBuffer R32UI: nearest point per canvas pixel
GT_CONST kBindingNeighbours = 3;    // usamplerBuffer R32UI: kMax neighbours per point
GT_CONST kBindingInterpOutput = 4;  // image2D rgba32f
// image2D r32f: per pixel, the distance to the sample it took most from (its nearest), in units
// of that point's spacing p: how directly this frame saw the pixel (TAA weighs by it).
GT_CONST kBindingInterpSupport = 10;
// interpolate_motion.comp, in a scene that moves: the samples' motion (kBindingSampleMotion) in,
// and per pixel the motion of its nearest sample out (image2D rgba32f, as the samples').
GT_CONST kBindingInterpSampleMotion = 14;
GT_CONST kBindingInterpMotion = 15;
// Every method but nearest neighbour: where each point sits on the screen this frame, its sites
// pass's buffer (kBindingSitesOut) as a samplerBuffer RGBA32F.
GT_CONST kBindingInterpSites = 16;
GT_CONST kInterpGroupX = 8;
GT_CONST kInterpGroupY = 8;
GT_CONST kMaxK = 20;

GT_CONST kMethodNearest = 0;
GT_CONST kMethodShepard = 1;
GT_CONST kMethodRbf = 5;
// Debug views (--view): the sampled points, the nearest-neighbour cells (thesis Figure 8) and
// the point spacing as a heat map.
GT_CONST kViewPoints = 2;
GT_CONST kViewCells = 3;
GT_CONST kViewSpacing = 4;

struct InterpolatePush {
    vec4 offset;  // x, y: canvas -> screen offset; z: margin; w: Shepard power (1 thesis, 2 Renka)
    uvec4 params; // x = width, y = height, z = k, w = method
    uvec4 canvas; // x = canvas width, y = canvas height, z = neighbours stored per point,
                  // w = RBF kernel
    vec4 rbf;     // x = shape c in units of the spacing p; y = exposure of display-referred
                  // blending (0: linear radiance, the thesis); z = depth tolerance of the
                  // geometry-aware weights (0: off); w = luminance sigma of the
                  // colour-guided weights (0: off)
    uvec4 table;  // x = slot texels per row (flat: per pixel) of the k-NN table, y = its
                  // k, z = texels per canvas pixel of the RBF pixel weights (RBF with the table),
                  // w = the frame whose moved sites it blends from (kBindingInterpSites; 0: the
                  // sites stay put)
};

// interpolate's sites pass (interpolate_sites.comp): where every point of the set sits on the
// screen this frame (site_jitter.glsl), once per point rather than once for every pixel that
// weighs it.
GT_CONST kBindingSitesPoints = 0; // samplerBuffer RGBA32F (as kBindingPoints)
GT_CONST kBindingSitesOut = 1;    // buffer of vec4: screen x, y, spacing p, 0
GT_CONST kSitesGroup = 64;

struct SitesPush {
    vec4 offset;  // x, y: canvas -> screen offset; z: the scale of the sites' moves; w unused
    uvec4 params; // x = points, y = the frame whose moved sites (0: fixed), z = groups in x
};

// interpolate, RBF only: the weights rbf_solve wrote, one float per neighbour and channel.
GT_CONST kBindingLambdaR = 5;
GT_CONST kBindingLambdaG = 6;
GT_CONST kBindingLambdaB = 7;
// interpolate with the thesis's per-canvas-pixel k-NN table, flat (per canvas pixel its k
// nearest point indices, RGBA32UI, four a texel, in kBindingKnnTable alone) or in its compact
// layout (engine/foveation/pixel_knn_table.hpp): the canvas in kKnnTile x kKnnTile tiles, each
// with its candidate points and its distinct rows of k slots into them, and per pixel its row.
GT_CONST kBindingKnnTable = 8;       // usamplerBuffer RGBA8UI/RGBA16UI: rows' slots, 4 a texel
GT_CONST kBindingKnnTiles = 11;      // usamplerBuffer RG32UI: per tile, candidate and row base
GT_CONST kBindingKnnCandidates = 12; // usamplerBuffer R32UI: point indices
GT_CONST kBindingKnnPixelRows = 13;  // usamplerBuffer R8UI: per canvas pixel, its row in its tile
GT_CONST kKnnTile = 8;
// interpolate, RBF with the k-NN table: samplerBuffer RGBA32F, per canvas pixel the weights of
// its k table neighbours (engine/foveation/rbf_pixel_weights.hpp), four to a texel.
GT_CONST kBindingRbfPixelWeights = 9;

// rbf_solve (thesis, eqs. 7-10): for every sampled point q, the weights of the RBF
// interpolant through q and its k-1 nearest neighbours, from the precomputed inverse.
GT_CONST kBindingSolvePoints = 0;     // samplerBuffer RGBA32F
GT_CONST kBindingSolveSamples = 1;    // buffer of vec4
GT_CONST kBindingSolveNeighbours = 2; // usamplerBuffer R32UI
GT_CONST kBindingSolveLambdaR = 3;    // buffer of float, k per point
GT_CONST kBindingSolveLambdaG = 4;
GT_CONST kBindingSolveLambdaB = 5;
GT_CONST kBindingSolveInverse = 6; // samplerBuffer RGBA32F: per point, the k x k inverse
GT_CONST kSolveGroupSize = 64;
GT_CONST kKernelMultiquadric = 0; // phi(r) = sqrt(r^2 + c^2)  (thesis eq. 10)
GT_CONST kKernelGaussian = 1;     // phi(r) = exp(-(r / c)^2)   (thesis eq. 9, c as a length)

struct RbfSolvePush {
    vec4 offset;  // x, y: canvas -> screen offset; z: margin; w: shape c in units of the spacing p
    uvec4 params; // x = width, y = height, z = k, w = kernel
    uvec4 counts; // x = points, y = neighbours stored per point, z = inverse texels per point
};

GT_NAMESPACE_END
#endif
