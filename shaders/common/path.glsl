// The path-tracing integrator (docs/path-tracing.md) beside trace.glsl's direct one, chosen per
// pipeline by the specialisation constant kIntegrator (trace::IntegratorSettings): the direct
// pipelines compile only traceRadiance, as before.
//
// Model: glTF 2.0's metallic-roughness BRDF (the specification's Appendix B): a Lambertian
// diffuse lobe and a GGX (Trowbridge-Reitz) microfacet specular lobe with height-correlated
// Smith masking-shadowing and Schlick's Fresnel, mixed by metallic. Paths of up to kBounces
// scattering vertices; at each, next-event estimation towards every punctual light (delta
// lights: no MIS), one emissive triangle (power-sampled) and, for an environment map, one
// direction by its luminance, both weighted against the BSDF sample by the power heuristic;
// the sky gradient is found by the BSDF samples only. Russian roulette from the third vertex
// on; an optional firefly clamp on indirect light. Normal, emissive and transmission textures;
// KHR_materials_ior's Fresnel; KHR_materials_transmission as thin-walled glass that light
// crosses straight (shadow rays too); every texture filtered by the ray's footprint (ray cones,
// Akenine-Moller et al. 2019).
#ifndef PATH_GLSL
#define PATH_GLSL
#include "random.glsl"
#include "sequence_shared.h"
#include "trace.glsl"

layout(constant_id = kSpecIntegrator) const uint kIntegrator = kIntegratorDirect;
layout(constant_id = kSpecBounces) const uint kBounces = 4u;
layout(constant_id = kSpecFireflyClamp) const float kFireflyClamp = 0.0;

// GGX alpha below this is a mirror in all but name; the floor keeps D and the VNDF finite.
const float kMinAlpha = 0.002;

// ---- Random numbers ---------------------------------------------------------------------------
// Each random decision of a path draws one 2-D point (nextRandom2; nextRandom uses its first
// coordinate), in the order the path makes them, so decision d of every path of a pixel (or
// point) comes from one sequence indexed by frame * rays + ray. kSequence picks it:
//   sobol:       the shuffled, Owen-scrambled Sobol' points of sequence_shared.h, seeded per
//                pixel or point and decision: stratified over the rays and frames a pixel pools;
//   independent: a 32-bit LCG whose state goes through PCG's output permutation (O'Neill 2014;
//                the RXS-M-XS step of Jarzynski & Olano 2020), one stream per (pixel or point,
//                ray, frame).
layout(constant_id = kSpecSequence) const uint kSequence = kSequenceIndependent;
uint gPathRng = 0u;
uint gSampleIndex = 0u, gSampleSeed = 0u, gSampleDecision = 0u;

void seedPath(uint point, uint ray, uint rays, uint frame) {
    gPathRng = pcgHash(point ^ pcgHash(ray ^ pcgHash(frame + 0x632BE5ABu)));
    gSampleIndex = frame * rays + ray;
    gSampleSeed = sequenceHash(point ^ 0x632BE5ABu);
    gSampleDecision = 0u;
}

float independentRandom() {
    gPathRng = gPathRng * 747796405u + 2891336453u;
    uint w = ((gPathRng >> ((gPathRng >> 28u) + 4u)) ^ gPathRng) * 277803737u;
    return hashToFloat((w >> 22u) ^ w);
}

vec2 nextRandom2() {
    if (kSequence == kSequenceSobol) {
        uint seed = hashCombine(gSampleSeed, sequenceHash(gSampleDecision++));
        return sobolOwen2(gSampleIndex, seed);
    }
    float u = independentRandom();
    return vec2(u, independentRandom());
}

float nextRandom() { return kSequence == kSequenceSobol ? nextRandom2().x : independentRandom(); }

// Where in its pixel ray `ray` of `rays` goes in `frame`: for the path integrator with the Sobol'
// sequence a decision of its own (seeded apart from the path's), stratified over the rays and
// frames the pixel pools as the path's decisions are; otherwise `otherwise` (the reference's
// jittered strata, as the direct integrator has them).
vec2 pixelOffset(uint pixel, uint ray, uint rays, uint frame, vec2 otherwise) {
    if (kIntegrator == kIntegratorDirect || kSequence != kSequenceSobol) return otherwise;
    return sobolOwen2(frame * rays + ray, hashCombine(sequenceHash(pixel ^ 0x632BE5ABu), 0xB5297A4Du));
}

// Rec. 709 luminance, as gpu_scene.cpp weighs the emitters' power.
float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// ---- The surface at a hit ---------------------------------------------------------------------
struct Surface {
    vec3 p;          // position
    vec3 n;          // shading normal, on the side the ray came from
    vec3 ng;         // geometric normal, on that side too
    vec3 base;       // base colour (factor times texture)
    vec3 emissive;   // radiance emitted (both sides, as the direct integrator sees it)
    vec3 emissiveFactor; // the material's emissive factor (what the emitter table weighs)
    float metallic;  // < 0: KHR_materials_unlit
    float alpha;     // GGX alpha = roughness^2 (the glTF convention)
    float specular;  // a dielectric's specular weight (KHR_materials_specular)
    float f0;        // a dielectric's Fresnel reflectance at normal incidence, from its IOR
    float transmission; // KHR_materials_transmission (times its texture)
    float coverage;  // alphaMode BLEND: the base colour's alpha; else 1
};

// Ray cones (Akenine-Moller et al. 2019, "Texture Level of Detail Strategies for Real-Time Ray
// Tracing", section 20.3.4): a ray's footprint is a cone of spread angle gConeSpread (radians
// per unit distance) whose width grows by spread * t along each segment. The tracing pass sets
// gPixelSpread to a display pixel's angle (0: every texture at level 0); each scattering
// widens the cone by its lobe (bsdfSample).
float gPixelSpread = 0.0;
float gConeSpread = 0.0, gConeWidth = 0.0;

// log2 of the cone's footprint in UV units on the hit's triangle: the cone's width over the
// cosine of incidence, scaled by the triangle's UV-to-world area ratio (the paper's Delta,
// eq. 20.4, without the texture's size, which materialTexture adds).
float footprintUvLod(vec3 e1, vec3 e2, vec2 duv1, vec2 duv2, vec3 n, vec3 dir) {
    if (gConeWidth <= 0.0) return -1e30;
    float worldArea = length(cross(e1, e2));
    float uvArea = abs(duv1.x * duv2.y - duv2.x * duv1.y);
    float cosine = max(abs(dot(n, dir)), 1e-3);
    return log2(gConeWidth / cosine) + 0.5 * log2(max(uvArea, 1e-20) / max(worldArea, 1e-20));
}

// The shading normal bent by a tangent-space normal texture (glTF 2.0, 3.9.3), as the glTF
// sample viewer does without TANGENT: the tangent is the triangle's dp/du from its UVs (flat
// over the triangle, an approximation of MikkTSpace's smooth one), the bitangent n x t. nRaw:
// the interpolated normal before it was turned to face the ray; the result is turned the same
// way, and kept facing wo so that a bent normal leaves no black pixels.
vec3 normalMapped(uint tex, float scale, vec2 uv, float uvLod, vec3 nRaw, vec3 n, vec3 wo,
                  vec3 e1, vec3 e2, vec2 duv1, vec2 duv2, uint inst) {
    float det = duv1.x * duv2.y - duv2.x * duv1.y;
    if (tex == kNoTexture || abs(det) < 1e-20) return n;
    vec3 t = (e1 * duv2.y - e2 * duv1.y) / det;
    if (kDynamic && inst != 0xffffffffu) t = instanceNormalToWorld(inst, t);
    t -= nRaw * dot(nRaw, t);
    if (dot(t, t) < 1e-20) return n;
    t = normalize(t);
    vec3 c = materialTexture(tex, uv, uvLod, false, vec4(0.5, 0.5, 1.0, 1.0)).xyz * 2.0 - 1.0;
    c.xy *= scale;
    vec3 bent = normalize(c.x * t + c.y * cross(nRaw, t) + max(c.z, 1e-3) * nRaw);
    if (dot(nRaw, n) < 0.0) bent = -bent;
    float facing = dot(bent, wo);
    return facing >= 0.01 ? bent : normalize(bent + (0.01 - facing) * wo);
}

// The surface hit by the ray (origin, dir), its normals as traceRadiance orients them, its
// textures filtered by the ray cone's width there (gConeWidth).
Surface surfaceAt(Hit hit, vec3 origin, vec3 dir) {
    vec4 s0, s1, s2, s3;
    shadingTexels(hit.tri, s0, s1, s2, s3);
    vec3 n, ng;
    hitNormals(hit, dir, s0, s1, s2, n, ng);
    uint material = floatBitsToUint(s3.w);
    int mb = int(material * kMaterialTexels);
    vec4 m0 = texelFetch(uMaterials, mb);
    vec4 m1 = texelFetch(uMaterials, mb + 1);
    vec4 m2 = texelFetch(uMaterials, mb + 2);
    vec4 m3 = texelFetch(uMaterials, mb + 3);
    vec4 m4 = texelFetch(uMaterials, mb + 4);
    vec2 uv = shadingUv(s0, s1, s2, s3, hit.u, hit.v);
    int tb = int(hit.tri) * 3;
    vec3 e1 = texelFetch(uTriangles, tb + 1).xyz, e2 = texelFetch(uTriangles, tb + 2).xyz;
    vec2 duv1 = vec2(s2.w, s3.x) - vec2(s0.w, s1.w), duv2 = s3.yz - vec2(s0.w, s1.w);
    float uvLod = footprintUvLod(e1, e2, duv1, duv2, ng, dir);
    float roughness = m2.x;
    Surface s;
    s.p = origin + hit.t * dir;
    s.ng = ng;
    vec4 base = m0 * materialTexture(floatBitsToUint(m2.y), uv, uvLod, true, vec4(1.0));
    s.base = base.rgb;
    s.coverage = m4.w > 0.5 ? clamp(base.a, 0.0, 1.0) : 1.0;
    s.emissiveFactor = m1.rgb;
    s.emissive = m1.rgb * s.coverage *
                 materialTexture(floatBitsToUint(m3.w), uv, uvLod, true, vec4(1.0)).rgb;
    s.metallic = m1.w;
    if (s.metallic >= 0.0) { // glTF 2.0, 3.9.2: G roughness, B metal
        vec4 mr = materialTexture(floatBitsToUint(m3.x), uv, uvLod, false, vec4(1.0));
        roughness *= mr.g;
        s.metallic *= mr.b;
    }
    s.alpha = max(roughness * roughness, kMinAlpha);
    s.specular = m2.w;
    float r = (m4.y - 1.0) / (m4.y + 1.0); // KHR_materials_ior: F0 = ((ior - 1) / (ior + 1))^2
    s.f0 = r * r;
    s.transmission = m4.x * materialTexture(floatBitsToUint(m4.z), uv, uvLod, false, vec4(1.0)).r;
    vec3 nRaw = (1.0 - hit.u - hit.v) * s0.xyz + hit.u * s1.xyz + hit.v * s2.xyz;
    if (kDynamic && hit.inst != 0xffffffffu) nRaw = instanceNormalToWorld(hit.inst, nRaw);
    s.n = normalMapped(floatBitsToUint(m3.y), m3.z, uv, uvLod, normalize(nRaw), n, -dir, e1, e2,
                       duv1, duv2, hit.inst);
    return s;
}

vec3 offsetOrigin(Surface s) { return s.p + s.ng * offsetScale(s.p); }

// ---- Light through a surface: thin-walled transmission and blended coverage -------------------
// KHR_materials_transmission without KHR_materials_volume: the surface is a thin sheet, and
// light it transmits leaves on the other side in the direction it came, tinted by the base
// colour (glTF's specular_btdf * baseColor, mixed by transmission under the Fresnel layer). The
// transmitted lobe is taken as straight through, a delta: its roughness does not blur what is
// seen through it (not modelled). Weight at cosine c: (1 - metallic) * transmission *
// (1 - specular * F(c)) * base. alphaMode BLEND: the surface covers `coverage` of its area;
// the rest passes everything, and the surface's own response (bsdfEval, emission) is scaled
// by its coverage.
vec3 passWeight(Surface s, vec3 dir) {
    if (s.metallic < 0.0) return vec3(0.0);
    float f = s.f0 + (1.0 - s.f0) * pow(1.0 - abs(dot(s.n, dir)), 5.0); // Schlick
    vec3 sheet = (1.0 - s.metallic) * s.transmission * (1.0 - s.specular * f) * s.base;
    return (1.0 - s.coverage) + s.coverage * sheet;
}

// Surfaces a path or a shadow ray may cross this way before it counts as blocked.
const uint kMaxPasses = 8u;

// What reaches along the ray (origin, dir) over distance tMax: nothing past an opaque surface,
// through each thin transmissive one its passWeight. A scene without such materials
// (SceneUniforms::emitters.w) takes the any-hit occlusion test alone.
vec3 transmittance(vec3 origin, vec3 dir, float tMax) {
    if (uScene.emitters.w == 0u) return traceOccluded(origin, dir, tMax) ? vec3(0.0) : vec3(1.0);
    vec3 through = vec3(1.0);
    for (uint k = 0u; k <= kMaxPasses; ++k) {
        Hit hit = traceClosest(origin, dir, 0.0, tMax);
        if (hit.tri == 0xffffffffu) return through;
        Surface s = surfaceAt(hit, origin, dir);
        through *= passWeight(s, dir);
        if (dot(through, through) == 0.0) break;
        vec3 next = s.p - s.ng * offsetScale(s.p);
        tMax -= length(next - origin);
        origin = next;
        if (tMax <= 0.0) return through;
    }
    return vec3(0.0);
}

// ---- The BSDF ---------------------------------------------------------------------------------
// Trowbridge-Reitz / GGX normal distribution (Walter et al. 2007, eq. 33).
float ggxD(float nh, float a2) {
    float d = nh * nh * (a2 - 1.0) + 1.0;
    return a2 / (kPi * d * d);
}

// Smith's Lambda for GGX (Heitz 2014, "Understanding the Masking-Shadowing Function", eq. 72).
float smithLambda(float c, float a2) {
    float c2 = c * c;
    return 0.5 * (-1.0 + sqrt(1.0 + a2 * max(1.0 - c2, 0.0) / c2));
}

float schlick(float f0, float c) { return f0 + (1.0 - f0) * pow(1.0 - c, 5.0); }
vec3 schlick(vec3 f0, float c) { return f0 + (1.0 - f0) * pow(1.0 - c, 5.0); }

// The share of samples bsdfSample gives the specular lobe: its Fresnel-weighted albedo against
// the diffuse lobe's, both estimated at the view angle.
float specularProbability(Surface s, float nv) {
    float fd = s.specular * schlick(s.f0, nv);
    float spec = (1.0 - s.metallic) * fd + s.metallic * luminance(schlick(s.base, nv));
    float diff = (1.0 - s.metallic) * (1.0 - fd) * (1.0 - s.transmission) * luminance(s.base);
    return spec + diff > 0.0 ? spec / (spec + diff) : 0.0;
}

// f(wo, wi), and in `pdf` the solid-angle density with which bsdfSample picks wi. glTF 2.0,
// Appendix B: mix(dielectric, metal, metallic), dielectric = mix(diffuse, specular, weight
// * F(f0)) and metal = specular * F(base); specular = F D G2 / (4 |n.wo| |n.wi|) with the
// height-correlated G2 = 1 / (1 + Lambda(wo) + Lambda(wi)) (Heitz 2014, eq. 99). The diffuse
// lobe keeps the share (1 - transmission) that the thin sheet does not pass (passWeight).
vec3 bsdfEval(Surface s, vec3 wo, vec3 wi, out float pdf) {
    pdf = 0.0;
    float nv = dot(s.n, wo), nl = dot(s.n, wi);
    if (nv <= 0.0 || nl <= 0.0) return vec3(0.0);
    vec3 h = normalize(wo + wi);
    float nh = clamp(dot(s.n, h), 0.0, 1.0), vh = clamp(dot(wo, h), 0.0, 1.0);
    float a2 = s.alpha * s.alpha;
    float d = ggxD(nh, a2);
    float lambdaV = smithLambda(nv, a2);
    float g2 = 1.0 / (1.0 + lambdaV + smithLambda(nl, a2));
    float fd = s.specular * schlick(s.f0, vh);
    vec3 fSpec = (1.0 - s.metallic) * fd + s.metallic * schlick(s.base, vh);
    vec3 f = s.coverage * ((1.0 - s.metallic) * (1.0 - fd) * (1.0 - s.transmission) * s.base / kPi
                           + fSpec * d * g2 / (4.0 * nv * nl));
    // The visible-normal density reflected about h: G1(wo) D(h) / (4 n.wo) (Heitz 2018,
    // "Sampling the GGX Distribution of Visible Normals", eq. 3 with the reflection's 1 / (4 wo.h)).
    float pdfSpec = d / (4.0 * nv * (1.0 + lambdaV));
    float ps = specularProbability(s, nv);
    pdf = ps * pdfSpec + (1.0 - ps) * nl / kPi;
    return f;
}

// An orthonormal basis around n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
void basisOf(vec3 n, out vec3 t, out vec3 b) {
    float sign = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (sign + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x);
    b = vec3(c, sign + n.y * n.y * a, -n.y);
}

// A microfacet normal from GGX's distribution of normals visible from ve (local frame, z up;
// Heitz 2018, listing 1): a point on the hemisphere stretched to alpha 1, projected.
vec3 sampleGgxVndf(vec3 ve, float alpha, vec2 u) {
    vec3 vh = normalize(vec3(alpha * ve.x, alpha * ve.y, ve.z));
    float lensq = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = lensq > 0.0 ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(lensq) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(vh, t1);
    float r = sqrt(u.x), phi = 2.0 * kPi * u.y;
    float p1 = r * cos(phi), p2 = r * sin(phi);
    float sh = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - sh) * sqrt(max(1.0 - p1 * p1, 0.0)) + sh * p2;
    vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    return normalize(vec3(alpha * nh.x, alpha * nh.y, max(0.0, nh.z)));
}

// A direction wi by one lobe, picked with specularProbability: the specular lobe's by its
// visible normals, the diffuse lobe's cosine-weighted (Malley's method). False when wi falls
// below the shading or the geometric surface (the path ends: no light leaks through).
// The ray cone widens by the sampled lobe's angular width: GGX alpha for the specular lobe (a
// mirror keeps the cone), a radian for the diffuse one (a heuristic; ray cones define no
// spread for rough lobes).
bool bsdfSample(Surface s, vec3 wo, out vec3 wi) {
    vec3 t, b;
    basisOf(s.n, t, b);
    float nv = dot(s.n, wo);
    float pick = nextRandom();
    vec2 u = nextRandom2();
    if (pick < specularProbability(s, nv)) {
        vec3 m = sampleGgxVndf(vec3(dot(wo, t), dot(wo, b), nv), s.alpha, u);
        wi = reflect(-wo, m.x * t + m.y * b + m.z * s.n);
        gConeSpread += s.alpha > kMinAlpha ? s.alpha : 0.0;
    } else {
        float r = sqrt(u.x), phi = 2.0 * kPi * u.y;
        wi = r * cos(phi) * t + r * sin(phi) * b + sqrt(max(0.0, 1.0 - u.x)) * s.n;
        gConeSpread += 1.0;
    }
    return dot(s.n, wi) > 0.0 && dot(s.ng, wi) > 0.0;
}

// ---- Light -------------------------------------------------------------------------------------
// Veach 1997, section 9.2.4: the power heuristic with beta = 2.
float powerHeuristic(float a, float b) {
    float a2 = a * a;
    return a2 + b * b > 0.0 ? a2 / (a2 + b * b) : 0.0;
}

// Punctual light li as traceRadiance sees it (lightIrradiance), or zero for a light that
// stands in for an emissive surface (trace_shared.h): that surface is sampled itself.
vec3 punctualIrradiance(uint li, vec3 p, out vec3 toLight, out float dist) {
    toLight = vec3(0.0, 1.0, 0.0);
    dist = kInf;
    if (texelFetch(uLights, int(li * kLightTexels) + 3).y > 0.5) return vec3(0.0);
    return lightIrradiance(li, p, toLight, dist);
}

// Light from every punctual light scattered at s towards wo. `lit` gets the lights 0-7 that
// reach s (gMotion's shadow mask).
vec3 punctualLight(Surface s, vec3 wo, out uint lit) {
    vec3 sum = vec3(0.0);
    lit = 0u;
    for (uint li = 0u; li < uScene.counts.x; ++li) {
        vec3 toLight;
        float dist;
        vec3 e = punctualIrradiance(li, s.p, toLight, dist);
        float cosTheta = dot(s.n, toLight);
        if (cosTheta <= 0.0 || dot(s.ng, toLight) <= 0.0 || dot(e, e) == 0.0) continue;
        float pdf;
        vec3 f = bsdfEval(s, wo, toLight, pdf);
        vec3 through = transmittance(offsetOrigin(s), toLight, isinf(dist) ? kInf : dist * 0.999);
        if (dot(through, through) == 0.0) continue;
        sum += f * e * cosTheta * through;
        if (li < 8u) lit |= 1u << li;
    }
    return sum;
}

// The solid-angle density with which emitterLight picks the direction to a point at distance
// `dist` on a triangle emitting `emissive`, whose geometric normal makes cosine cosLight with
// the direction: per unit area luminance(emissive) / total power (gpu_scene.cpp, packEmitters),
// times dist^2 / cosLight.
float emitterPdf(vec3 emissive, float dist, float cosLight) {
    float perArea = luminance(emissive) / uintBitsToFloat(uScene.emitters.z);
    return cosLight > 0.0 ? perArea * dist * dist / cosLight : 0.0;
}

// Next-event estimation towards the emissive triangles: one triangle from the alias table
// (Walker 1977), a point uniform on it (Turk 1990), weighted against the BSDF sample that
// could have found the same point by the power heuristic.
vec3 emitterLight(Surface s, vec3 wo) {
    uint count = uScene.emitters.x;
    if (count == 0u) return vec3(0.0);
    vec2 pick = nextRandom2(); // the table's column and its coin: stratified together
    uint k = min(uint(pick.x * float(count)), count - 1u);
    vec4 entry = texelFetch(uMaterials, int(uScene.emitters.y + k));
    if (pick.y >= entry.x) {
        entry = texelFetch(uMaterials, int(uScene.emitters.y + floatBitsToUint(entry.y)));
    }
    uint tri = floatBitsToUint(entry.z);
    int tb = int(tri) * 3;
    vec3 v0 = texelFetch(uTriangles, tb).xyz;
    vec3 e1 = texelFetch(uTriangles, tb + 1).xyz, e2 = texelFetch(uTriangles, tb + 2).xyz;
    vec2 u = nextRandom2();
    float su = sqrt(u.x), v = u.y;
    vec3 q = v0 + su * (1.0 - v) * e1 + su * v * e2;
    float dist = length(q - s.p);
    vec3 wi = (q - s.p) / dist;
    float cosTheta = dot(s.n, wi);
    if (cosTheta <= 0.0 || dot(s.ng, wi) <= 0.0) return vec3(0.0);
    vec4 s0, s1, s2, s3;
    shadingTexels(tri, s0, s1, s2, s3);
    int mb = int(floatBitsToUint(s3.w) * kMaterialTexels);
    vec3 emissive = texelFetch(uMaterials, mb + 1).rgb;
    float pdfLight = emitterPdf(emissive, dist, abs(dot(normalize(cross(e1, e2)), wi)));
    float pdfBsdf;
    vec3 f = bsdfEval(s, wo, wi, pdfBsdf);
    if (pdfLight <= 0.0 || dot(f, f) == 0.0) return vec3(0.0);
    // An emissive texture varies the radiance over the triangle; the table weighs the factor
    // alone, which keeps the density above consistent with the one emissionWeight computes.
    vec2 uv = shadingUv(s0, s1, s2, s3, su * (1.0 - v), su * v);
    emissive *= materialTexture(floatBitsToUint(texelFetch(uMaterials, mb + 3).w), uv, -1e30,
                                true, vec4(1.0)).rgb;
    // The shadow ray from the offset origin, ending short of the emitter by a share of its own
    // length: from s.p, a surface a few offsets from the lamp would find the lamp itself.
    vec3 o = offsetOrigin(s);
    float shadowDist = length(q - o);
    vec3 through = transmittance(o, (q - o) / shadowDist, shadowDist * 0.999);
    return f * emissive * through * cosTheta * powerHeuristic(pdfLight, pdfBsdf) / pdfLight;
}

// ---- The environment map's importance sampling (gpu_scene.cpp, packEnvironmentCdf) ---------
// Float k of the tables (four per texel after the map's texels).
float environmentCdf(uint k) {
    return texelFetch(uEnvironment, int(uScene.environment.z + k / 4u))[k % 4u];
}

// The first of n CDF entries from `first` on that exceeds u (binary search).
uint searchCdf(uint first, uint n, float u) {
    uint lo = 0u, hi = n - 1u;
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        if (environmentCdf(first + mid) > u) hi = mid;
        else lo = mid + 1u;
    }
    return lo;
}

float cdfStep(uint first, uint k) {
    return environmentCdf(first + k) - (k > 0u ? environmentCdf(first + k - 1u) : 0.0);
}

// The solid-angle density with which sampleEnvironment picks direction d: the cell's
// probability (marginal times conditional) over its solid angle, (2 pi / cw) (pi / ch) sin(theta)
// (PBR 3rd ed., eq. 14.18).
float environmentPdf(vec3 d) {
    uint cw = uScene.environment.w & 0xffffu, ch = uScene.environment.w >> 16;
    float sinTheta = sqrt(max(0.0, 1.0 - d.y * d.y));
    if (sinTheta <= 1e-6) return 0.0;
    float u = 0.5 + atan(d.x, -d.z) / (2.0 * kPi), v = acos(clamp(d.y, -1.0, 1.0)) / kPi;
    uint i = min(uint(u * float(cw)), cw - 1u), j = min(uint(v * float(ch)), ch - 1u);
    float p = cdfStep(0u, j) * cdfStep(ch + j * cw, i);
    return p * float(cw) * float(ch) / (2.0 * kPi * kPi * sinTheta);
}

// A direction drawn by the environment's luminance: a row by the marginal CDF, a cell in it by
// the row's conditional CDF, a point uniform in the cell's (u, v); as environmentRadiance maps
// them (u from the azimuth, 0 at -z; v from the polar angle, 0 straight up).
vec3 sampleEnvironment(out float pdf) {
    uint cw = uScene.environment.w & 0xffffu, ch = uScene.environment.w >> 16;
    vec2 cell = nextRandom2(), inCell = nextRandom2();
    uint j = searchCdf(0u, ch, cell.x);
    uint i = searchCdf(ch + j * cw, cw, cell.y);
    float u = (float(i) + inCell.x) / float(cw), v = (float(j) + inCell.y) / float(ch);
    float theta = v * kPi, phi = (u - 0.5) * 2.0 * kPi;
    vec3 d = vec3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
    pdf = environmentPdf(d);
    return d;
}

// Next-event estimation towards the environment map: one direction by its luminance, a shadow
// ray to infinity, weighted against the BSDF sample by the power heuristic.
vec3 environmentLight(Surface s, vec3 wo) {
    if (uScene.environment.x == 0u) return vec3(0.0);
    float pdfLight;
    vec3 wi = sampleEnvironment(pdfLight);
    float cosTheta = dot(s.n, wi);
    if (pdfLight <= 0.0 || cosTheta <= 0.0 || dot(s.ng, wi) <= 0.0) return vec3(0.0);
    float pdfBsdf;
    vec3 f = bsdfEval(s, wo, wi, pdfBsdf);
    if (dot(f, f) == 0.0) return vec3(0.0);
    vec3 through = transmittance(offsetOrigin(s), wi, kInf);
    return f * environmentRadiance(wi) * through * cosTheta * powerHeuristic(pdfLight, pdfBsdf) /
           pdfLight;
}

// The MIS weight of the sky found by a BSDF sample of density pdfBsdf: an environment map is
// also sampled by environmentLight; the sky gradient is not.
float skyWeight(vec3 dir, float pdfBsdf) {
    if (uScene.environment.x == 0u) return 1.0;
    return powerHeuristic(pdfBsdf, environmentPdf(dir));
}

// The MIS weight of emission found by a BSDF sample of density pdfBsdf: the emitter table also
// holds the triangle unless it belongs to a moving instance (those are not in the table).
// `dist`: from the vertex that sampled the direction, across any thin sheets passed since.
float emissionWeight(Hit hit, vec3 dir, vec3 emissive, float pdfBsdf, float dist) {
    if (kDynamic && hit.inst != 0xffffffffu) return 1.0;
    if (uScene.emitters.x == 0u) return 1.0;
    int tb = int(hit.tri) * 3;
    vec3 ng = normalize(cross(texelFetch(uTriangles, tb + 1).xyz, texelFetch(uTriangles, tb + 2).xyz));
    return powerHeuristic(pdfBsdf, emitterPdf(emissive, dist, abs(dot(ng, dir))));
}

// Light that reached the eye through `vertices` scattering vertices: from two on it is
// indirect, and the firefly clamp (when on) scales it down to luminance kFireflyClamp. Biased
// (dimmer caustics and glossy interreflections), so off wherever unbiasedness is measured.
vec3 clampIndirect(vec3 c, uint vertices) {
    if (kFireflyClamp <= 0.0 || vertices < 2u) return c;
    float l = luminance(c);
    return l > kFireflyClamp ? c * (kFireflyClamp / l) : c;
}

// The first hit's depth and, in a scene that moves, its motion (as traceRadiance gives them).
void recordFirstHit(Hit hit, vec3 origin, vec3 dir, out float depth) {
    depth = hit.t;
    if (kDynamic) gMotion = hitMotion(hit, origin + hit.t * dir);
}

// The first visible surface's shading normal (0 for the sky) and the colour its light is
// divided by before the point denoiser filters it and multiplied by after (1 where the path
// ends at that surface: the sky, an unlit material, an emitter). Filtering the light without
// the texture keeps the texture's detail (Schied et al. 2017, 4: "demodulated albedo"); the
// floor keeps a black texel from dividing the noise up.
vec3 gFirstNormal = vec3(0.0), gFirstAlbedo = vec3(1.0);
void recordFirstSurface(Surface s) {
    gFirstNormal = s.n;
    const bool ends = s.metallic < 0.0 || dot(s.emissive, s.emissive) > 0.0;
    gFirstAlbedo = ends ? vec3(1.0) : clamp(s.base, vec3(0.02), vec3(1.0));
}

// ---- The integrators --------------------------------------------------------------------------
// A thin transmissive sheet at s (passWeight): the path crosses it straight with probability by
// the weight's luminance, `throughput` scaled for the choice either way. True: it crossed, and
// `origin` moved past the sheet; `dir` and the density of the direction stay.
bool crossSheet(Surface s, vec3 dir, inout vec3 origin, inout vec3 throughput) {
    vec3 pass = passWeight(s, dir);
    float p = min(luminance(pass), 0.99);
    if (p <= 0.0) return false;
    if (nextRandom() < p) {
        throughput *= pass / p;
        origin = s.p - s.ng * offsetScale(s.p);
        return true;
    }
    throughput /= 1.0 - p;
    return false;
}

// Radiance along a camera ray by path tracing. A path's vertex b (0: the camera ray's hit)
// gathers its emission (MIS-weighted against the emitter sampling from vertex b - 1), and
// unless it is the last, next-event estimation; the BSDF sample then extends the path. Thin
// transmissive sheets are crossed without a vertex (crossSheet), at most kMaxPasses a path.
vec3 tracePath(vec3 origin, vec3 dir, out float depth) {
    vec3 radiance = vec3(0.0), throughput = vec3(1.0);
    float pdfBsdf = 0.0; // of the direction that led to the current vertex
    float segment = 0.0; // from the vertex that sampled it to `origin`, across sheets crossed
    uint passes = 0u;
    gConeSpread = gPixelSpread;
    gConeWidth = 0.0;
    depth = kInf;
    gFirstNormal = vec3(0.0);
    gFirstAlbedo = vec3(1.0);
    for (uint b = 0u; b <= kBounces;) {
        Hit hit = traceClosest(origin, dir, 0.0, kInf);
        if (b == 0u && passes == 0u) recordFirstHit(hit, origin, dir, depth);
        if (hit.tri == 0xffffffffu) {
            float w = b == 0u ? 1.0 : skyWeight(dir, pdfBsdf);
            radiance += clampIndirect(throughput * skyRadiance(dir) * w, b);
            break;
        }
        gConeWidth += gConeSpread * hit.t;
        Surface s = surfaceAt(hit, origin, dir);
        if (b == 0u && passes == 0u) recordFirstSurface(s);
        if (s.metallic < 0.0) { // KHR_materials_unlit: the base colour is what the eye sees
            radiance += clampIndirect(throughput * s.base, b);
            break;
        }
        if (dot(s.emissive, s.emissive) > 0.0) {
            float w = b == 0u ? 1.0
                              : emissionWeight(hit, dir, s.emissiveFactor, pdfBsdf, segment + hit.t);
            radiance += clampIndirect(throughput * s.emissive * w, b);
        }
        if (s.transmission > 0.0 || s.coverage < 1.0) {
            vec3 before = origin;
            if (crossSheet(s, dir, origin, throughput)) {
                segment += length(origin - before);
                if (++passes > kMaxPasses) break;
                continue;
            }
        }
        vec3 wo = -dir;
        if (b == kBounces || dot(s.n, wo) <= 0.0) break;
        uint lit;
        vec3 nee = punctualLight(s, wo, lit) + emitterLight(s, wo) + environmentLight(s, wo);
        if (kDynamic && b == 0u) {
            gMotion.w = uintBitsToFloat(floatBitsToUint(gMotion.w) | (lit << kShadowMaskShift));
        }
        radiance += clampIndirect(throughput * nee, b + 1u);
        vec3 wi;
        if (!bsdfSample(s, wo, wi)) break;
        vec3 f = bsdfEval(s, wo, wi, pdfBsdf);
        if (pdfBsdf <= 0.0) break;
        throughput *= f * dot(s.n, wi) / pdfBsdf;
        // Russian roulette from the third vertex on (Arvo & Kirk 1990): survive with
        // probability q = max channel of the throughput (at most 1) and divide by it.
        if (b >= 2u) {
            float q = min(max(throughput.r, max(throughput.g, throughput.b)), 1.0);
            if (nextRandom() >= q) break;
            throughput /= q;
        }
        origin = offsetOrigin(s);
        dir = wi;
        segment = 0.0;
        ++b;
    }
    return radiance;
}

// The same integral by brute force, for verification only: directions uniform over the
// hemisphere of the shading normal, emission counted only where a path hits an emitter (no
// next-event estimation, no MIS, no roulette, no clamp). It shares the BSDF's evaluation with
// tracePath and none of its sampling. Punctual lights cannot be hit and are left out: compare
// on scenes whose light is emissive surfaces and sky.
vec3 traceBruteForce(vec3 origin, vec3 dir, out float depth) {
    vec3 radiance = vec3(0.0), throughput = vec3(1.0);
    depth = kInf;
    for (uint b = 0u; b <= kBounces; ++b) {
        Hit hit = traceClosest(origin, dir, 0.0, kInf);
        if (b == 0u) recordFirstHit(hit, origin, dir, depth);
        if (hit.tri == 0xffffffffu) {
            radiance += throughput * skyRadiance(dir);
            break;
        }
        Surface s = surfaceAt(hit, origin, dir);
        if (s.metallic < 0.0) {
            radiance += throughput * s.base;
            break;
        }
        radiance += throughput * s.emissive;
        vec3 wo = -dir;
        if (b == kBounces || dot(s.n, wo) <= 0.0) break;
        vec3 t, bt;
        basisOf(s.n, t, bt);
        vec2 u = nextRandom2();
        float z = u.x, phi = 2.0 * kPi * u.y;
        float r = sqrt(max(0.0, 1.0 - z * z));
        vec3 wi = r * cos(phi) * t + r * sin(phi) * bt + z * s.n;
        if (dot(s.ng, wi) <= 0.0) break;
        float unused;
        throughput *= bsdfEval(s, wo, wi, unused) * z * (2.0 * kPi); // pdf 1 / (2 pi)
        origin = offsetOrigin(s);
        dir = wi;
    }
    return radiance;
}

// Radiance along a camera ray by the pipeline's integrator; ray `ray` of `rays` per pixel or
// point in `frame` seeds the path's random numbers (the direct integrator uses none).
vec3 traceIntegrator(vec3 origin, vec3 dir, uint point, uint ray, uint rays, uint frame,
                     out float depth) {
    if (kIntegrator == kIntegratorDirect) return traceRadiance(origin, dir, depth);
    seedPath(point, ray, rays, frame);
    if (kIntegrator == kIntegratorBruteForce) return traceBruteForce(origin, dir, depth);
    return tracePath(origin, dir, depth);
}
#endif
