// The set laid on an HMD's panel (engine/display/display_space.hpp): a panel pixel's position
// in the image, through the lens model (green). lens: xy = lens centre (normalised), z =
// aspect, w = rMax (0: no warp); coeffs: x = k1, y = k2, z = 1 / (1 + k1 + k2).
#ifndef PANEL_WARP_GLSL
#define PANEL_WARP_GLSL

vec2 panelToImage(vec2 panel, vec2 size, vec4 lens, vec4 coeffs) {
    if (lens.w <= 0.0) return panel;
    vec2 d = panel / size - lens.xy;
    float r = length(d * vec2(lens.z, 1.0)) / lens.w;
    float r2 = r * r;
    float f = (1.0 + coeffs.x * r2 + coeffs.y * r2 * r2) * coeffs.z;
    return (lens.xy + d * f) * size;
}

#endif
