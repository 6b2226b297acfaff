// Owen-scrambled Sobol points, one independent 2D (0,2)-sequence per pair of dimensions
// ("padded", as pbrt-v4's PaddedSobolSampler): sample i of a pixel takes point
// shuffle(i) of its pair's sequence. Scrambling and shuffling are nested uniform (Owen)
// permutations computed by hashing (Burley, "Practical Hash-based Owen Scrambling", JCGT 2020),
// so every value is a pure function of (index, key): deterministic whatever thread or rank
// traces the sample. For every power of two N, any N consecutive aligned indices give a (0,2)-net
// in base 2: each of the N elementary intervals of area 1/N (1 x N, 2 x N/2, ..., N x 1) holds
// exactly one point, so the first N samples of a pixel are stratified at every prefix.
#pragma once

#include "kernels/random.h"
#include "core/math.h"

#include <immintrin.h>

#include <cstdint>

namespace rayproc::kernels {

inline std::uint32_t reverseBits(std::uint32_t v) {
    v = __builtin_bswap32(v);
    v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    return ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
}
// Two 32-bit reversals for the price of one: reversing the 64 bits of (hi << 32 | lo) reverses
// each half and swaps them, so the result is reverseBits(lo) << 32 | reverseBits(hi).
inline std::uint64_t reverseBits64(std::uint64_t v) {
    v = __builtin_bswap64(v);
    v = ((v >> 4) & 0x0f0f0f0f0f0f0f0fULL) | ((v & 0x0f0f0f0f0f0f0f0fULL) << 4);
    v = ((v >> 2) & 0x3333333333333333ULL) | ((v & 0x3333333333333333ULL) << 2);
    return ((v >> 1) & 0x5555555555555555ULL) | ((v & 0x5555555555555555ULL) << 1);
}

// The second Sobol dimension (the first is the bit reversal of i): y = xor over the set bits k
// of i of the direction number v_k, v_0 = 2^31 and v_(k+1) = v_k ^ (v_k >> 1) (the binary
// Pascal matrix). Bit-reversed here, by byte: table b holds the xor for byte b of i.
struct SobolSecondTables {
    std::uint32_t byByte[4][256];
    constexpr SobolSecondTables() : byByte{} {
        std::uint32_t v[32] = {};
        v[0] = 0x80000000u;
        for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
        for (int b = 0; b < 4; ++b)
            for (std::uint32_t byte = 0; byte < 256; ++byte) {
                std::uint32_t y = 0;
                for (int k = 0; k < 8; ++k)
                    if (byte & (1u << k)) y ^= v[8 * b + k];
                // reversed
                std::uint32_t r = 0;
                for (int k = 0; k < 32; ++k)
                    if (y & (1u << k)) r |= 1u << (31 - k);
                byByte[b][byte] = r;
            }
    }
};
inline constexpr SobolSecondTables kSobolSecond{};
inline std::uint32_t sobolSecondReversed(std::uint32_t i) {
    const auto& t = kSobolSecond.byByte;
    return t[0][i & 0xffu] ^ t[1][(i >> 8) & 0xffu] ^ t[2][(i >> 16) & 0xffu] ^ t[3][i >> 24];
}
inline std::uint32_t sobolSecond(std::uint32_t i) { return reverseBits(sobolSecondReversed(i)); }

// Laine and Karras's permutation on bit-reversed values: each bit flipped by a hash of the
// bits below it and the seed. A multiply by an even constant carries each bit only towards the
// more significant ones.
inline std::uint32_t laineKarras(std::uint32_t x, std::uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// A nested uniform scramble of the 32-bit fixed-point value x: each bit is flipped by a hash of
// the seed and the bits above it (the more significant digits).
inline std::uint32_t owenScramble(std::uint32_t x, std::uint32_t seed) {
    return reverseBits(laineKarras(reverseBits(x), seed));
}

inline float fixedToUnit(std::uint32_t x) {
    return float(x >> 8) * (1.0f / 16777216.0f); // 24 bits: exactly representable, below 1
}

// Three seeds from one key: the shuffle of the indices and the scrambles of x and y.
struct SobolSeeds {
    std::uint32_t shuffle, x, y;
    explicit SobolSeeds(std::uint64_t key) {
        std::uint64_t h = mix64(key);
        shuffle = std::uint32_t(h);
        x = std::uint32_t(h >> 32);
        y = std::uint32_t((h ^ (h >> 29)) * 0xbf58476d1ce4e5b9ULL >> 32);
    }
};

// Sample of the pair of dimensions that `key` names, for the index whose bit reversal is
// `reversedIndex` (reverseBits(index): callers drawing several pairs for one sample reverse it
// once). The shuffle is a nested scramble of the index, so aligned blocks of 2^m indices map to
// aligned blocks: nets stay nets. With r the shuffled index reversed, the first coordinate is
// the scrambled bit reversal of the shuffled index i = reverseBits(r):
// owenScramble(r) = reverseBits(laineKarras(i)); the second reads i's bytes from r's.
inline Vec2 owenSobol2DReversed(std::uint32_t reversedIndex, std::uint64_t key) {
    SobolSeeds s(key);
    std::uint32_t i = reverseBits(laineKarras(reversedIndex, s.shuffle));
    // x's and y's scrambled values reversed together (reverseBits64): x's lands in the low half.
    std::uint64_t xy = reverseBits64(std::uint64_t(laineKarras(i, s.x)) << 32 |
                                     laineKarras(sobolSecondReversed(i), s.y));
    return {fixedToUnit(std::uint32_t(xy)), fixedToUnit(std::uint32_t(xy >> 32))};
}
inline Vec2 owenSobol2D(std::uint32_t index, std::uint64_t key) {
    return owenSobol2DReversed(reverseBits(index), key);
}

// reverseBits and laineKarras on each 32-bit lane (AVX2): the bytes reversed by a shuffle, the
// bits of each byte by two nibble lookups; 32-bit multiplies keep the low half, as uint32_t's.
inline __m256i reverseBits8(__m256i v) {
    const __m256i bswap = _mm256_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12,
                                           3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12);
    const __m256i nibble = _mm256_setr_epi8(0, 8, 4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15,
                                            0, 8, 4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15);
    const __m256i low = _mm256_set1_epi8(0x0f);
    v = _mm256_shuffle_epi8(v, bswap);
    __m256i lo = _mm256_shuffle_epi8(nibble, _mm256_and_si256(v, low));
    __m256i hi = _mm256_shuffle_epi8(nibble, _mm256_and_si256(_mm256_srli_epi16(v, 4), low));
    return _mm256_or_si256(_mm256_slli_epi16(lo, 4), hi);
}
inline __m256i laineKarras8(__m256i x, __m256i seed) {
    x = _mm256_add_epi32(x, seed);
    for (std::uint32_t c : {0x6c50b47cu, 0xb82f1e52u, 0xc7afe638u, 0x8d22f6e6u})
        x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32(int(c))));
    return x;
}

// Three pairs of one sample at once (a path vertex's: keys[k] names pair k): owenSobol2DReversed
// lane by lane, the shuffles in lanes 0-2, the x scrambles in 0-2 and the y ones in 4-6. The
// same integer operations on the same values, so the same numbers.
inline void owenSobol2DReversed3(std::uint32_t reversedIndex, const std::uint64_t (&keys)[3],
                                 Vec2 (&out)[3]) {
    const SobolSeeds s0(keys[0]), s1(keys[1]), s2(keys[2]);
    alignas(32) std::uint32_t i[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(i),
                       reverseBits8(laineKarras8(_mm256_set1_epi32(int(reversedIndex)),
                                                 _mm256_setr_epi32(int(s0.shuffle), int(s1.shuffle),
                                                                   int(s2.shuffle), 0, 0, 0, 0, 0))));
    const __m256i v = _mm256_setr_epi32(int(i[0]), int(i[1]), int(i[2]), 0,
                                        int(sobolSecondReversed(i[0])),
                                        int(sobolSecondReversed(i[1])),
                                        int(sobolSecondReversed(i[2])), 0);
    const __m256i seeds = _mm256_setr_epi32(int(s0.x), int(s1.x), int(s2.x), 0, int(s0.y),
                                            int(s1.y), int(s2.y), 0);
    const __m256i r = _mm256_srli_epi32(reverseBits8(laineKarras8(v, seeds)), 8);
    alignas(32) float f[8];
    _mm256_store_ps(f, _mm256_mul_ps(_mm256_cvtepi32_ps(r), _mm256_set1_ps(1.0f / 16777216.0f)));
    for (int k = 0; k < 3; ++k) out[k] = {f[k], f[4 + k]};
}

} // namespace rayproc::kernels
