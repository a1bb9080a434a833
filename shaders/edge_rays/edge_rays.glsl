// Pass `edge_rays`: in a scene that moves, a moving object's outline is where temporal
// anti-aliasing has least to work with. Its pixels change surface every frame, so their history
// is resampled along the motion, and the sparse samples a point set reconstructs them from blend
// across the edge. A pixel whose 3x3 neighbourhood shows more than one surface, one of them
// moving, gets a ray of its own through a jittered point inside it, as the reference traces
// every pixel; TAA then pools these as it pools a still edge's samples (support 0: sampled in
// the pixel). Every other pixel is copied.
#include "edge_rays_shared.h"
#include "random.glsl"
#include "trace.glsl"
#include "motion.glsl"

layout(local_size_x = kGroupSizeX, local_size_y = kGroupSizeY) in;
layout(set = 0, binding = kBindingRadiance, rgba32f) uniform readonly image2D uRadiance;
layout(set = 0, binding = kBindingMotion, rgba32f) uniform readonly image2D uMotionIn;
layout(set = 0, binding = kBindingRadianceOutput, rgba32f) uniform writeonly image2D uRadianceOut;
layout(set = 0, binding = kBindingMotionOutput, rgba32f) uniform writeonly image2D uMotionOut;
#ifdef EDGE_RAYS_SUPPORT
layout(set = 0, binding = kBindingSupport, r32f) uniform readonly image2D uSupport;
layout(set = 0, binding = kBindingSupportOutput, r32f) uniform writeonly image2D uSupportOut;
#endif
layout(push_constant) uniform Push { EdgeRaysPush pc; };

// Whether the pixel lies on a moving edge: its 3x3 neighbourhood shows more than one surface
// (a signature code's bits above the shadow mask) and one of them moves.
bool onMovingEdge(ivec2 px, ivec2 size) {
    uint first = uint(imageLoad(uMotionIn, px).w) >> 8u;
    bool mixed = false, moving = false;
    for (int t = 0; t < 9; ++t) {
        vec4 m = imageLoad(uMotionIn, clamp(px + ivec2(t % 3, t / 3) - 1, ivec2(0), size - 1));
        mixed = mixed || (uint(m.w) >> 8u) != first;
        moving = moving || dot(m.xyz, m.xyz) > 0.0;
    }
    return mixed && moving;
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(pc.params.xy);
    if (any(greaterThanEqual(px, size))) return;
    if (!onMovingEdge(px, size)) {
        imageStore(uRadianceOut, px, imageLoad(uRadiance, px));
        imageStore(uMotionOut, px, imageLoad(uMotionIn, px));
#ifdef EDGE_RAYS_SUPPORT
        imageStore(uSupportOut, px, imageLoad(uSupport, px));
#endif
        return;
    }
    CameraPush cam = CameraPush(pc.origin, pc.forward, pc.right, pc.up);
    uint pixelIndex = uint(px.y) * pc.params.x + uint(px.x);
    vec2 o = sampleOffset(pixelIndex, 0u, 1u, pc.params.w);
    vec3 dir = cameraRay(cam, vec2(px) + o, vec2(size));
    float depth;
    vec3 radiance = traceRadiance(pc.origin.xyz, dir, depth);
    imageStore(uRadianceOut, px, vec4(radiance, depth));
    imageStore(uMotionOut, px, kDynamic ? storedMotion() : vec4(0.0));
#ifdef EDGE_RAYS_SUPPORT
    imageStore(uSupportOut, px, vec4(0.0));
#endif
}
