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
// on; an optional firefly clamp on indirect light.
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
    float metallic;  // < 0: KHR_materials_unlit
    float alpha;     // GGX alpha = roughness^2 (the glTF convention)
    float specular;  // a dielectric's specular weight (KHR_materials_specular)
};

// The surface hit by the ray (origin, dir), its normals as traceRadiance orients them.
Surface surfaceAt(Hit hit, vec3 origin, vec3 dir) {
    vec4 s0, s1, s2, s3;
    shadingTexels(hit.tri, s0, s1, s2, s3);
    vec3 n, ng;
    hitNormals(hit, dir, s0, s1, s2, n, ng);
    uint material = floatBitsToUint(s3.w);
    int mb = int(material * kMaterialTexels);
    vec4 m1 = texelFetch(uMaterials, mb + 1);
    vec4 m2 = texelFetch(uMaterials, mb + 2);
    vec2 uv = shadingUv(s0, s1, s2, s3, hit.u, hit.v);
    float roughness = m2.x;
    Surface s;
    s.p = origin + hit.t * dir;
    s.n = n;
    s.ng = ng;
    s.base = materialBaseColor(material, uv).rgb;
    s.emissive = m1.rgb;
    s.metallic = m1.w;
    uint mrTexture = floatBitsToUint(texelFetch(uMaterials, mb + 3).x);
    if (mrTexture != kNoTexture && s.metallic >= 0.0) { // glTF 2.0, 3.9.2: G roughness, B metal
        vec4 mr = bilinearTexture(texelFetch(uTextureInfo, int(mrTexture)), uv, false);
        roughness *= mr.g;
        s.metallic *= mr.b;
    }
    s.alpha = max(roughness * roughness, kMinAlpha);
    s.specular = m2.w;
    return s;
}

vec3 offsetOrigin(Surface s) { return s.p + s.ng * offsetScale(s.p); }

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
    float fd = s.specular * schlick(0.04, nv);
    float spec = (1.0 - s.metallic) * fd + s.metallic * luminance(schlick(s.base, nv));
    float diff = (1.0 - s.metallic) * (1.0 - fd) * luminance(s.base);
    return spec + diff > 0.0 ? spec / (spec + diff) : 0.0;
}

// f(wo, wi), and in `pdf` the solid-angle density with which bsdfSample picks wi. glTF 2.0,
// Appendix B: mix(dielectric, metal, metallic), dielectric = mix(diffuse, specular, weight
// * F(0.04)) and metal = specular * F(base); specular = F D G2 / (4 |n.wo| |n.wi|) with the
// height-correlated G2 = 1 / (1 + Lambda(wo) + Lambda(wi)) (Heitz 2014, eq. 99).
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
    float fd = s.specular * schlick(0.04, vh);
    vec3 fSpec = (1.0 - s.metallic) * fd + s.metallic * schlick(s.base, vh);
    vec3 f = (1.0 - s.metallic) * (1.0 - fd) * s.base / kPi + fSpec * d * g2 / (4.0 * nv * nl);
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
bool bsdfSample(Surface s, vec3 wo, out vec3 wi) {
    vec3 t, b;
    basisOf(s.n, t, b);
    float nv = dot(s.n, wo);
    float pick = nextRandom();
    vec2 u = nextRandom2();
    if (pick < specularProbability(s, nv)) {
        vec3 m = sampleGgxVndf(vec3(dot(wo, t), dot(wo, b), nv), s.alpha, u);
        wi = reflect(-wo, m.x * t + m.y * b + m.z * s.n);
    } else {
        float r = sqrt(u.x), phi = 2.0 * kPi * u.y;
        wi = r * cos(phi) * t + r * sin(phi) * b + sqrt(max(0.0, 1.0 - u.x)) * s.n;
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
        if (traceOccluded(offsetOrigin(s), toLight, isinf(dist) ? kInf : dist * 0.999)) continue;
        sum += f * e * cosTheta;
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
    uint material = floatBitsToUint(texelFetch(uShading, int(tri * kShadingTexels) + 3).w);
    vec3 emissive = texelFetch(uMaterials, int(material * kMaterialTexels) + 1).rgb;
    float pdfLight = emitterPdf(emissive, dist, abs(dot(normalize(cross(e1, e2)), wi)));
    float pdfBsdf;
    vec3 f = bsdfEval(s, wo, wi, pdfBsdf);
    if (pdfLight <= 0.0 || dot(f, f) == 0.0) return vec3(0.0);
    // The shadow ray from the offset origin, ending short of the emitter by a share of its own
    // length: from s.p, a surface a few offsets from the lamp would find the lamp itself.
    vec3 o = offsetOrigin(s);
    float shadowDist = length(q - o);
    if (traceOccluded(o, (q - o) / shadowDist, shadowDist * 0.999)) return vec3(0.0);
    return f * emissive * cosTheta * powerHeuristic(pdfLight, pdfBsdf) / pdfLight;
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
    if (dot(f, f) == 0.0 || traceOccluded(offsetOrigin(s), wi, kInf)) return vec3(0.0);
    return f * environmentRadiance(wi) * cosTheta * powerHeuristic(pdfLight, pdfBsdf) / pdfLight;
}

// The MIS weight of the sky found by a BSDF sample of density pdfBsdf: an environment map is
// also sampled by environmentLight; the sky gradient is not.
float skyWeight(vec3 dir, float pdfBsdf) {
    if (uScene.environment.x == 0u) return 1.0;
    return powerHeuristic(pdfBsdf, environmentPdf(dir));
}

// The MIS weight of emission found by a BSDF sample of density pdfBsdf: the emitter table also
// holds the triangle unless it belongs to a moving instance (those are not in the table).
float emissionWeight(Hit hit, vec3 dir, vec3 emissive, float pdfBsdf) {
    if (kDynamic && hit.inst != 0xffffffffu) return 1.0;
    if (uScene.emitters.x == 0u) return 1.0;
    int tb = int(hit.tri) * 3;
    vec3 ng = normalize(cross(texelFetch(uTriangles, tb + 1).xyz, texelFetch(uTriangles, tb + 2).xyz));
    return powerHeuristic(pdfBsdf, emitterPdf(emissive, hit.t, abs(dot(ng, dir))));
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

// ---- The integrators --------------------------------------------------------------------------
// Radiance along a camera ray by path tracing. A path's vertex b (0: the camera ray's hit)
// gathers its emission (MIS-weighted against the emitter sampling from vertex b - 1), and
// unless it is the last, next-event estimation; the BSDF sample then extends the path.
vec3 tracePath(vec3 origin, vec3 dir, out float depth) {
    vec3 radiance = vec3(0.0), throughput = vec3(1.0);
    float pdfBsdf = 0.0; // of the direction that led to the current vertex
    depth = kInf;
    for (uint b = 0u; b <= kBounces; ++b) {
        Hit hit = traceClosest(origin, dir, 0.0, kInf);
        if (b == 0u) recordFirstHit(hit, origin, dir, depth);
        if (hit.tri == 0xffffffffu) {
            float w = b == 0u ? 1.0 : skyWeight(dir, pdfBsdf);
            radiance += clampIndirect(throughput * skyRadiance(dir) * w, b);
            break;
        }
        Surface s = surfaceAt(hit, origin, dir);
        if (s.metallic < 0.0) { // KHR_materials_unlit: the base colour is what the eye sees
            radiance += clampIndirect(throughput * s.base, b);
            break;
        }
        if (dot(s.emissive, s.emissive) > 0.0) {
            float w = b == 0u ? 1.0 : emissionWeight(hit, dir, s.emissive, pdfBsdf);
            radiance += clampIndirect(throughput * s.emissive * w, b);
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
