// Pass `taa`: the previous output reprojected through the first-hit distance and both cameras,
// clipped to the current frame's 3x3 neighbourhood in YCoCg (variance clipping, Salvi 2016),
// then blended. History is rejected where the reprojected distance disagrees (disocclusion),
// off screen, and on reset — a saccade or gaze jump — so the fovea is sharp at once instead
// of converging (Patney et al. 2016, as summarised in the thesis, section 3.1).
#include "taa_shared.h"

layout(local_size_x = kGroupX, local_size_y = kGroupY) in;
layout(set = 0, binding = kBindingCurrent, rgba32f) uniform readonly image2D uCurrent;
layout(set = 0, binding = kBindingHistory, rgba32f) uniform readonly image2D uHistory;
layout(set = 0, binding = kBindingOutput, rgba32f) uniform writeonly image2D uOutput;
layout(push_constant) uniform Push { TaaPush pc; };
// Camera and gaze still over a scene that does not move (taa.cpp sets it where the push says
// so: no clipping, no distance test, no eccentric falloff): the pipeline is then built without
// that code, as a driver that runs both sides of a branch on its SIMD lanes (lavapipe) pays
// for it even where no pixel takes it.
layout(constant_id = 3) const bool kStillView = false;
#ifdef TAA_SUPPORT
// A method that rebuilds the image from sparse samples whose sites move every frame (the point
// set, site_jitter.glsl) reports per pixel the distance s to the sample it took most from, in
// units of the sample spacing. On a still view each frame then counts by how near its samples
// fell, w = floor + exp(-(s / sigma)^2), in a weighted running mean whose weight sum W is a
// history of its own: a pixel ends up built from the frames that sampled it closely, as if the
// frames' samples were pooled (temporal supersampling), instead of the mean of interpolated
// frames, which blurs by the sample spacing. The floor keeps the estimate moving where no site
// ever comes close.
layout(set = 0, binding = kBindingSupport, r32f) uniform readonly image2D uSupport;
layout(set = 0, binding = kBindingWeightHistory, r32f) uniform readonly image2D uWeightHistory;
layout(set = 0, binding = kBindingWeightOutput, r32f) uniform writeonly image2D uWeightOutput;
// eval, builtin:market, fove, 4 rays per point, after 8 still frames: sigma 0.2 and floor 0.002
// against the plain running mean take flip_ecc beyond 20 deg from 0.0060 to 0.0035 and the
// bleeding from 4.5 to 1.7 /255 (sigma 0.35 / floor 0.05: 0.0046; 0.25 / 0.005: 0.0037).
const float kSupportSigma = 0.2;
const float kSupportFloor = 0.002;
const float kMaxWeight = 64.0; // as TaaSettings::maxStillFrames caps the plain running mean
#endif
#ifdef TAA_MOTION
// A scene that moves: each pixel's first hit moved by motion.xyz since last frame (world
// space), so history is fetched where the moved point was seen, p + motion, through the
// previous camera; and it is rejected where the surface or shadow the history shows is not the
// pixel's now (its signature, motion.glsl), which is what removes the trail of a moving object
// and of a moving shadow. The still view's shortcuts (no clipping, no distance test, pooling
// over up to kMaxWeight) hold only where the hit neither moved nor changed: a pixel whose
// hit moved blends as on a moving camera, with these (TaaSettings::currentWeight, clipGamma and
// depthTolerance, set per pipeline). A history stands for no more frames than it gathered since
// it was last rejected: a pixel uncovered k frames ago blends as the running mean of its k
// frames (weight 1 / k) until the blend weight's own bound takes over, where a fixed weight
// would leave it mostly its first, unfiltered frame for many frames. A moving object's edge
// keeps its anti-aliasing: the pixels around it follow the object (edgeMotion) and keep the
// history of either side, sampled sharply (historyOfSurface), and a moved pixel pools its
// frames by how near their samples fell, as a still one does.
layout(set = 0, binding = kBindingMotion, rgba32f) uniform readonly image2D uMotion;
layout(set = 0, binding = kBindingSignatureHistory, r32ui) uniform readonly uimage2D uSignatureHistory;
layout(set = 0, binding = kBindingSignatureOutput, r32ui) uniform writeonly uimage2D uSignatureOutput;
layout(constant_id = 0) const float kMovingWeight = 0.1;
layout(constant_id = 1) const float kMovingGamma = 1.0;
layout(constant_id = 2) const float kMovingTolerance = 0.05;
#endif

vec3 toYCoCg(vec3 c) {
    return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * c.r - 0.5 * c.b,
                -0.25 * c.r + 0.5 * c.g - 0.25 * c.b);
}
vec3 fromYCoCg(vec3 c) { return vec3(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z); }

// Clips `h` towards the box centre `m` so it lies inside [m - e, m + e].
vec3 clipToBox(vec3 h, vec3 m, vec3 e) {
    vec3 d = h - m;
    vec3 unit = abs(d / max(e, vec3(1e-6)));
    float f = max(unit.x, max(unit.y, unit.z));
    return f > 1.0 ? m + d / f : h;
}

// The mean m1 and standard deviation sigma of the current frame's 3x3 neighbourhood around
// `px` in YCoCg: the clipping box's centre and half-size in units of gamma. Only a pixel that
// clips needs them.
void neighbourhood(ivec2 px, ivec2 size, out vec3 m1, out vec3 sigma) {
    m1 = vec3(0.0);
    vec3 m2 = vec3(0.0);
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            vec3 c = toYCoCg(imageLoad(uCurrent, clamp(px + ivec2(dx, dy), ivec2(0), size - 1)).rgb);
            m1 += c;
            m2 += c * c;
        }
    }
    m1 /= 9.0;
    sigma = sqrt(max(m2 / 9.0 - m1 * m1, vec3(0.0)));
}

// Radiance -> an approximation of the displayed value: Reinhard's c / (1 + e L) (which maps
// every radiance below 1 in luminance at exposure e), then a 1 / 2.2 power as the display
// encoding; and back.
float luma(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }
vec3 toDisplay(vec3 c, float e) {
    return pow(max(c / (1.0 + e * luma(c)), vec3(0.0)), vec3(1.0 / 2.2));
}
vec3 fromDisplay(vec3 y, float e) {
    vec3 t = pow(max(y, vec3(0.0)), vec3(2.2));
    return t / max(1.0 - e * luma(t), 1e-3);
}

// The history and this frame blended with weight alpha on this frame: display-referred
// (params.z = exposure e > 0), in the space of toDisplay, close to what the display shows, so a
// frame moves a pixel by at most alpha of its displayed range (a firefly, or a dark pixel where
// sRGB is steep, no longer jumps); else in linear radiance.
vec3 blendFrames(vec3 history, vec3 current, float alpha) {
    float e = pc.params.z;
    return e > 0.0 ? fromDisplay(mix(toDisplay(history, e), toDisplay(current, e), alpha), e)
                   : mix(history, current, alpha);
}

// The unit ray through the centre of pixel `px` of the current camera.
vec3 pixelRay(ivec2 px, ivec2 size) {
    vec2 s = (vec2(px) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec3 up = cross(pc.currentRight.xyz, pc.currentForward.xyz);
    return normalize(pc.currentForward.xyz
                     + (s.x * pc.currentOrigin.w * pc.currentForward.w + pc.centres.x) * pc.currentRight.xyz
                     + (pc.centres.y - s.y * pc.currentOrigin.w) * up);
}

vec4 historyBilinear(vec2 p, ivec2 size) {
    vec2 q = p - 0.5;
    ivec2 i = ivec2(floor(q));
    vec2 f = q - vec2(i);
    vec4 a = imageLoad(uHistory, clamp(i, ivec2(0), size - 1));
    vec4 b = imageLoad(uHistory, clamp(i + ivec2(1, 0), ivec2(0), size - 1));
    vec4 c = imageLoad(uHistory, clamp(i + ivec2(0, 1), ivec2(0), size - 1));
    vec4 d = imageLoad(uHistory, clamp(i + ivec2(1, 1), ivec2(0), size - 1));
    // Distances do not blend across edges: take the nearest tap's.
    vec4 colour = mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
    vec4 nearest = f.y < 0.5 ? (f.x < 0.5 ? a : b) : (f.x < 0.5 ? c : d);
    return vec4(colour.rgb, nearest.a);
}

#ifdef TAA_MOTION
const uint kSignatureMask = (1u << kHistoryFramesShift) - 1u;
const uint kShadowMask = 0xffu; // motion.glsl: the lights reaching the hit, below the surface id

// Whether the surface a motion texel shows moves (the sky and static geometry never do).
bool surfaceMoves(vec4 motion) { return dot(motion.xyz, motion.xyz) > 0.0; }

// The 3x3 pixels around this invocation's pixel now: the surface each shows (a signature code's
// bits above the shadow mask) and whether it moves. Read once (readAround); every history test
// below asks them.
uint gAroundSurface[9];
bool gAroundMoves[9];

void readAround(ivec2 px, ivec2 size) {
    for (int t = 0; t < 9; ++t) {
        vec4 m = imageLoad(uMotion, clamp(px + ivec2(t % 3, t / 3) - 1, ivec2(0), size - 1));
        gAroundSurface[t] = uint(m.w) >> 8u;
        gAroundMoves[t] = surfaceMoves(m);
    }
}

// Whether the surface `surface` shows around the pixel now; with `still`, also standing still
// wherever it does.
bool beside(uint surface, bool still) {
    bool seen = false;
    for (int t = 0; t < 9; ++t) {
        if (gAroundSurface[t] != surface) continue;
        if (still && gAroundMoves[t]) return false;
        seen = true;
    }
    return seen;
}

// The motion a pixel at a moving edge follows: where its 3x3 neighbourhood shows more than one
// surface and the nearest of them moves, that one's, with its distance along this pixel's ray
// (`ray`). Jittered samples make such a pixel alternate between the surfaces, and the history
// that followed the foreground holds the edge's coverage. An edge where a moving surface
// passes behind another (an object rising out of a still box) is not followed: what the moving
// one shows now was hidden there last frame.
bool edgeMotion(ivec2 px, ivec2 size, uint surface, vec3 ray, inout float depth,
                inout vec3 follow) {
    bool mixed = false, moving = false;
    for (int t = 0; t < 9; ++t) {
        mixed = mixed || gAroundSurface[t] != surface;
        moving = moving || gAroundMoves[t];
    }
    if (!mixed || !moving) return false;
    float nearest = 3.0e38, nearestMoving = 3.0e38;
    int front = 0;
    for (int t = 0; t < 9; ++t) {
        float z = imageLoad(uCurrent, clamp(px + ivec2(t % 3, t / 3) - 1, ivec2(0), size - 1)).a;
        nearest = min(nearest, z);
        if (gAroundMoves[t] && z < nearestMoving) {
            nearestMoving = z;
            front = t;
        }
    }
    // In front within the distance tolerance of a moved pixel's disocclusion test: a contact
    // edge (a box on a floor) is followed, a rim standing in front is not.
    if (nearestMoving > nearest * (1.0 + kMovingTolerance)) return false;
    ivec2 q = clamp(px + ivec2(front % 3, front / 3) - 1, ivec2(0), size - 1);
    follow = imageLoad(uMotion, q).xyz;
    // Its distance along this pixel's ray, as if it were a plane facing the camera at the
    // neighbour's distance along the view axis.
    vec3 forward = pc.currentForward.xyz;
    depth = nearestMoving * dot(pixelRay(q, size), forward) / dot(ray, forward);
    return true;
}

// Whether a history texel shows the past of this pixel, whose surface now has the signature
// `now` (moving or not). The same signature does. So does another surface under the same
// lights that shows beside the pixel now, where the pixel follows a moving edge (edgeMotion)
// or where both stand still: jittered samples alternate between the two sides of an edge, and
// that history holds the edge's coverage, as a still scene's does. Otherwise another surface
// is a disocclusion (the one beside it moving now, even if it stood still last frame, as at
// the start of a motion), and other lights are a shadow that moved (whose occluder moved is
// not known, so a still shadow's edge is rejected too).
bool samePast(uint now, bool nowMoves, uint texel, bool followsEdge) {
    uint then = texel & kSignatureMask;
    if (then == now) return true;
    if ((then & kShadowMask) != (now & kShadowMask)) return false;
    if (followsEdge) return beside(then >> 8u, false);
    return !nowMoves && beside(then >> 8u, true);
}

// Catmull-Rom weights of the taps at -1, 0, 1 and 2 for a sample at fraction t past tap 0.
vec4 catmullRom(float t) {
    return vec4(t * (-0.5 + t * (1.0 - 0.5 * t)), 1.0 + t * t * (-2.5 + 1.5 * t),
                t * (0.5 + t * (2.0 - 1.5 * t)), t * t * (-0.5 + 0.5 * t));
}

// The history at `p` over the taps that show the pixel's past (samePast): a tap of another
// surface is not, and would bleed a moving object's colour into what it uncovered. Bilinear
// over the four nearest such taps (their weights renormalised), sharpened by Catmull-Rom over
// the 4x4 around them where p falls between texels, as a moving surface's history does every
// frame: bilinear alone blurs it a little each frame, which adds up along the motion. A tap
// not taken stands in as the bilinear estimate, and the result stays within the four taps'
// range (no ringing at an edge). Also the distance and frame count of the heaviest tap, and
// whether any holds a moving edge's mix (kEdgeMixBit). found = false where no tap shows the
// past.
vec4 historyOfSurface(vec2 p, ivec2 size, uint signature, bool moving, bool followsEdge,
                      out bool found, out uint frames, out bool edgeMix) {
    vec2 q = p - 0.5;
    ivec2 i = ivec2(floor(q));
    vec2 f = q - vec2(i);
    vec3 colour = vec3(0.0), lo = vec3(3.0e38), hi = vec3(-3.0e38);
    float total = 0.0, best = -1.0, depth = 0.0;
    frames = 0u;
    edgeMix = false;
    uint taken = 0u; // which of the four nearest taps show the past (bit t)
    for (int t = 0; t < 4; ++t) {
        ivec2 o = ivec2(t & 1, t >> 1);
        ivec2 at = clamp(i + o, ivec2(0), size - 1);
        float w = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y);
        uint h = imageLoad(uSignatureHistory, at).r;
        if (!samePast(signature, moving, h, followsEdge)) continue;
        taken |= 1u << uint(t);
        vec4 c = imageLoad(uHistory, at);
        colour += w * c.rgb;
        total += w;
        lo = min(lo, c.rgb);
        hi = max(hi, c.rgb);
        edgeMix = edgeMix || (h >> kEdgeMixBit) != 0u;
        if (w > best) {
            best = w;
            depth = c.a;
            frames = (h >> kHistoryFramesShift) & uint(kMaxHistoryFrames);
        }
    }
    found = total > 0.0;
    if (!found) return vec4(0.0);
    vec3 b = colour / total;
    // A still surface under a still camera lands on texel centres: nothing to sharpen.
    if (all(lessThan(min(f, 1.0 - f), vec2(1e-3)))) return vec4(b, depth);
    vec4 wx = catmullRom(f.x), wy = catmullRom(f.y);
    vec3 sharp = b;
    for (int t = 0; t < 16; ++t) {
        ivec2 o = ivec2(t & 3, t >> 2) - 1;
        ivec2 at = clamp(i + o, ivec2(0), size - 1);
        bool inner = all(greaterThanEqual(o, ivec2(0))) && all(lessThanEqual(o, ivec2(1)));
        bool past = inner ? (taken & (1u << uint(o.x + 2 * o.y))) != 0u
                          : samePast(signature, moving, imageLoad(uSignatureHistory, at).r,
                                     followsEdge);
        if (!past) continue;
        sharp += wx[o.x + 1] * wy[o.y + 1] * (imageLoad(uHistory, at).rgb - b);
    }
    return vec4(clamp(sharp, lo, hi), depth);
}

// Whether any of the 3x3 pixels around `px` shows something now that is not its counterpart's
// past around `prevPixel` last frame (samePast, judged by what stands beside `px`).
bool changedAround(ivec2 px, vec2 prevPixel, ivec2 size) {
    ivec2 prev = ivec2(floor(prevPixel));
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            ivec2 o = ivec2(dx, dy);
            vec4 now = imageLoad(uMotion, clamp(px + o, ivec2(0), size - 1));
            uint then = imageLoad(uSignatureHistory, clamp(prev + o, ivec2(0), size - 1)).r;
            if (!samePast(uint(now.w), surfaceMoves(now), then, false)) return true;
        }
    }
    return false;
}
#endif

#ifndef TAA_MOTION
// A still view's frame (kStillView: camera and gaze still, a scene that does not move): nothing
// clips, no distance is tested, nothing falls off with eccentricity, so the frame is the
// running mean main() computes then, read from the pixel's own history texel: with support, the
// frames weighted by it; without, the fixed weight alpha.
void stillViewBlend(ivec2 px, vec4 current, vec4 history
#ifdef TAA_SUPPORT
                    , float w
#endif
) {
    float alpha = pc.params.x;
#ifdef TAA_SUPPORT
    float weightSum = imageLoad(uWeightHistory, px).r;
    alpha = w / max(weightSum + w, 1e-6);
    imageStore(uWeightOutput, px, vec4(min(weightSum + w, kMaxWeight)));
#endif
    imageStore(uOutput, px, vec4(blendFrames(history.rgb, current.rgb, alpha), current.a));
}
#endif

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(uOutput);
    if (any(greaterThanEqual(px, size))) return;
    vec4 current = imageLoad(uCurrent, px);
#ifdef TAA_SUPPORT
    float support = imageLoad(uSupport, px).r;
    float w = kSupportFloor + exp(-(support * support) / (kSupportSigma * kSupportSigma));
#endif
#ifdef TAA_MOTION
    vec4 motion = imageLoad(uMotion, px);
    uint signature = uint(motion.w);
    // A history that starts here holds this frame alone.
    imageStore(uSignatureOutput, px, uvec4(signature | (1u << kHistoryFramesShift)));
#endif
    if (pc.params.z < 0.0) {
        imageStore(uOutput, px, current);
#ifdef TAA_SUPPORT
        imageStore(uWeightOutput, px, vec4(w));
#endif
        return;
    }
#ifndef TAA_MOTION
    if (kStillView) {
        // The camera did not move (taa.cpp requires it): every pixel's history is its own
        // texel, which the reprojection below finds up to rounding.
        stillViewBlend(px, current, imageLoad(uHistory, px)
#ifdef TAA_SUPPORT
                       , w
#endif
        );
        return;
    }
#endif
    // Reproject: world point along this pixel's ray at the first-hit distance.
    vec3 dir = pixelRay(px, size);
    float depth = current.a;
    bool sky = !(depth < 1e30);
    vec3 d = sky ? dir : pc.currentOrigin.xyz + depth * dir - pc.previousOrigin.xyz;
#ifdef TAA_MOTION
    // Where the hit was one frame ago: p + motion (0 for static geometry and the sky); at a
    // moving edge, where the followed surface's point along this ray was.
    bool moved = !sky && dot(motion.xyz, motion.xyz) > 0.0;
    vec3 follow = motion.xyz;
    float followDepth = depth;
    readAround(px, size);
    bool followsEdge = !sky && edgeMotion(px, size, signature >> 8u, dir, followDepth, follow);
    if (followsEdge) d = pc.currentOrigin.xyz + followDepth * dir - pc.previousOrigin.xyz;
    if (!sky) d += follow;
    moved = moved || followsEdge;
#endif
    vec3 prevUp = cross(pc.previousRight.xyz, pc.previousForward.xyz);
    float z = dot(d, pc.previousForward.xyz);
    bool valid = z > 1e-6;
    vec2 ps = vec2(dot(d, pc.previousRight.xyz), dot(d, prevUp)) / max(z, 1e-6);
    ps = (ps - pc.centres.zw) / vec2(pc.previousOrigin.w * pc.previousForward.w, pc.previousOrigin.w);
    vec2 prevPixel = vec2((ps.x + 1.0) * 0.5, (1.0 - ps.y) * 0.5) * vec2(size);
    valid = valid && all(greaterThanEqual(prevPixel, vec2(0.0))) && all(lessThan(prevPixel, vec2(size)));
#ifdef TAA_MOTION
    bool sameSurface = false;
    uint frames = 0u;
    bool edgeMix = false;
    vec4 history = valid ? historyOfSurface(prevPixel, size, signature, moved, followsEdge,
                                            sameSurface, frames, edgeMix)
                         : current;
    // A history that held a moving edge's mix of surfaces (both sides' colours under one
    // signature), now off the edge, is clipped.
    moved = moved || edgeMix;
    valid = valid && sameSurface;
    if (!valid) history = current;
    // Something changed around the pixel since last frame (a surface or shadow edge moved past
    // it): its history may hold a mix of what was there, such as a sample straddling a moving
    // object's edge under the floor's signature; it is clipped as a moved pixel's, not pooled.
    if (valid && !moved) moved = changedAround(px, prevPixel, size);
#else
    vec4 history = valid ? historyBilinear(prevPixel, size) : current;
#endif
    // Disocclusion: the surface seen last frame must be at the distance we expect. A tolerance
    // of 1e29 or more means nothing moved (taa.cpp): then neither distances nor sky against
    // geometry are tested, as the rays moving in their discs change which one a pixel's
    // nearest sample saw, not what the pixel shows.
    bool testDepth = !kStillView && pc.params.w < 1e29;
    float tolerance = pc.params.w;
#ifdef TAA_MOTION
    // The distance expected is the moved point's (length(d) above).
    if (moved) {
        // An edge pixel's history holds either side's distance: its signatures decide.
        testDepth = !followsEdge;
        tolerance = min(tolerance, kMovingTolerance);
    }
#endif
    if (valid && !sky && testDepth) {
        float expected = length(d);
        valid = abs(history.a - expected) <= tolerance * expected;
    } else if (valid && sky && testDepth) {
        valid = !(history.a < 1e30);
    }
    vec3 result = current.rgb;
    float alpha = pc.params.x, gamma = pc.params.y;
#ifdef TAA_SUPPORT
    // Camera and gaze still (no clipping): the weighted running mean. Otherwise the history
    // stands for 1 / alpha frames of this frame's weight when the view comes to rest.
    bool weighted = valid && gamma >= 1e29;
#ifdef TAA_MOTION
    weighted = weighted && !moved;
#endif
    float weightSum = weighted ? imageLoad(uWeightHistory, px).r : 0.0;
#ifdef TAA_MOTION
    // A moved pixel pools its frames too, with the weight history of where its history came
    // from, over at most the frames' weight the moving blend allows (1 / currentWeight - 1 at
    // full weight); the clipping still bounds what a stale frame can hold.
    bool pooledMoving = valid && moved;
    if (pooledMoving) {
        ivec2 from = clamp(ivec2(floor(prevPixel)), ivec2(0), size - 1);
        weightSum = min(imageLoad(uWeightHistory, from).r, 1.0 / kMovingWeight - 1.0);
    }
#endif
#endif
    if (!kStillView && pc.previousRight.w != 0.0) {
        // A foveated image whose gaze or camera moved: away from the gaze its sparse sampling
        // changes under the image from frame to frame (the set slides with a pursuing gaze,
        // the scene moves over it with the camera), so the history counts more there while
        // the fovea stays responsive: by d / r with the camera still (smooth pursuit over a
        // still scene), by the gentler sqrt(d / r) with it moving (radius < 0), whose history
        // is only reprojected.
        vec2 gaze = unpackHalf2x16(floatBitsToUint(pc.currentRight.w));
        float f = max(1.0, length(vec2(px) + 0.5 - gaze) / abs(pc.previousRight.w));
        if (pc.previousRight.w < 0.0) f = sqrt(f);
        alpha /= f;
        gamma *= f;
    }
#ifdef TAA_MOTION
    if (moved) {
        alpha = max(alpha, kMovingWeight);
        gamma = min(gamma, kMovingGamma);
    }
    alpha = max(alpha, 1.0 / float(frames + 1u));
#endif
#ifdef TAA_SUPPORT
#ifdef TAA_MOTION
    weighted = weighted || pooledMoving;
#endif
    if (weighted) alpha = w / max(weightSum + w, 1e-6);
#endif
    if (valid) {
        // gamma >= 1e29: no clipping (a flat neighbourhood has sigma 0, and 0 * 1e30 would
        // clip the history to the current mean).
        vec3 clipped = history.rgb;
        if (!kStillView && gamma < 1e29) {
            vec3 m1, sigma;
            neighbourhood(px, size, m1, sigma);
            clipped = fromYCoCg(clipToBox(toYCoCg(history.rgb), m1, gamma * sigma));
        }
        result = blendFrames(clipped, current.rgb, alpha);
    }
    imageStore(uOutput, px, vec4(result, current.a));
#ifdef TAA_MOTION
    if (valid) {
        uint gathered = min(frames + 1u, uint(kMaxHistoryFrames));
        imageStore(uSignatureOutput, px,
                   uvec4(signature | (gathered << kHistoryFramesShift) |
                         (followsEdge ? 1u << kEdgeMixBit : 0u)));
    }
#endif
#ifdef TAA_SUPPORT
    imageStore(uWeightOutput, px,
               vec4(weighted ? min(weightSum + w, kMaxWeight) : w / max(valid ? alpha : 1.0, 1e-6)));
#endif
}
