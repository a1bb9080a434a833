// Compute-shader ray tracing over the flattened BVH (engine/scene/bvh.hpp) and the shading of
// engine/trace/cpu_tracer.cpp, which is the reference these functions are tested against.
// Include after declaring nothing else at the scene bindings (trace_shared.h, set 0).
#ifndef TRACE_GLSL
#define TRACE_GLSL
#include "trace_shared.h"

layout(set = 0, binding = kBindingNodes) uniform samplerBuffer uNodes;
layout(set = 0, binding = kBindingTriangles) uniform samplerBuffer uTriangles;
layout(set = 0, binding = kBindingShading) uniform samplerBuffer uShading;
layout(set = 0, binding = kBindingMaterials) uniform samplerBuffer uMaterials;
layout(set = 0, binding = kBindingLights) uniform samplerBuffer uLights;
layout(set = 0, binding = kBindingTexels) uniform usamplerBuffer uTexels;
layout(set = 0, binding = kBindingTextureInfo) uniform usamplerBuffer uTextureInfo;
layout(set = 0, binding = kBindingEnvironment) uniform samplerBuffer uEnvironment;
// A read-only storage buffer, not a uniform block: Mesa 22.3's lavapipe inlines the values of
// the first uniform block wherever they decide a branch or a loop, and redoes that on every
// dispatch, keeping ~0.35 MB per traced pass per frame until the pipeline is destroyed (the
// soak: +0.69 MB a frame, flat once these reads left the uniform block). The block
// is four vec4s read a few times per ray; as a storage buffer it costs nothing measurable.
layout(std430, set = 0, binding = kBindingSceneUniforms) readonly buffer SceneBlock {
    SceneUniforms uScene;
};

// Specialisation constant 0 of every shader that includes this file: whether a material is
// alpha-masked (trace::GpuScene::alphaMasked). Off, the alpha test compiles away; tested at run
// time inside the traversal loops instead, it made llvmpipe trace 3.5x slower even when no
// material was masked (reference, market, 2 spp: 2.08 s -> 7.4 s).
layout(constant_id = 0) const bool kAlphaMask = false;
// Specialisation constant kSpecDynamic: the scene moves (trace::GpuScene::dynamic()). Rays then
// test the static tree and the two-level part after it: the top level over the instances, at
// each instance leaf the ray in object space through that instance's bottom-level tree. Off,
// all of it compiles away and the tracer is the single-level one.
layout(constant_id = kSpecDynamic) const bool kDynamic = false;

// With kDynamic, traceRadiance's first hit: xyz = its world position one frame ago minus its
// position now (0 for static geometry and misses); w = uintBitsToFloat(signature), the surface
// id (kSurfaceSky, kSurfaceStatic, kSurfaceInstance0 + instance) in bits 0-23 and which of
// lights 0-7 reach the hit (its shadow state) from kShadowMaskShift on. Temporal passes reject
// history whose signature differs.
vec4 gMotion = vec4(0.0);

// The BVH rays traverse: one geometric LOD level's (SceneUniforms::lodRoots). A pass picks the
// level once per ray, before tracing it; the shadow rays of its hits then use the same level.
int gLodRoot = 0;
void selectLod(uint level) {
    gLodRoot = int(uScene.lodRoots[min(level, uint(kLodLevels - 1))]);
}

const float kPi = 3.14159265358979;
const float kInf = 1.0 / 0.0;

struct Hit {
    float t;
    uint tri;
    float u;
    float v;
    uint inst; // instance record (kDynamic); 0xffffffff: the static tree
};

bool slabTest(int node, vec3 origin, vec3 invDir, float tMin, float tMax, out float tEnter) {
    vec3 lo = texelFetch(uNodes, node * 2).xyz;
    vec3 hi = texelFetch(uNodes, node * 2 + 1).xyz;
    vec3 t0 = (lo - origin) * invDir;
    vec3 t1 = (hi - origin) * invDir;
    vec3 a = min(t0, t1), b = max(t0, t1);
    float enter = max(max(a.x, a.y), max(a.z, tMin));
    float exit = min(min(b.x, b.y), min(b.z, tMax));
    tEnter = enter;
    return enter <= exit;
}

// (leftFirst, count) of a node: count > 0 makes it a leaf (see gt::scene::BvhNode).
uvec2 nodeLinks(int node) {
    return uvec2(floatBitsToUint(texelFetch(uNodes, node * 2).w),
                 floatBitsToUint(texelFetch(uNodes, node * 2 + 1).w));
}

// Möller–Trumbore, as gt::scene::intersectTriangle.
bool triangleTest(uint tri, vec3 origin, vec3 dir, float tMin, float tMax, out float t,
                  out float u, out float v) {
    int base = int(tri) * 3;
    vec3 v0 = texelFetch(uTriangles, base).xyz;
    vec3 e1 = texelFetch(uTriangles, base + 1).xyz;
    vec3 e2 = texelFetch(uTriangles, base + 2).xyz;
    vec3 p = cross(dir, e2);
    float det = dot(e1, p);
    t = 0.0; u = 0.0; v = 0.0;
    if (abs(det) < 1e-12) return false;
    float inv = 1.0 / det;
    vec3 s = origin - v0;
    u = dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) return false;
    vec3 q = cross(s, e1);
    v = dot(dir, q) * inv;
    if (v < 0.0 || u + v > 1.0) return false;
    t = dot(e2, q) * inv;
    return t > tMin && t < tMax;
}

vec4 materialBaseColor(uint material, vec2 uv);

// A triangle's four shading texels (packed by trace::packScene): three normals and UVs, the
// material in s3.w.
void shadingTexels(uint tri, out vec4 s0, out vec4 s1, out vec4 s2, out vec4 s3) {
    int sb = int(tri * kShadingTexels);
    s0 = texelFetch(uShading, sb);
    s1 = texelFetch(uShading, sb + 1);
    s2 = texelFetch(uShading, sb + 2);
    s3 = texelFetch(uShading, sb + 3);
}

// A hit's UV from its triangle's shading texels.
vec2 shadingUv(vec4 s0, vec4 s1, vec4 s2, vec4 s3, float u, float v) {
    return (1.0 - u - v) * vec2(s0.w, s1.w) + u * vec2(s2.w, s3.x) + v * s3.yz;
}

// alphaMode MASK: a hit on a masked material where the base colour's alpha falls below the
// cutoff is no hit (glTF 2.0, 3.9.4).
bool alphaRejects(uint tri, float u, float v) {
    if (!kAlphaMask) return false;
    vec4 s0, s1, s2, s3;
    shadingTexels(tri, s0, s1, s2, s3);
    uint material = floatBitsToUint(s3.w);
    float cutoff = texelFetch(uMaterials, int(material * kMaterialTexels) + 2).z;
    if (cutoff < 0.0) return false;
    return materialBaseColor(material, shadingUv(s0, s1, s2, s3, u, v)).a < cutoff;
}

// ---- The two-level part (kDynamic) ------------------------------------------------------
// Texel k of instance record `record` (trace_shared.h: kInstanceTexels per record).
vec4 instanceTexel(uint record, int k) {
    return texelFetch(uNodes, int(uScene.dynamic.y + record * kInstanceTexels) + k);
}

// A 3x4 matrix given by its rows, applied to a point and to a direction.
vec3 rowsPoint(vec4 r0, vec4 r1, vec4 r2, vec3 p) {
    vec4 h = vec4(p, 1.0);
    return vec3(dot(r0, h), dot(r1, h), dot(r2, h));
}
vec3 rowsDirection(vec4 r0, vec4 r1, vec4 r2, vec3 d) {
    return vec3(dot(r0.xyz, d), dot(r1.xyz, d), dot(r2.xyz, d));
}

// An object-space normal of instance record `record` in world space: by the inverse transpose of
// the object-to-world matrix, which is the transpose of the world-to-object rows.
vec3 instanceNormalToWorld(uint record, vec3 n) {
    return normalize(n.x * instanceTexel(record, 0).xyz + n.y * instanceTexel(record, 1).xyz +
                     n.z * instanceTexel(record, 2).xyz);
}

// Closest hit in one bottom-level tree of the ray (origin, dir) in its object space. dir is the
// world direction transformed and not normalised, so t is the world ray's and compares with
// `best` across trees. Ties on t go to the lower record, then the lower triangle.
void closestInBottomLevel(uint record, int root, vec3 origin, vec3 dir, float tMin,
                          inout Hit best) {
    vec3 invDir = 1.0 / dir;
    float tEnter;
    if (!slabTest(root, origin, invDir, tMin, best.t, tEnter)) return;
    uint stack[kStackSize];
    float stackT[kStackSize];
    int sp = 0;
    int node = root;
    // Children are tested at their parent; the far one waits on the stack with its entry
    // distance and is skipped if a closer hit has been found by the time it is popped.
    while (true) {
        uvec2 links = nodeLinks(node);
        uint leftFirst = links.x, count = links.y;
        bool descend = false;
        if (count > 0u) {
            for (uint i = leftFirst; i < leftFirst + count; ++i) {
                float t, u, v;
                if (triangleTest(i, origin, dir, tMin, kInf, t, u, v) && t <= best.t &&
                    (t < best.t || record < best.inst || (record == best.inst && i < best.tri)) &&
                    !alphaRejects(i, u, v)) {
                    best = Hit(t, i, u, v, record);
                }
            }
        } else {
            float tl, tr;
            bool hl = slabTest(int(leftFirst), origin, invDir, tMin, best.t, tl);
            bool hr = slabTest(int(leftFirst) + 1, origin, invDir, tMin, best.t, tr);
            if (hl && hr) {
                bool leftNear = tl <= tr;
                stack[sp] = leftNear ? leftFirst + 1u : leftFirst;
                stackT[sp++] = leftNear ? tr : tl;
                node = int(leftNear ? leftFirst : leftFirst + 1u);
                descend = true;
            } else if (hl || hr) {
                node = int(leftFirst) + (hl ? 0 : 1);
                descend = true;
            }
        }
        if (descend) continue;
        while (sp > 0 && stackT[sp - 1] > best.t) --sp;
        if (sp == 0) break;
        node = int(stack[--sp]);
    }
}

// The top level over the instances' world bounds: at a leaf, each of its instance records'
// bottom level with the ray moved into that instance's object space.
void closestInstance(vec3 origin, vec3 dir, float tMin, inout Hit best) {
    if (uScene.dynamic.z == 0u) return;
    int root = int(uScene.dynamic.x);
    vec3 invDir = 1.0 / dir;
    float tEnter;
    if (!slabTest(root, origin, invDir, tMin, best.t, tEnter)) return;
    uint stack[kStackSize];
    float stackT[kStackSize];
    int sp = 0;
    int node = root;
    while (true) {
        uvec2 links = nodeLinks(node);
        uint leftFirst = links.x, count = links.y;
        bool descend = false;
        if (count > 0u) {
            for (uint k = leftFirst; k < leftFirst + count; ++k) {
                vec4 r0 = instanceTexel(k, 0), r1 = instanceTexel(k, 1), r2 = instanceTexel(k, 2);
                uint bottomRoot = floatBitsToUint(instanceTexel(k, 6).x);
                closestInBottomLevel(k, int(bottomRoot), rowsPoint(r0, r1, r2, origin),
                                     rowsDirection(r0, r1, r2, dir), tMin, best);
            }
        } else {
            float tl, tr;
            bool hl = slabTest(int(leftFirst), origin, invDir, tMin, best.t, tl);
            bool hr = slabTest(int(leftFirst) + 1, origin, invDir, tMin, best.t, tr);
            if (hl && hr) {
                bool leftNear = tl <= tr;
                stack[sp] = leftNear ? leftFirst + 1u : leftFirst;
                stackT[sp++] = leftNear ? tr : tl;
                node = int(leftNear ? leftFirst : leftFirst + 1u);
                descend = true;
            } else if (hl || hr) {
                node = int(leftFirst) + (hl ? 0 : 1);
                descend = true;
            }
        }
        if (descend) continue;
        while (sp > 0 && stackT[sp - 1] > best.t) --sp;
        if (sp == 0) break;
        node = int(stack[--sp]);
    }
}

// Any hit in (0, tMax) in one bottom-level tree (object-space ray, as closestInBottomLevel).
bool occludedInBottomLevel(int root, vec3 origin, vec3 dir, float tMax) {
    vec3 invDir = 1.0 / dir;
    float tEnter;
    if (!slabTest(root, origin, invDir, 0.0, tMax, tEnter)) return false;
    uint stack[kStackSize];
    int sp = 0;
    int node = root;
    while (true) {
        uvec2 links = nodeLinks(node);
        uint leftFirst = links.x, count = links.y;
        if (count > 0u) {
            for (uint i = leftFirst; i < leftFirst + count; ++i) {
                float t, u, v;
                if (triangleTest(i, origin, dir, 0.0, tMax, t, u, v) && !alphaRejects(i, u, v)) {
                    return true;
                }
            }
            if (sp == 0) return false;
            node = int(stack[--sp]);
            continue;
        }
        float tl, tr;
        bool hl = slabTest(int(leftFirst), origin, invDir, 0.0, tMax, tl);
        bool hr = slabTest(int(leftFirst) + 1, origin, invDir, 0.0, tMax, tr);
        if (hl && hr) {
            stack[sp++] = leftFirst + 1u;
            node = int(leftFirst);
        } else if (hl || hr) {
            node = int(leftFirst) + (hl ? 0 : 1);
        } else {
            if (sp == 0) return false;
            node = int(stack[--sp]);
        }
    }
    return false;
}

bool occludedByInstance(vec3 origin, vec3 dir, float tMax) {
    if (uScene.dynamic.z == 0u) return false;
    int root = int(uScene.dynamic.x);
    vec3 invDir = 1.0 / dir;
    float tEnter;
    if (!slabTest(root, origin, invDir, 0.0, tMax, tEnter)) return false;
    uint stack[kStackSize];
    int sp = 0;
    int node = root;
    while (true) {
        uvec2 links = nodeLinks(node);
        uint leftFirst = links.x, count = links.y;
        if (count > 0u) {
            for (uint k = leftFirst; k < leftFirst + count; ++k) {
                vec4 r0 = instanceTexel(k, 0), r1 = instanceTexel(k, 1), r2 = instanceTexel(k, 2);
                uint bottomRoot = floatBitsToUint(instanceTexel(k, 6).x);
                if (occludedInBottomLevel(int(bottomRoot), rowsPoint(r0, r1, r2, origin),
                                          rowsDirection(r0, r1, r2, dir), tMax)) {
                    return true;
                }
            }
            if (sp == 0) return false;
            node = int(stack[--sp]);
            continue;
        }
        float tl, tr;
        bool hl = slabTest(int(leftFirst), origin, invDir, 0.0, tMax, tl);
        bool hr = slabTest(int(leftFirst) + 1, origin, invDir, 0.0, tMax, tr);
        if (hl && hr) {
            stack[sp++] = leftFirst + 1u;
            node = int(leftFirst);
        } else if (hl || hr) {
            node = int(leftFirst) + (hl ? 0 : 1);
        } else {
            if (sp == 0) return false;
            node = int(stack[--sp]);
        }
    }
    return false;
}

// gMotion of a first hit at world position p (see gMotion): where the surface point was one
// frame ago, from the instance's previous transform and, for a deforming instance, its
// previous triangle at the same barycentrics.
vec4 hitMotion(Hit hit, vec3 p) {
    if (hit.tri == 0xffffffffu) return vec4(0.0, 0.0, 0.0, uintBitsToFloat(kSurfaceSky));
    if (hit.inst == 0xffffffffu) return vec4(0.0, 0.0, 0.0, uintBitsToFloat(kSurfaceStatic));
    uvec4 info = floatBitsToUint(instanceTexel(hit.inst, 6));
    vec3 object;
    if (info.z != kNoPrevious) {
        int base = int(info.z + (hit.tri - info.y)) * 3;
        object = texelFetch(uTriangles, base).xyz + hit.u * texelFetch(uTriangles, base + 1).xyz +
                 hit.v * texelFetch(uTriangles, base + 2).xyz;
    } else {
        object = rowsPoint(instanceTexel(hit.inst, 0), instanceTexel(hit.inst, 1),
                           instanceTexel(hit.inst, 2), p);
    }
    vec3 previous = rowsPoint(instanceTexel(hit.inst, 3), instanceTexel(hit.inst, 4),
                              instanceTexel(hit.inst, 5), object);
    return vec4(previous - p, uintBitsToFloat((kSurfaceInstance0 + info.w) & kSurfaceIdMask));
}

Hit traceClosest(vec3 origin, vec3 dir, float tMin, float tMax) {
    Hit best = Hit(tMax, 0xffffffffu, 0.0, 0.0, 0xffffffffu);
    // Environment only (a scene that moves may have all its triangles in instances).
    if (uScene.counts.w == 0u && !kDynamic) return Hit(kInf, 0xffffffffu, 0.0, 0.0, 0xffffffffu);
    // The static tree is a bottom level in world space with no instance record (0xffffffff:
    // ties on t then go to the lower triangle, and any instance's hit at the same t loses).
    if (uScene.counts.w != 0u) closestInBottomLevel(0xffffffffu, gLodRoot, origin, dir, tMin, best);
    if (kDynamic) closestInstance(origin, dir, tMin, best);
    if (best.tri == 0xffffffffu) best.t = kInf;
    return best;
}

bool traceOccluded(vec3 origin, vec3 dir, float tMax) {
    if (kDynamic && occludedByInstance(origin, dir, tMax)) return true;
    if (uScene.counts.w == 0u) return false;
    return occludedInBottomLevel(gLodRoot, origin, dir, tMax);
}

vec3 environmentTexel(int x, int y) {
    int w = int(uScene.environment.x), h = int(uScene.environment.y);
    x = ((x % w) + w) % w;
    y = clamp(y, 0, h - 1);
    return texelFetch(uEnvironment, y * w + x).rgb;
}

// As gt::scene::sampleEnvironment.
vec3 environmentRadiance(vec3 d) {
    bool pole = abs(d.x) + abs(d.z) < 1e-12; // atan(0, 0) is undefined in GLSL
    float u = pole ? 0.5 : 0.5 + atan(d.x, -d.z) / (2.0 * kPi);
    float v = acos(clamp(d.y, -1.0, 1.0)) / kPi;
    float x = u * float(uScene.environment.x) - 0.5, y = v * float(uScene.environment.y) - 0.5;
    float fx0 = floor(x), fy0 = floor(y);
    float ax = x - fx0, ay = y - fy0;
    int x0 = int(fx0), y0 = int(fy0);
    return mix(mix(environmentTexel(x0, y0), environmentTexel(x0 + 1, y0), ax),
               mix(environmentTexel(x0, y0 + 1), environmentTexel(x0 + 1, y0 + 1), ax), ay);
}

vec3 skyRadiance(vec3 d) {
    if (uScene.environment.x > 0u) return environmentRadiance(d);
    if (d.y >= 0.0) return mix(uScene.skyHorizon.rgb, uScene.skyZenith.rgb, d.y);
    return mix(uScene.skyHorizon.rgb, uScene.skyGround.rgb, min(1.0, -4.0 * d.y));
}

float srgbToLinear(float c) {
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

vec4 unpackTexel(uint p) {
    return vec4(srgbToLinear(float(p & 0xffu) / 255.0), srgbToLinear(float((p >> 8) & 0xffu) / 255.0),
                srgbToLinear(float((p >> 16) & 0xffu) / 255.0), float(p >> 24) / 255.0);
}

int wrapIndex(int i, int n) { return ((i % n) + n) % n; }

// Texel (x, y) of a texture: sRGB colour decoded to linear, or data (`srgb` false) as stored.
vec4 fetchTexel(uvec4 info, int x, int y, bool srgb) {
    uint p = texelFetch(uTexels, int(info.x) + y * int(info.y) + x).r;
    return srgb ? unpackTexel(p) : unpackUnorm4x8(p);
}

// Texture `info` bilinearly at uv, wrapping: colour (sRGB) or data such as glTF's
// metallic-roughness texture.
vec4 bilinearTexture(uvec4 info, vec2 uv, bool srgb) {
    int w = int(info.y), h = int(info.z);
    float x = uv.x * float(w) - 0.5;
    float y = uv.y * float(h) - 0.5;
    float fx = floor(x), fy = floor(y);
    float ax = x - fx, ay = y - fy;
    int x0 = wrapIndex(int(fx), w), x1 = wrapIndex(int(fx) + 1, w);
    int y0 = wrapIndex(int(fy), h), y1 = wrapIndex(int(fy) + 1, h);
    return mix(mix(fetchTexel(info, x0, y0, srgb), fetchTexel(info, x1, y0, srgb), ax),
               mix(fetchTexel(info, x0, y1, srgb), fetchTexel(info, x1, y1, srgb), ax), ay);
}

// Level `level` of texture `info`'s mip chain (trace_shared.h) as an info texel of its own.
uvec4 textureLevel(uvec4 info, uint level) {
    uint offset = info.x, w = info.y, h = info.z;
    for (uint l = 0u; l < level; ++l) {
        offset += w * h;
        w = max(1u, w / 2u);
        h = max(1u, h / 2u);
    }
    return uvec4(offset, w, h, 1u);
}

// Texture `info` at level of detail `lod` (log2 of level-0 texels across the footprint),
// trilinearly between the two nearest levels; at lod <= 0, level 0 as bilinearTexture.
vec4 filteredTexture(uvec4 info, vec2 uv, float lod, bool srgb) {
    float top = float(max(info.w, 1u) - 1u);
    lod = min(lod, top);
    if (lod <= 0.0) return bilinearTexture(info, uv, srgb);
    uint l0 = uint(lod);
    float f = lod - float(l0);
    vec4 a = bilinearTexture(textureLevel(info, l0), uv, srgb);
    if (f <= 0.0) return a;
    return mix(a, bilinearTexture(textureLevel(info, l0 + 1u), uv, srgb), f);
}

// Texture `tex` of a material (kNoTexture: `none`) at a footprint whose level of detail per
// unit of UV is uvLod (log2 of the footprint's width in UV units): ray cones (Akenine-Moller et
// al. 2019) add log2 of the texture's size.
vec4 materialTexture(uint tex, vec2 uv, float uvLod, bool srgb, vec4 none) {
    if (tex == kNoTexture) return none;
    uvec4 info = texelFetch(uTextureInfo, int(tex));
    return filteredTexture(info, uv, uvLod + 0.5 * log2(float(info.y) * float(info.z)), srgb);
}

vec4 materialBaseColor(uint material, vec2 uv) {
    vec4 factor = texelFetch(uMaterials, int(material * kMaterialTexels));
    uint tex = floatBitsToUint(texelFetch(uMaterials, int(material * kMaterialTexels) + 2).y);
    if (tex == kNoTexture) return factor;
    return factor * bilinearTexture(texelFetch(uTextureInfo, int(tex)), uv, true);
}

// The shading normal n and geometric normal ng of a hit, in world space, ng facing the ray
// (dir) and n on ng's side.
void hitNormals(Hit hit, vec3 dir, vec4 s0, vec4 s1, vec4 s2, out vec3 n, out vec3 ng) {
    float w0 = 1.0 - hit.u - hit.v;
    n = normalize(w0 * s0.xyz + hit.u * s1.xyz + hit.v * s2.xyz);
    int tb = int(hit.tri) * 3;
    ng = normalize(cross(texelFetch(uTriangles, tb + 1).xyz, texelFetch(uTriangles, tb + 2).xyz));
    if (kDynamic && hit.inst != 0xffffffffu) { // an instance's normals are in object space
        n = instanceNormalToWorld(hit.inst, n);
        ng = instanceNormalToWorld(hit.inst, ng);
    }
    if (dot(ng, dir) > 0.0) ng = -ng;
    if (dot(n, ng) < 0.0) n = -n;
}

float offsetScale(vec3 p) { return 1e-4 * max(1.0, max(abs(p.x), max(abs(p.y), abs(p.z)))); }

// Punctual light li's irradiance at p (normal to the light) and its direction and distance
// (infinite for a directional light): KHR_lights_punctual's inverse-square falloff, its range
// window and its spot cone.
vec3 lightIrradiance(uint li, vec3 p, out vec3 toLight, out float dist) {
    int lb = int(li * kLightTexels);
    vec4 l0 = texelFetch(uLights, lb), l1 = texelFetch(uLights, lb + 1);
    vec4 l2 = texelFetch(uLights, lb + 2), l3 = texelFetch(uLights, lb + 3);
    uint type = floatBitsToUint(l0.w);
    if (type == kLightDirectional) {
        toLight = -l1.xyz;
        dist = kInf;
        return l2.rgb;
    }
    vec3 d = l0.xyz - p;
    dist = length(d);
    toLight = d / dist;
    float atten = 1.0 / max(dist * dist, 1e-4);
    if (l1.w > 0.0) {
        float r = dist / l1.w;
        atten *= clamp(1.0 - r * r * r * r, 0.0, 1.0);
    }
    if (type == kLightSpot) {
        float s = clamp((dot(l1.xyz, -toLight) - l3.x) / max(l2.w - l3.x, 1e-4), 0.0, 1.0);
        atten *= s * s;
    }
    return l2.rgb * atten;
}

// Radiance along a camera ray: see gt::trace::CpuTracer::radiance for the rules.
// `depth` receives the distance to the first hit (kInf on a miss) for temporal passes.
vec3 traceRadiance(vec3 origin, vec3 dir, out float depth) {
    vec3 result = vec3(0.0);
    vec3 throughput = vec3(1.0);
    depth = kInf;
    for (int bounce = 0; bounce < 2; ++bounce) {
        Hit hit = traceClosest(origin, dir, 0.0, kInf);
        if (bounce == 0) depth = hit.t;
        if (kDynamic && bounce == 0) gMotion = hitMotion(hit, origin + hit.t * dir);
        if (hit.tri == 0xffffffffu) {
            result += throughput * skyRadiance(dir);
            break;
        }
        vec4 s0, s1, s2, s3;
        shadingTexels(hit.tri, s0, s1, s2, s3);
        vec3 n, ng;
        hitNormals(hit, dir, s0, s1, s2, n, ng);
        vec2 uv = shadingUv(s0, s1, s2, s3, hit.u, hit.v);
        uint material = floatBitsToUint(s3.w);
        vec3 base = materialBaseColor(material, uv).rgb;
        vec4 m1 = texelFetch(uMaterials, int(material * kMaterialTexels) + 1);
        vec3 emissive = m1.rgb;
        float metallic = m1.w;
        if (metallic < 0.0) { // KHR_materials_unlit: the base colour is what the eye sees
            result += throughput * base;
            break;
        }
        vec3 p = origin + hit.t * dir;
        vec3 offsetOrigin = p + ng * offsetScale(p);

        vec3 direct = vec3(0.0);
        uint lit = 0u; // lights 0-7 reaching the first hit, for gMotion's signature
        uint lightCount = uScene.counts.x;
        for (uint li = 0u; li < lightCount; ++li) {
            vec3 toLight;
            float dist;
            vec3 e = lightIrradiance(li, p, toLight, dist);
            float cosTheta = dot(n, toLight);
            if (cosTheta <= 0.0 || dot(e, e) == 0.0) continue;
            float shadowMax = isinf(dist) ? kInf : dist * 0.999;
            if (!traceOccluded(offsetOrigin, toLight, shadowMax)) {
                direct += e * cosTheta;
                if (kDynamic && li < 8u) lit |= 1u << li;
            }
        }
        if (kDynamic && bounce == 0) {
            gMotion.w = uintBitsToFloat(floatBitsToUint(gMotion.w) | (lit << kShadowMaskShift));
        }
        vec3 albedo = base * (1.0 - metallic);
        vec3 ambient = uScene.skyHorizon.w * skyRadiance(n);
        result += throughput * (emissive + albedo * (direct / kPi + ambient));
        if (metallic <= 0.0 || bounce == 1) break;
        throughput *= metallic * base;
        dir = reflect(dir, n);
        origin = offsetOrigin;
    }
    return result;
}

vec3 cameraRay(CameraPush cam, vec2 pixel, vec2 size) {
    // right.w and up.w: the centre of an off-axis frustum (0 for a symmetric one).
    float sx = (2.0 * pixel.x / size.x - 1.0) * cam.origin.w * cam.forward.w + cam.right.w;
    float sy = (1.0 - 2.0 * pixel.y / size.y) * cam.origin.w + cam.up.w;
    return normalize(cam.forward.xyz + sx * cam.right.xyz + sy * cam.up.xyz);
}
#endif
