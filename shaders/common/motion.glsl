// The motion every traced sample carries in a scene that moves (specialisation constant 1
// kDynamic, GpuScene::dynamic()): trace.glsl's traceRadiance leaves the camera ray's first hit's
// motion in gMotion (xyz: its world position one frame ago minus now; w: its signature's bits).
// Include after trace.glsl.
#ifndef MOTION_GLSL
#define MOTION_GLSL

// The signature (surface id in bits 0-23: 0 sky, 1 static geometry, 2 + instance; the shadow
// mask of the first 8 lights in bits 24-31) as the passes store it, in the w of an rgba32f
// texel: an integer-valued float, 16 bits of the surface id above the 8 of the shadow mask,
// exact below 2^24. Its bit pattern as a float would be a denormal for a surface no light
// reaches, which a device may flush to zero and so confuse with the sky; only equality is ever
// asked of it (taa.glsl), so instances 2^16 apart sharing a code costs at most a kept history.
float signatureCode(uint signature) {
    return float(((signature & 0xffffu) << 8u) | (signature >> 24u));
}

// The first hit's motion as a pass stores it: xyz world motion, w = signatureCode.
vec4 storedMotion() { return vec4(gMotion.xyz, signatureCode(floatBitsToUint(gMotion.w))); }
#endif
