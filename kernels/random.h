// Counter-based random numbers: every value is a pure function of (key, dimension), so a
// sample's randomness never depends on which thread traced it or in which order.
#pragma once

#include <cstdint>

namespace rayproc::kernels {

// SplitMix64's finaliser: a bijective 64-bit mix with full avalanche.
inline std::uint64_t mix64(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

inline std::uint64_t hashCombine(std::uint64_t a, std::uint64_t b) {
    return mix64(a ^ (b + 0x9e3779b97f4a7c15ULL + (a << 6) + (a >> 2)));
}

// The key of one camera sample's path.
inline std::uint64_t pathKey(std::uint64_t seed, std::uint32_t pixel, std::uint32_t sample) {
    return hashCombine(hashCombine(mix64(seed), pixel), sample);
}

// A uniform float in [0, 1) for dimension `dim` of the stream `key`.
inline float uniform(std::uint64_t key, std::uint32_t dim) {
    std::uint64_t h = hashCombine(key, dim);
    return float(h >> 40) * (1.0f / 16777216.0f); // 24 bits: exactly representable
}

// A permutation of [0, n) chosen by `key` (bijective hashing with cycle walking, after
// Kensler's "Correlated Multi-Jittered Sampling").
inline std::uint32_t permute(std::uint32_t i, std::uint32_t n, std::uint64_t key) {
    if (n <= 1) return 0;
    std::uint32_t mask = n - 1;
    mask |= mask >> 1; mask |= mask >> 2; mask |= mask >> 4; mask |= mask >> 8; mask |= mask >> 16;
    std::uint32_t p = std::uint32_t(key) | 1u;
    std::uint32_t q = std::uint32_t(key >> 32);
    do {
        // Each step is a bijection on [0, mask]: xor with constants, odd multiplies, shifts.
        i ^= q; i *= 0xe170893du; i ^= q >> 16;
        i ^= (i & mask) >> 4; i ^= q >> 8; i *= 0x0929eb3fu; i ^= q >> 23;
        i ^= (i & mask) >> 1; i *= 1u | q >> 27; i *= 0x6935fa69u;
        i ^= (i & mask) >> 11; i *= 0x74dcb303u; i ^= (i & mask) >> 2;
        i *= 0x9e501cc3u; i ^= (i & mask) >> 2; i *= 0xc860a3dfu;
        i &= mask; i ^= i >> 5;
        i = (i + p) & mask;
    } while (i >= n);
    return i;
}

} // namespace rayproc::kernels
