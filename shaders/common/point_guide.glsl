// One point's guides for the point denoiser (pass point_denoise), as point_sample writes them:
// the first visible surface's normal (octahedral, Cigolle et al. 2014, "A Survey of Efficient
// Representations for Independent Unit Vectors"), the albedo its light is demodulated by (8
// bits a channel), and the variance of the point's mean luminance over its rays.
#ifndef POINT_GUIDE_GLSL
#define POINT_GUIDE_GLSL

vec2 octWrap(vec2 v) { return (1.0 - abs(v.yx)) * mix(vec2(-1.0), vec2(1.0), greaterThanEqual(v, vec2(0.0))); }

// n = 0 (the sky) encodes as (2, 2), outside the octahedron's square.
vec2 octEncode(vec3 n) {
    float l1 = abs(n.x) + abs(n.y) + abs(n.z);
    if (l1 <= 0.0) return vec2(2.0);
    vec2 p = n.xy / l1;
    return n.z >= 0.0 ? p : octWrap(p);
}

vec3 octDecode(vec2 e) {
    if (e.x > 1.5) return vec3(0.0);
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = octWrap(n.xy);
    return normalize(n);
}

// variance < 0: unknown (a point of one ray).
vec4 encodePointGuide(vec3 normal, vec3 albedo, float variance) {
    return vec4(octEncode(normal), uintBitsToFloat(packUnorm4x8(vec4(albedo, 0.0))), variance);
}

struct PointGuide {
    vec3 normal;
    vec3 albedo;
    float variance;
};

PointGuide decodePointGuide(vec4 g) {
    return PointGuide(octDecode(g.xy), max(unpackUnorm4x8(floatBitsToUint(g.z)).rgb, vec3(0.02)), g.w);
}

#endif
