// Linear radiance -> the displayed 8-bit value: exposure, the ACES filmic fit of Narkowicz
// (2015), then the sRGB transfer function. Pass `tonemap` and TAA's tone-mapped output
// (taa.glsl, TAA_TONEMAP) share it, so both give the same bytes.
#ifndef TONEMAP_GLSL
#define TONEMAP_GLSL

vec3 acesFit(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 linearToSrgb(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

vec4 tonemapped(vec3 radiance, float exposure) {
    return vec4(linearToSrgb(acesFit(max(radiance, vec3(0.0)) * exposure)), 1.0);
}
#endif
