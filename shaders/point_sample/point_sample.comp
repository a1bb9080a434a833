#version 460
// Pass `point_sample` (thesis, 4.2): the point set shifted to the gaze; every point on screen
// or within the margin is traced with R rays through random positions inside its disc (radius
// p in the thesis; by default here at most 0.6 px, kRayDiscMaxPx below). The positions come
// from the point's index and the ray's number, so they do not depend on which thread traces
// them. In the thesis they are the same every frame, so TAA over a still
// view adds nothing; here frame f > 0 rotates them (a Cranley-Patterson shift of the angle and
// the squared radius by the R2 low-discrepancy sequence), so TAA gathers new rays each frame
// and a still view converges to the disc's mean. Frame 0 is the thesis's.
//
// kLanes threads share a point and trace its rays side by side (lane l takes rays l, l + kLanes,
// ...), summed in shared memory. On a GPU the lanes of a subgroup then follow nearly the same
// path through the BVH, and a frame has up to R times as many threads to fill the machine
// with. With kLanes = 1 a thread traces all R rays of its point, which suits a CPU driver
// (PointSamplePass picks). The group stays 1-D either way: lavapipe packs its SIMD lanes along
// local_size_x only.
//
// With kChunked the dispatch covers only the chunks of kSampleGroupSize consecutive points
// that can land on screen (engine/foveation/point_chunks.hpp), listed per frame in `chunks`:
// the set's Morton order makes a chunk a compact patch of the canvas, so a workgroup traces
// neighbouring rays and none is spent on a patch off screen. A point keeps its index, and its
// rays with it.
#extension GL_GOOGLE_include_directive : require
#include "foveated_shared.h"
#include "random.glsl"
#include "site_jitter.glsl"
#include "trace.glsl"
#include "path.glsl"
#include "motion.glsl"
#include "panel_warp.glsl"
#include "point_guide.glsl"

layout(local_size_x = kSampleGroupSize) in;
layout(constant_id = 1) const uint kLanes = 1u; // a power of two up to kSampleGroupSize / 2
layout(constant_id = 2) const bool kChunked = false;
layout(constant_id = kSpecFoveaRadius) const float kFoveaRadius = 0.0;
layout(set = 0, binding = kBindingPoints) uniform samplerBuffer uPoints;
layout(std430, set = 0, binding = kBindingSamples) writeonly buffer Samples { vec4 samples[]; };
layout(std430, set = 0, binding = kBindingChunks) readonly buffer Chunks { uint chunks[]; };
layout(std430, set = 0, binding = kBindingSampleMotion) writeonly buffer SampleMotion {
    vec4 sampleMotion[];
};
layout(std430, set = 0, binding = kBindingSampleGuide) writeonly buffer SampleGuide {
    vec4 sampleGuide[];
};
layout(push_constant) uniform Push { PointSamplePush pc; };

shared vec4 partial[kSampleGroupSize]; // rgb and the sum of squared luminance
// A ray lands within min(p, 0.6) px of its point's site, not anywhere in the point's disc of
// radius p as in the thesis: averaging a sparse point's whole disc blurs the periphery by its
// spacing (3-6 px beyond 20 deg) before interpolation blurs it again, and lets a lamp in the
// disc brighten the point (the bleeding eval measures). Rays about one display pixel wide keep
// the detail each point can carry; the area between points is rebuilt by interpolation, and
// over frames by the moving sites and TAA. Measured with eval on builtin:market (fove, 4 rays
// per point, scale 1): FLIP 10-20 deg 0.0336 -> 0.0261, 20+ 0.0126 -> 0.0088, bleeding
// 9.9 -> 4.3 /255; the fovea (p = 0.56 px) is unchanged.
// Points sparser than 1.5 px keep their rays within 0.35 px: such a point's sample stands for
// the pixels around it, and one that straddles a bright/dark edge (a grey mean) greys the dark
// side for pixels away; a near-point sample is either side. At scale 2 (market, eval) the
// bleeding fell from 5.1-6.1 to 3.6-4.5 /255; denser points keep 0.6 px, as their pixel-wide
// average is the anti-aliasing the reference's pixels have (0.35 everywhere cost FLIP 0-5 deg
// 0.0090 -> 0.0116).
const float kRayDiscMaxPx = 0.6;
const float kRayDiscSparsePx = 0.35;
const float kSparseSpacingPx = 1.5;

// Panel pixel -> image pixel through the lens (green), when the set is laid on the panel.
vec2 toImage(vec2 panel, vec2 size) { return panelToImage(panel, size, pc.lens, pc.lensCoeffs); }

// The path tracer's points carry their guides for the point denoiser (point_guide.glsl).
const bool kWritesGuide = kIntegrator == kIntegratorPath;

// The variance of the mean of `rays` luminances from their sum and sum of squares (unbiased;
// unknown, < 0, for one ray).
float meanVariance(float sum, float sumSq, float rays) {
    return rays > 1.0 ? max(sumSq - sum * sum / rays, 0.0) / (rays * (rays - 1.0)) : -1.0;
}

// The point this invocation traces rays of: a chunk takes kLanes workgroups, each
// kSampleGroupSize / kLanes of its points, as the whole set's dispatch would.
uint pointIndex() {
    if (!kChunked) return gl_GlobalInvocationID.x / kLanes;
    const uint chunk = chunks[gl_WorkGroupID.x / kLanes];
    return chunk * kSampleGroupSize + (gl_WorkGroupID.x % kLanes) * (kSampleGroupSize / kLanes)
         + gl_LocalInvocationIndex / kLanes;
}

void main() {
    const uint i = pointIndex();
    const uint lane = gl_LocalInvocationIndex % kLanes;
    const uint raysAway = pc.params.z & 0xffffu, raysFovea = pc.params.z >> 16;
    const vec2 size = vec2(pc.params.xy);
    const float margin = pc.offset.z;
    vec4 p = vec4(0.0);
    vec2 s = vec2(0.0);
    bool onScreen = false;
    // lensCoeffs.w: the frame (rays rotate in their discs) plus half the sites' jitter scale.
    const float frameField = floor(pc.lensCoeffs.w);
    const uint siteFrame = uint(frameField);
    const float siteScale = 2.0 * (pc.lensCoeffs.w - frameField);
    if (i < pc.params.w) {
        p = texelFetch(uPoints, int(i));
        s = p.xy + pc.offset.xy + siteJitter(i, siteFrame, p.z, siteScale);
        onScreen = all(greaterThanEqual(s, vec2(-margin))) && all(lessThan(s, size + margin));
    }
    if (kLanes == 1u && !onScreen) return; // a specialisation constant: no barrier follows
    // Paths per point by eccentricity: more where the eye resolves most (the canvas centre is
    // the gaze), as Mohanto et al. 2024's samples per pixel by eccentricity band.
    const bool inFovea = kFoveaRadius > 0.0 && raysFovea > 0u &&
                         length(p.xy - vec2(pc.params.xy)) <= kFoveaRadius;
    const uint rays = inFovea ? raysFovea : raysAway;
    const CameraPush cam = CameraPush(pc.origin, pc.forward, pc.right, pc.up);
    // The ray cone spreads by a display pixel's angle, as the reference's (the periphery's
    // sparser points are prefiltered by TAA over their moving sites, not by wider cones).
    gPixelSpread = 2.0 * cam.origin.w / size.y;
    // Geometric LOD (Guenter et al. 2012, 6, here for the point set): a point whose neighbours lie p pixels
    // apart resolves no detail finer than that, so it traces the scene's subdivision cages
    // one level coarser per doubling past 4 px (scene::lodForPitch). Each point keeps its level
    // as the set follows the gaze.
    // offset.w: the LOD levels (magnitude; <= 1.5 off), negative for the thesis's ray disc.
    const float lodLevels = abs(pc.offset.w);
    const float disc = pc.offset.w < 0.0 ? p.z
                     : p.z >= kSparseSpacingPx ? kRayDiscSparsePx : min(p.z, kRayDiscMaxPx);
    if (lodLevels > 1.5 && p.z >= 4.0) {
        selectLod(min(uint(floor(log2(p.z * 0.5))), uint(lodLevels) - 1u));
    }
    vec3 sum = vec3(0.0);
    float sumSq = 0.0; // of the rays' luminance
    vec3 firstNormal = vec3(0.0), firstAlbedo = vec3(1.0);
    float firstDepth = 0.0; // first-hit distance of ray 0 (always lane 0's), for TAA
    vec4 firstMotion = vec4(0.0); // and its motion, in a scene that moves
    for (uint r = lane; onScreen && r < rays; r += kLanes) {
        vec2 pos = s;
        float frame = frameField;
        if (rays > 1u || frame > 0.0) {
            uint h = pcgHash(i * 0x9E3779B9u ^ pcgHash(r + 0x51ED27u));
            float angle = 6.28318531 * fract(hashToFloat(h) + frame * 0.7548776662);
            float radius = disc * sqrt(fract(hashToFloat(pcgHash(h)) + frame * 0.5698402910));
            pos += radius * vec2(cos(angle), sin(angle));
        }
        float depth;
        const vec3 radiance = traceIntegrator(pc.origin.xyz, cameraRay(cam, toImage(pos, size), size),
                                              i, r, rays, siteFrame, depth);
        sum += radiance;
        sumSq += luminance(radiance) * luminance(radiance);
        if (r == 0u) {
            firstDepth = depth;
            if (kDynamic) firstMotion = storedMotion();
            firstNormal = gFirstNormal;
            firstAlbedo = gFirstAlbedo;
        }
    }
    if (kLanes > 1u) {
        partial[gl_LocalInvocationIndex] = vec4(sum, sumSq);
        barrier(); // every thread of the group reaches it: off-screen ones only skip the tracing
        if (lane != 0u || !onScreen) return;
        for (uint l = 1u; l < kLanes; ++l) {
            sum += partial[gl_LocalInvocationIndex + l].rgb;
            sumSq += partial[gl_LocalInvocationIndex + l].a;
        }
    }
    samples[i] = vec4(sum / float(rays), firstDepth);
    if (kDynamic) sampleMotion[i] = firstMotion;
    if (kWritesGuide) {
        sampleGuide[i] = encodePointGuide(firstNormal, firstAlbedo,
                                          meanVariance(luminance(sum), sumSq, float(rays)));
    }
}
