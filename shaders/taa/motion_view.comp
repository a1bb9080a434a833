#version 460
// Debug view `motion` (--view motion): each pixel's screen-space motion since the last frame,
// in pixels, as colour — its direction as the hue, its length as the brightness (full at
// kFullPx and beyond); dark grey where nothing moved. Camera and scene motion together: the
// pixel's first hit p and where it was one frame ago, p + motion, each through its frame's
// camera, as TAA reprojects it (taa.glsl).
#extension GL_GOOGLE_include_directive : require
#include "taa_shared.h"

layout(local_size_x = kGroupX, local_size_y = kGroupY) in;
layout(set = 0, binding = kBindingCurrent, rgba32f) uniform readonly image2D uCurrent;
layout(set = 0, binding = kBindingOutput, rgba32f) uniform writeonly image2D uOutput;
layout(set = 0, binding = kBindingMotion, rgba32f) uniform readonly image2D uMotion;
// TaaPush's cameras; params.x = 1: uMotion holds the scene's motion (else only the camera's).
layout(push_constant) uniform Push { TaaPush pc; };

const float kFullPx = 16.0;

vec3 hue(float h) {
    return clamp(abs(fract(h + vec3(0.0, 2.0 / 3.0, 1.0 / 3.0)) * 6.0 - 3.0) - 1.0, 0.0, 1.0);
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(uOutput);
    if (any(greaterThanEqual(px, size))) return;
    vec4 current = imageLoad(uCurrent, px);
    vec2 s = (vec2(px) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec3 up = cross(pc.currentRight.xyz, pc.currentForward.xyz);
    vec3 dir = normalize(pc.currentForward.xyz
                         + (s.x * pc.currentOrigin.w * pc.currentForward.w + pc.centres.x) * pc.currentRight.xyz
                         + (pc.centres.y - s.y * pc.currentOrigin.w) * up);
    bool sky = !(current.a < 1e30);
    vec3 d = sky ? dir : pc.currentOrigin.xyz + current.a * dir - pc.previousOrigin.xyz;
    if (!sky && pc.params.x > 0.5) d += imageLoad(uMotion, px).xyz;
    vec3 prevUp = cross(pc.previousRight.xyz, pc.previousForward.xyz);
    float z = dot(d, pc.previousForward.xyz);
    vec3 colour = vec3(0.5, 0.0, 0.5); // behind the previous camera
    if (z > 1e-6) {
        vec2 ps = vec2(dot(d, pc.previousRight.xyz), dot(d, prevUp)) / z;
        ps = (ps - pc.centres.zw) / vec2(pc.previousOrigin.w * pc.previousForward.w, pc.previousOrigin.w);
        vec2 prevPixel = vec2((ps.x + 1.0) * 0.5, (1.0 - ps.y) * 0.5) * vec2(size);
        vec2 v = vec2(px) + 0.5 - prevPixel;
        float pixels = length(v);
        float h = pixels > 0.0 ? atan(v.y, v.x) / 6.28318531 + 0.5 : 0.0;
        colour = mix(vec3(0.02), hue(h), clamp(pixels / kFullPx, 0.0, 1.0));
    }
    imageStore(uOutput, px, vec4(colour * 2.0, current.a)); // * 2: before the tone mapper
}
