#pragma once
// Random draws for the study library that give the same numbers on every standard library: the
// engine (std::mt19937_64) is fully specified by the standard, the distributions are not, so the
// study draws its uniforms, indices and shuffles here. A run is a pure function of its seed.
#include <cstddef>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace gt::study {

// A uniform double in [0, 1) from the engine's top 53 bits.
inline double uniform01(std::mt19937_64& random) {
    return static_cast<double>(random() >> 11) * 0x1.0p-53;
}

// A uniform index in [0, n) (n > 0), by rejection so every index is equally likely.
inline std::size_t uniformIndex(std::mt19937_64& random, std::size_t n) {
    const uint64_t count = n;
    const uint64_t limit = UINT64_MAX - UINT64_MAX % count;
    uint64_t draw = random();
    while (draw >= limit)
        draw = random();
    return static_cast<std::size_t>(draw % count);
}

// Fisher-Yates with uniformIndex.
template <typename T> void shuffleInPlace(std::vector<T>& values, std::mt19937_64& random) {
    for (std::size_t i = values.size(); i > 1; --i) {
        std::swap(values[i - 1], values[uniformIndex(random, i)]);
    }
}

// Decorrelates seeds derived from one another (splitmix64's finaliser), so seed, seed + 1, ...
// start unrelated streams.
inline uint64_t mixSeed(uint64_t seed, uint64_t salt) {
    uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (salt + 1);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

} // namespace gt::study
