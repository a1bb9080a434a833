// PCG hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering"); the CPU twin is
// gt::trace::pcgHash in engine/trace/cpu_tracer.cpp.
#ifndef RANDOM_GLSL
#define RANDOM_GLSL

uint pcgHash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

float hashToFloat(uint h) { return float(h >> 8) * (1.0 / 16777216.0); }

// Jittered position of ray `s` of `count` in a pixel: a sx x sy grid of strata.
vec2 sampleOffset(uint pixelIndex, uint s, uint count, uint frameSeed) {
    uint sx = 1u;
    while (sx * sx < count) sx++;
    uint sy = (count + sx - 1u) / sx;
    uint h = pcgHash(pixelIndex ^ pcgHash(s + frameSeed * 0x9E3779B9u));
    float r1 = hashToFloat(h);
    h = pcgHash(h);
    float r2 = hashToFloat(h);
    return vec2((float(s % sx) + r1) / float(sx), (float(s / sx) + r2) / float(sy));
}
#endif
