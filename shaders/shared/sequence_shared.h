// Low-discrepancy sample sequences for the path integrator (path.glsl), compiled both as GLSL
// and as C++ (gt::shaders::sequence) so that tests check the very code the shaders run.
//
// Each random decision of a path draws a 2-D point of the Sobol' sequence (dimensions 0 and 1,
// Sobol' 1967), Owen-scrambled and shuffled by hashing (Burley 2020, "Practical Hash-based Owen
// Scrambling", JCGT 9(4)): the index is shuffled by a nested uniform scramble seeded per pixel
// (or point) and per decision, and each coordinate is scrambled with a seed of its own. The
// index runs over frames and rays (frame * rays + ray), so the first 2^m samples a pixel pools
// over frames are a (0, m, 2)-net: stratified in every elementary interval, in any decision of
// the path. Different decisions are decorrelated by their different shuffles (Burley's
// "padding"). Owen scrambling keeps each point uniform on [0, 1)^2, so estimates stay unbiased.
#ifndef SEQUENCE_SHARED_H
#define SEQUENCE_SHARED_H
#include "gt_shared.h"

GT_NAMESPACE_BEGIN(sequence)

#ifdef __cplusplus
#define GT_FN inline
// GLSL's built-in.
inline uint bitfieldReverse(uint v) {
    v = ((v >> 1u) & 0x55555555u) | ((v & 0x55555555u) << 1u);
    v = ((v >> 2u) & 0x33333333u) | ((v & 0x33333333u) << 2u);
    v = ((v >> 4u) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4u);
    v = ((v >> 8u) & 0x00FF00FFu) | ((v & 0x00FF00FFu) << 8u);
    return (v >> 16u) | (v << 16u);
}
#else
#define GT_FN
#endif

// Sobol' dimension 1 (x + 1, the primitive polynomial of degree 1): direction numbers
// v_1 = 2^31, v_k = v_(k-1) xor (v_(k-1) >> 1). Dimension 0 is the bit-reversed index.
GT_FN uint sobolDimension1(uint index) {
    uint result = 0u;
    uint v = 0x80000000u;
    for (uint i = index; i != 0u; i >>= 1u) {
        if ((i & 1u) != 0u) result ^= v;
        v ^= v >> 1u;
    }
    return result;
}

// Laine & Karras 2011's permutation of the bits above each bit, with Burley 2020's constants:
// an Owen scramble of the bit-reversed value.
GT_FN uint laineKarrasPermutation(uint x, uint seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// A nested uniform (Owen) scramble of a 32-bit fixed-point value in [0, 1).
GT_FN uint nestedUniformScramble(uint x, uint seed) {
    return bitfieldReverse(laineKarrasPermutation(bitfieldReverse(x), seed));
}

GT_FN uint hashCombine(uint seed, uint v) {
    return seed ^ (v + (seed << 6u) + (seed >> 2u));
}

// Burley 2020's seed hash (a variant of Wellons' "lowbias32").
GT_FN uint sequenceHash(uint x) {
    x ^= x >> 16u;
    x *= 0x21f0aaadu;
    x ^= x >> 15u;
    x *= 0x735a2d97u;
    x ^= x >> 15u;
    return x;
}

// The top 24 bits of a fixed-point value as a float in [0, 1).
GT_FN float unitFloat(uint x) {
    return float(x >> 8u) * 5.9604644775390625e-8f;
}

// Point `index` of the shuffled, scrambled 2-D Sobol' sequence with `seed`.
GT_FN vec2 sobolOwen2(uint index, uint seed) {
    const uint i = nestedUniformScramble(index, seed);
    const uint x = nestedUniformScramble(bitfieldReverse(i), hashCombine(seed, 0x9e3779b9u));
    const uint y = nestedUniformScramble(sobolDimension1(i), hashCombine(seed, 0x7f4a7c15u));
    return vec2(unitFloat(x), unitFloat(y));
}

GT_NAMESPACE_END
#endif
