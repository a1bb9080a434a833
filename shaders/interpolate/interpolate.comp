#version 460
// Pass `interpolate` (thesis, 4.3): every screen pixel from the k nearest sampled points.
// Nearest neighbour takes the nearest point's colour; the Modified Shepard method weighs the k
// neighbours by w_i = ((R - h_i) / (R h_i))^q with R the distance to the farthest of them
// (thesis eqs. 5-6, q = 1; Renka 1988 uses q = 2); RBF (eqs. 7-10) sums the k neighbours with
// the per-pixel weights prepared once, or evaluates rbf_solve's per-point weights.
#extension GL_GOOGLE_include_directive : require
#include "foveated_shared.h"
#include "rbf.glsl"

layout(local_size_x = kInterpGroupX, local_size_y = kInterpGroupY) in;
layout(set = 0, binding = kBindingInterpPoints) uniform samplerBuffer uPoints;
layout(std430, set = 0, binding = kBindingInterpSamples) readonly buffer Samples { vec4 samples[]; };
// interpolate_sites.comp's: each point on the screen this frame (x, y) and its spacing p.
layout(set = 0, binding = kBindingInterpSites) uniform samplerBuffer uSites;
layout(set = 0, binding = kBindingNearest) uniform usamplerBuffer uNearest;
layout(set = 0, binding = kBindingNeighbours) uniform usamplerBuffer uNeighbours;
layout(set = 0, binding = kBindingKnnTable) uniform usamplerBuffer uKnnSlots;
layout(set = 0, binding = kBindingKnnTiles) uniform usamplerBuffer uKnnTiles;
layout(set = 0, binding = kBindingKnnCandidates) uniform usamplerBuffer uKnnCandidates;
layout(set = 0, binding = kBindingKnnPixelRows) uniform usamplerBuffer uKnnPixelRows;
layout(set = 0, binding = kBindingRbfPixelWeights) uniform samplerBuffer uRbfPixelWeights;
layout(set = 0, binding = kBindingInterpOutput, rgba32f) uniform writeonly image2D uOutput;
layout(set = 0, binding = kBindingInterpSupport, r32f) uniform writeonly image2D uSupport;
layout(std430, set = 0, binding = kBindingLambdaR) readonly buffer LambdaR { float lambdaR[]; };
layout(std430, set = 0, binding = kBindingLambdaG) readonly buffer LambdaG { float lambdaG[]; };
layout(std430, set = 0, binding = kBindingLambdaB) readonly buffer LambdaB { float lambdaB[]; };
layout(push_constant) uniform Push { InterpolatePush pc; };
// One pipeline per method and neighbour index: llvmpipe runs both sides of a branch under a
// lane mask, so a method chosen at run time paid for every other method's code (nearest
// neighbour took 50 ms, a constant write 46 ms at 1280x1440); specialised, dead code goes.
layout(constant_id = 0) const uint kMethod = kMethodNearest;
layout(constant_id = 1) const bool kUseTable = false;
// A scene that moves: each pixel takes the motion of the sample it is nearest to, the one whose
// first-hit distance it keeps in a (motion.glsl's layout), so that TAA reprojects the point
// that distance names with that point's own motion and tests its surface's signature.
layout(constant_id = 2) const bool kMotion = false;
// The k-NN table's layout (engine/foveation/gpu_point_set.hpp): flat, per canvas pixel its k
// nearest as indices (kBindingKnnTable, RGBA32UI), or compact (tiles, candidates, slots).
layout(constant_id = 3) const bool kFlatTable = false;
// Nearest neighbour where every screen pixel's nearest point is one that point_sample traced:
// the set's covering radius is within the sampling margin and the gaze on screen
// (InterpolatePass). The search for a nearer sampled point then compiles away.
layout(constant_id = 4) const bool kExactNearest = false;
layout(std430, set = 0, binding = kBindingInterpSampleMotion) readonly buffer SampleMotion {
    vec4 sampleMotion[];
};
layout(set = 0, binding = kBindingInterpMotion, rgba32f) uniform writeonly image2D uMotion;

// Display-referred interpolation (pc.rbf.y = exposure e > 0): samples are blended as
// T(c) = c / (1 + e L(c)) and the blend is mapped back with T^-1(y) = y / (1 - e L(y)). A linear
// blend of HDR radiance lets a few very bright samples dominate their dark neighbours (a lamp
// bleeds into the dark pillar beside it); in T's space each sample counts about as much as it
// shows on the display. For Modified Shepard this is Karis's luminance-normalised weighting:
// sum w_i c_i / (1 + e L_i) / sum w_i / (1 + e L_i).
float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }
vec3 compress(vec3 c) { return pc.rbf.y > 0.0 ? c / (1.0 + pc.rbf.y * luminance(c)) : c; }
vec3 expand(vec3 y) {
    return pc.rbf.y > 0.0 ? y / max(1.0 - pc.rbf.y * luminance(y), 1e-3) : y;
}

// Geometry-aware weight (pc.rbf.z = tolerance t > 0, a joint-bilateral filter guided by the
// first hit): a neighbour whose first-hit distance differs from the nearest sample's by dz
// weighs exp(-(dz / (t z))^2) as much, so samples across a silhouette do not mix (no halos or
// specks on edges, thin geometry stays whole); sky against geometry weighs 0.
float edgeWeight(float nearestDepth, float depth) {
    if (pc.rbf.z <= 0.0) return 1.0;
    bool skyA = !(nearestDepth < 1e30), skyB = !(depth < 1e30);
    if (skyA || skyB) return skyA == skyB ? 1.0 : 0.0;
    float rel = (depth - nearestDepth) / (pc.rbf.z * max(min(depth, nearestDepth), 1e-6));
    return exp(-rel * rel);
}

// Colour-guided weight (pc.rbf.w = sigma s > 0, a cross-bilateral filter guided by the nearest
// sample): a neighbour whose display-referred luminance differs from the nearest sample's by
// dL weighs exp(-(dL / s)^2) as much. At a bright/dark boundary a pixel keeps the side its
// nearest sample lies on, as nearest neighbour does, while flat areas still blend k samples.
float rangeWeight(vec3 nearest, vec3 other) {
    if (pc.rbf.w <= 0.0) return 1.0;
    float d = (luminance(other) - luminance(nearest)) / pc.rbf.w;
    return exp(-d * d);
}

// The pixel's colour, and its distance to the sample it took most from (at `site`, spacing
// `p`; p < 0: none) in units of p, or of one pixel where the points lie closer
// (kBindingInterpSupport; 1e9 where no sample was near). Near the gaze, where points are denser than pixels, every frame
// then sees the pixel about as directly and TAA keeps its plain running mean there (FLIP 0-5
// deg on builtin:market 0.0127 with p alone, 0.0111 with the pixel floor).
void store(ivec2 px, vec4 colour, vec2 site, float p) {
    imageStore(uOutput, px, colour);
    float s = p >= 0.0 ? length(site - (vec2(px) + 0.5)) / max(p, 1.0) : 1e9;
    imageStore(uSupport, px, vec4(s));
}

const uint kNoSample = 0xffffffffu;
// The motion of the pixel's nearest sample (none: no motion, the sky's signature).
void storeMotion(ivec2 px, uint nearest) {
    if (!kMotion) return;
    imageStore(uMotion, px, nearest == kNoSample ? vec4(0.0) : sampleMotion[nearest]);
}

// Canvas pixel c's row of the k-NN table (pixel_knn_table.hpp): its tile's first candidate,
// and the first texel of the row's slots (flat: of the pixel's own).
uvec2 knnRow(ivec2 c) {
    int canvasWidth = int(pc.canvas.x);
    if (kFlatTable) return uvec2(0u, uint(c.y * canvasWidth + c.x) * pc.table.x);
    int tilesX = (canvasWidth + int(kKnnTile) - 1) / int(kKnnTile);
    uvec2 tile = texelFetch(uKnnTiles, (c.y / int(kKnnTile)) * tilesX + c.x / int(kKnnTile)).xy;
    uint row = tile.y + texelFetch(uKnnPixelRows, c.y * canvasWidth + c.x).r;
    return uvec2(tile.x, row * pc.table.x);
}

// The j-th of a k-NN table row's points, nearest to its tile's centre first (flat: to the
// pixel's centre); `slots` holds the row's slots j & ~3 .. j | 3, fetched when j % 4 == 0.
uint knnEntry(uvec2 row, uint j, inout uvec4 slots) {
    if ((j & 3u) == 0u) slots = texelFetch(uKnnSlots, int(row.y + (j >> 2u)));
    return kFlatTable ? slots[j & 3u] : texelFetch(uKnnCandidates, int(row.x + slots[j & 3u])).r;
}

// The table's own order (pixel_knn_table.hpp): squared distance from the canvas pixel centre
// in float, as the table's build computes it (so `precise`: no fused multiply-add), then index.
float tableDistance2(vec2 point, ivec2 canvasPixel) {
    precise float dx = point.x - (float(canvasPixel.x) + 0.5);
    precise float dy = point.y - (float(canvasPixel.y) + 0.5);
    precise float d2 = dx * dx + dy * dy;
    return d2;
}

// Whether table candidate a (squared distance this frame dd, point index i) goes before b: by
// distance this frame, equal distances in the table's order, which the flat table's rows were
// sorted in (rare: only then are the points fetched again).
bool before(float ddA, uint iA, float ddB, uint iB, ivec2 canvasPixel) {
    if (ddA != ddB) return ddA < ddB;
    float tdA = tableDistance2(texelFetch(uPoints, int(iA)).xy, canvasPixel);
    float tdB = tableDistance2(texelFetch(uPoints, int(iB)).xy, canvasPixel);
    return tdA < tdB || (tdA == tdB && iA < iB);
}

// RBF (thesis, eq. 7): s(x) = sum lambda_i phi(|x - x_i|) over the neighbourhood of the
// pixel's nearest point q, with the weights rbf_solve computed for q.
vec3 evaluateRbf(uint q, vec2 pos) {
    uint k = min(pc.params.z, kMaxK);
    uint stored = pc.canvas.z;
    float c = max(pc.rbf.x * texelFetch(uPoints, int(q)).z, 1e-3);
    vec3 sum = vec3(0.0);
    for (uint j = 0u; j < k; ++j) {
        uint i = j == 0u ? q : texelFetch(uNeighbours, int(q * stored + j - 1u)).r;
        vec2 p = texelFetch(uPoints, int(i)).xy;
        float phi = rbfKernel(length(p + pc.offset.xy - pos), c, pc.canvas.w);
        uint at = q * k + j;
        sum += phi * vec3(lambdaR[at], lambdaG[at], lambdaB[at]);
    }
    return sum;
}

// Nearest neighbour (thesis, 4.3), whose sites never move (PointSetMethod): the canvas pixel's
// nearest point q is exact. Where q lies beyond the sampled margin, the nearest sampled one of q
// and its neighbour list stands in (strictly nearer wins, so ties keep the list's order: the
// general search's answer at k = 1). A search of its own, with no arrays: llvmpipe runs the
// code of a branch even when no lane takes it, so the general k-nearest search cost every
// pixel; that search of q's list, too, where kExactNearest says it is never needed.
void nearestNeighbour(ivec2 px, vec2 pos, uint q, vec2 offset, ivec2 size, float margin) {
    vec4 qpoint = texelFetch(uPoints, int(q));
    uint best = q;
    vec4 bestPoint = qpoint;
    if (!kExactNearest && !isSampled(qpoint.xy, offset, vec2(size), margin)) {
        best = kNoSample;
        float bestD2 = 1.0 / 0.0;
        for (uint j = 1u; j <= pc.canvas.z; ++j) {
            uint i = texelFetch(uNeighbours, int(q * pc.canvas.z + j - 1u)).r;
            vec4 pt = texelFetch(uPoints, int(i));
            if (!isSampled(pt.xy, offset, vec2(size), margin)) continue;
            vec2 d = pt.xy + offset - pos;
            float dd = dot(d, d);
            if (best == kNoSample || dd < bestD2) {
                best = i;
                bestD2 = dd;
                bestPoint = pt;
            }
        }
    }
    storeMotion(px, best);
    if (best == kNoSample) {
        store(px, vec4(vec3(0.0), 1.0 / 0.0), vec2(0.0), -1.0);
    } else {
        store(px, samples[best], bestPoint.xy + offset, bestPoint.z);
    }
}

// The j-th point of a table row, and where it sits this frame (x, y, spacing p): false where
// point_sample did not trace it (beyond the margin).
bool rowSite(uvec2 row, uint j, inout uvec4 slots, vec2 size, float margin, out uint i,
             out vec4 site) {
    i = knnEntry(row, j, slots);
    site = texelFetch(uSites, int(i));
    return !(any(lessThan(site.xy, vec2(-margin))) || any(greaterThanEqual(site.xy, size + margin)));
}

// Modified Shepard through the k-NN table (thesis eqs. 5-6). A row is the canvas pixel's k
// nearest points as a set, and every one of them point_sample traced is blended, so nothing is
// sorted: one walk over the row finds the nearest (in `before`'s order) and the farthest, a
// second sums the weights. Sorting cost llvmpipe half this pass: with the sites moving, rows
// arrive out of order and each insertion shifted private arrays lane by lane.
void shepardThroughTable(ivec2 px, vec2 pos, ivec2 c, vec2 size, float margin) {
    uvec2 row = knnRow(c);
    uvec4 slots = uvec4(0u);
    uint n = 0u, nearest = kNoSample, i;
    float nearestD2 = 0.0, farthestD2 = 0.0;
    vec4 nearestSite = vec4(0.0), site;
    for (uint j = 0u; j < pc.table.y; ++j) {
        if (!rowSite(row, j, slots, size, margin, i, site)) continue;
        vec2 d = site.xy - pos;
        float dd = dot(d, d);
        if (n == 0u || before(dd, i, nearestD2, nearest, c)) {
            nearest = i;
            nearestD2 = dd;
            nearestSite = site;
        }
        farthestD2 = max(farthestD2, dd);
        ++n;
    }
    storeMotion(px, nearest);
    if (n == 0u) {
        store(px, vec4(vec3(0.0), 1.0 / 0.0), vec2(0.0), -1.0);
        return;
    }
    vec4 near = samples[nearest];
    vec3 colour = near.rgb;
    if (n > 1u) {
        vec3 nearestT = compress(colour);
        vec3 sum = nearestT; // a site at the pixel centre: its sample alone
        float wsum = 1.0;
        if (sqrt(nearestD2) >= 1e-6) {
            float r = sqrt(farthestD2);
            sum = vec3(0.0);
            wsum = 0.0;
            slots = uvec4(0u);
            for (uint j = 0u; j < pc.table.y; ++j) {
                if (!rowSite(row, j, slots, size, margin, i, site)) continue;
                vec2 d = site.xy - pos;
                float h = sqrt(dot(d, d));
                vec4 sample_ = samples[i];
                vec3 t = compress(sample_.rgb);
                float w = pow(max(r - h, 0.0) / (r * h), pc.offset.w)
                          * edgeWeight(near.w, sample_.w) * rangeWeight(nearestT, t);
                sum += w * t;
                wsum += w;
            }
        }
        if (wsum > 0.0) colour = expand(sum / wsum);
    }
    store(px, vec4(colour, near.w), nearestSite.xy, nearestSite.z);
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(pc.params.xy);
    if (any(greaterThanEqual(px, size))) return;
    vec2 pos = vec2(px) + 0.5;
    vec2 offset = pc.offset.xy;
    float margin = pc.offset.z;
    ivec2 c = clamp(ivec2(floor(pos - offset)), ivec2(0), ivec2(pc.canvas.xy) - 1);
    // The canvas pixel's nearest point. Modified Shepard through the table never uses it, and
    // its point set may hold a one-texel stand-in there (GpuPointSet::Index::OnDemand): no read.
    const bool readsIndex = !(kUseTable && kMethod == kMethodShepard);
    uint q = readsIndex ? texelFetch(uNearest, c.y * int(pc.canvas.x) + c.x).r : 0u;
    if (kMethod == kMethodNearest) {
        nearestNeighbour(px, pos, q, offset, size, margin);
        return;
    }
    if (kUseTable && kMethod == kMethodShepard) {
        shepardThroughTable(px, pos, c, vec2(size), margin);
        return;
    }
    uint k = min(pc.params.z, kMaxK);
    if (kMethod == kMethodRbf && kUseTable) {
        // s(x) = sum_j w_j f_j over the canvas pixel's k table neighbours (the thesis's
        // per-pixel solve of eq. 8, done once: rbf_pixel_weights.hpp). Neighbours beyond the
        // sampled margin take the colour of the nearest sampled one.
        int pixel = c.y * int(pc.canvas.x) + c.x;
        int wrow = pixel * int(pc.table.z);
        // The row nearest first, as the weights were stored.
        uvec2 row = knnRow(c);
        uvec4 slots = uvec4(0u);
        uint ordered[kMaxK];
        float orderedD2[kMaxK];
        for (uint j = 0u; j < k; ++j) {
            uint i = knnEntry(row, j, slots);
            float td = tableDistance2(texelFetch(uPoints, int(i)).xy, c);
            uint m = j;
            while (m > 0u && (td < orderedD2[m - 1u] || (td == orderedD2[m - 1u] && i < ordered[m - 1u]))) {
                ordered[m] = ordered[m - 1u];
                orderedD2[m] = orderedD2[m - 1u];
                --m;
            }
            ordered[m] = i;
            orderedD2[m] = td;
        }
        uint first = k;
        for (uint j = 0u; j < k; ++j) {
            uint i = ordered[j];
            if (isSampled(texelFetch(uPoints, int(i)).xy, offset, vec2(size), margin)) {
                first = j;
                break;
            }
        }
        if (first < k) {
            uint nearestIndex = ordered[first];
            vec4 nearest = samples[nearestIndex];
            vec3 sum = vec3(0.0);
            for (uint j = 0u; j < k; ++j) {
                uint i = ordered[j];
                float w = texelFetch(uRbfPixelWeights, wrow + int(j >> 2u))[j & 3u];
                vec2 at = texelFetch(uPoints, int(i)).xy;
                bool sampled = j == first || (j > first && isSampled(at, offset, vec2(size), margin));
                sum += w * compress(sampled ? samples[i].rgb : nearest.rgb);
            }
            vec4 nearestPoint = texelFetch(uPoints, int(nearestIndex));
            storeMotion(px, nearestIndex);
            store(px, vec4(max(expand(max(sum, vec3(0.0))), vec3(0.0)), nearest.w),
                  nearestPoint.xy + offset, nearestPoint.z);
            return;
        }
        k = 1u; // no neighbour sampled: the nearest sampled point through the lists below
    }
    if (kMethod == kMethodRbf && !kUseTable) {
        vec4 qpoint = texelFetch(uPoints, int(q));
        if (isSampled(qpoint.xy, offset, vec2(size), margin)) {
            vec4 qs = samples[q];
            storeMotion(px, q);
            store(px, vec4(max(evaluateRbf(q, pos), vec3(0.0)), qs.w), qpoint.xy + offset, qpoint.z);
            return;
        }
        k = 1u; // the nearest point was not sampled: nearest sampled neighbour instead
    }
    const uint siteFrame = pc.table.w; // sites moved this frame (site_jitter.glsl); 0: fixed

    // Candidates, kept sorted by distance: the nearest point and its stored neighbours (Modified
    // Shepard through the table blends its row unsorted above). Points that point_sample skipped
    // (beyond the margin) are left out.
    uint idx[kMaxK + 1];
    float d2[kMaxK + 1];
    vec2 site0 = vec2(0.0); // where the nearest one sits this frame, and its spacing
    float spacing0 = -1.0;
    uint n = 0u;
    for (uint j = 0u; j <= pc.canvas.z; ++j) {
        uint i = j == 0u ? q : texelFetch(uNeighbours, int(q * pc.canvas.z + j - 1u)).r;
        vec4 site = texelFetch(uSites, int(i));
        vec2 s = site.xy;
        if (any(lessThan(s, vec2(-margin))) || any(greaterThanEqual(s, vec2(size) + margin))) continue;
        vec2 d = s - pos;
        float dd = dot(d, d);
        if (n == k && !(dd < d2[n - 1u])) continue;
        uint m = min(n, k - 1u);
        while (m > 0u && dd < d2[m - 1u]) {
            idx[m] = idx[m - 1u];
            d2[m] = d2[m - 1u];
            --m;
        }
        idx[m] = i;
        d2[m] = dd;
        if (m == 0u) {
            site0 = s;
            spacing0 = site.z;
        }
        n = min(n + 1u, k);
        // The index's nearest point is exact: nothing closer follows (with the sites moved, the
        // rest of the candidates may still hold a closer one).
        if (siteFrame == 0u && n == k && j == 0u) break;
    }
    vec3 colour = vec3(0.0);
    float depth = 1.0 / 0.0; // first-hit distance of the nearest sample, for TAA
    if (n > 0u) {
        colour = samples[idx[0]].rgb;
        depth = samples[idx[0]].w;
        if (kMethod == kMethodShepard && n > 1u) {
            float r = sqrt(d2[n - 1u]);
            vec3 sum = vec3(0.0);
            float wsum = 0.0;
            vec3 nearestT = compress(colour);
            for (uint j = 0u; j < n; ++j) {
                float h = sqrt(d2[j]);
                if (h < 1e-6) { sum = compress(samples[idx[j]].rgb); wsum = 1.0; break; }
                vec3 t = compress(samples[idx[j]].rgb);
                float w = pow(max(r - h, 0.0) / (r * h), pc.offset.w)
                          * edgeWeight(depth, samples[idx[j]].w) * rangeWeight(nearestT, t);
                sum += w * t;
                wsum += w;
            }
            if (wsum > 0.0) colour = expand(sum / wsum);
        }
    }
    if (kMethod >= kViewPoints && kMethod <= kViewSpacing && n > 0u) {
        vec4 point = texelFetch(uPoints, int(idx[0]));
        if (kMethod == kViewPoints) {
            // The point's own sample where a point lies in this pixel, dark grey elsewhere.
            colour = d2[0] <= 0.5 ? samples[idx[0]].rgb : vec3(0.02);
        } else if (kMethod == kViewCells) {
            uint h = idx[0] * 2654435761u;
            colour = vec3(float(h & 255u), float((h >> 8) & 255u), float((h >> 16) & 255u)) / 255.0;
        } else {
            // Spacing p from sqrt(1/pi) (blue) to 16 px and beyond (red), log scale.
            float t = clamp(log2(point.z / 0.5642) / 5.0, 0.0, 1.0);
            colour = mix(mix(vec3(0.05, 0.1, 1.0), vec3(0.1, 1.0, 0.2), min(t * 2.0, 1.0)),
                         vec3(1.0, 0.1, 0.05), max(t * 2.0 - 1.0, 0.0));
        }
        colour *= 2.0; // before the tone mapper
    }
    storeMotion(px, n > 0u ? idx[0] : kNoSample);
    store(px, vec4(colour, depth), site0, n > 0u ? spacing0 : -1.0);
}
