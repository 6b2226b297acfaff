// Compact encodings of a stored photon's payload (Jensen 2001, ch. 6.1): power as Ward's
// shared-exponent RGBE (4 bytes), unit vectors as octahedral maps (Cigolle et al. 2014, "A
// Survey of Efficient Representations for Independent Unit Vectors") quantised to 2 x Bits bits.
//
// Precision (tests/gi/photon_map_test.cpp checks these bounds):
// - RGBE: every channel is rounded to a multiple of 2^(e-8), where 2^(e-1) <= max channel < 2^e,
//   so |decoded - c| <= maxComponent(c) / 255 per channel (half a step; 1/255 rather than 1/256
//   covers the largest channel rounding up into the next exponent). Negative and NaN channels,
//   and colours whose largest channel is below kRgbeSmallest, decode as 0; colours above
//   kRgbeLargest are scaled down to it (hue kept).
// - Octahedral, 8 + 8 bits (direction): at most kDirectionErrorDegrees from the input.
// - Octahedral, 7 + 7 bits (normal): at most kNormalErrorDegrees from the input.
// Both grids have an odd number of levels per axis, so the six axis directions (walls, floors)
// are represented exactly.
#pragma once

#include "core/math.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

namespace rayproc {

// RGBE ------------------------------------------------------------------------------------------

struct Rgbe {
    std::uint8_t r = 0, g = 0, b = 0, e = 0; // mantissas, exponent + 128 (Ward's; 0: black)
};

// The range of the largest channel: below kRgbeSmallest a colour is stored as black (so the
// exponent byte stays >= 1, Ward's "e == 0 is black"); kRgbeLargest = 255 * 2^119 is mantissa
// 255 with the largest exponent byte.
constexpr float kRgbeSmallest = 1.0e-37f;
constexpr float kRgbeLargest = 255.0f * 0x1p119f;
// Bound on |decoded - input| per channel, relative to the largest channel.
constexpr float kRgbeRelativeError = 1.0f / 255.0f;

namespace detail {
// 2^(i - 136) = 2^(e - 8), e = i - 128: the value of mantissa 1 with exponent byte i. Exact in
// float (2^-136 is a denormal, still exact).
constexpr std::array<float, 256> kRgbeScale = [] {
    std::array<float, 256> t{};
    double v = 1.0;
    for (int i = 0; i < 136; ++i) v *= 0.5;
    for (int i = 0; i < 256; ++i, v *= 2.0) t[i] = float(v);
    return t;
}();
} // namespace detail

inline Rgbe encodeRgbe(const Vec3& c) {
    // Flux is non-negative; anything else (negative, NaN) is stored as 0.
    float r = c.x > 0 ? c.x : 0.0f, g = c.y > 0 ? c.y : 0.0f, b = c.z > 0 ? c.z : 0.0f;
    float m = std::max(r, std::max(g, b));
    if (!(m >= kRgbeSmallest)) return {};
    if (m > kRgbeLargest) { // saturate, keeping the hue
        float s = kRgbeLargest / m;
        r *= s, g *= s, b *= s, m = kRgbeLargest;
    }
    // m = f 2^e with f in [0.5, 1) (m is a normal float: read e from its bits); mantissas are
    // channel * 2^(8-e), the largest in [128, 256], rounded to nearest. The scale 2^(8-e) can
    // exceed the float range for tiny colours, so it is a double.
    int e = int((std::bit_cast<std::uint32_t>(m) >> 23) & 0xffu) - 126;
    double scale = std::bit_cast<double>(std::uint64_t(1023 + 8 - e) << 52);
    if (double(m) * scale + 0.5 >= 256.0) { // the largest rounds up to 256: one exponent more
        ++e;
        scale *= 0.5;
    }
    auto mantissa = [scale](float c) { return std::uint8_t(double(c) * scale + 0.5); };
    return {mantissa(r), mantissa(g), mantissa(b), std::uint8_t(e + 128)};
}

inline Vec3 decodeRgbe(const Rgbe& c) {
    float s = detail::kRgbeScale[c.e];
    return {float(c.r) * s, float(c.g) * s, float(c.b) * s};
}

// Octahedral unit vectors -------------------------------------------------------------------------

// Bounds on the angle between a unit vector and its decoded code: the worst cases measured on a
// dense (theta, phi) grid of 18M directions were 0.638 and 1.282 degrees; the tests check 1M
// random directions and the octahedron's edges against these.
constexpr float kDirectionErrorDegrees = 0.66f; // 8 + 8 bits
constexpr float kNormalErrorDegrees = 1.32f;    // 7 + 7 bits

namespace detail {

inline float signNotZero(float v) {
    return v < 0 ? -1.0f : 1.0f;
}

// Unit vector -> point (u, v) of the square [-1,1]^2: project onto the octahedron |x|+|y|+|z| = 1
// and fold the lower half over the diagonals.
inline void octahedralWrap(const Vec3& d, float& u, float& v) {
    float l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
    u = d.x / l1;
    v = d.y / l1;
    if (d.z < 0) {
        float fu = (1.0f - std::abs(v)) * signNotZero(u);
        float fv = (1.0f - std::abs(u)) * signNotZero(v);
        u = fu, v = fv;
    }
}

// The point of the octahedron |x|+|y|+|z| = 1 that (u, v) maps to.
inline Vec3 octahedralUnwrap(float u, float v) {
    float z = 1.0f - std::abs(u) - std::abs(v);
    if (z < 0) {
        float fu = (1.0f - std::abs(v)) * signNotZero(u);
        float fv = (1.0f - std::abs(u)) * signNotZero(v);
        u = fu, v = fv;
    }
    return Vec3(u, v, z);
}

} // namespace detail

// Decodes Bits + Bits bits (u in the low Bits, v above; 2 S + 1 levels per axis,
// S = 2^(Bits-1) - 1) to the point on the octahedron: the direction, not normalised. Enough
// for sign tests, and for angle tests as dot(raw, n)^2 against cos^2 |raw|^2.
template <int Bits>
inline Vec3 decodeOctahedralRaw(std::uint32_t code) {
    constexpr int kS = (1 << (Bits - 1)) - 1;
    constexpr std::uint32_t kMask = (1u << Bits) - 1;
    constexpr float kInvS = 1.0f / float(kS);
    float u = float(int(code & kMask) - kS) * kInvS;
    float v = float(int((code >> Bits) & kMask) - kS) * kInvS;
    return detail::octahedralUnwrap(u, v);
}

template <int Bits>
inline Vec3 decodeOctahedral(std::uint32_t code) {
    return normalize(decodeOctahedralRaw<Bits>(code));
}

// Encodes a direction (normalised first; the zero vector becomes +z) to the grid point, among the
// four around it, whose decoded vector is closest in angle ("precise" octahedral encoding).
template <int Bits>
inline std::uint32_t encodeOctahedral(const Vec3& direction) {
    constexpr int kS = (1 << (Bits - 1)) - 1;
    Vec3 d = normalize(direction);
    if (!(dot(d, d) > 0.5f)) d = Vec3(0, 0, 1);
    float u, v;
    detail::octahedralWrap(d, u, v);
    int iu = int(std::floor(u * float(kS))), iv = int(std::floor(v * float(kS)));
    std::uint32_t best = 0;
    float bestScore = -2.0f;
    for (int du = 0; du < 2; ++du) {
        for (int dv = 0; dv < 2; ++dv) {
            int qu = std::clamp(iu + du, -kS, kS) + kS, qv = std::clamp(iv + dv, -kS, kS) + kS;
            std::uint32_t code = std::uint32_t(qu) | (std::uint32_t(qv) << Bits);
            // cos |cos| of the angle to d, which orders like the cosine, without a square root.
            Vec3 c = decodeOctahedralRaw<Bits>(code);
            float cd = dot(c, d), score = cd * std::abs(cd) / dot(c, c);
            if (score > bestScore) bestScore = score, best = code;
        }
    }
    return best;
}

// The two encodings a stored photon uses.
inline std::uint16_t encodeDirection(const Vec3& d) {
    return std::uint16_t(encodeOctahedral<8>(d));
}
inline Vec3 decodeDirection(std::uint16_t code) {
    return decodeOctahedral<8>(code);
}
inline std::uint16_t encodeNormal(const Vec3& n) {
    return std::uint16_t(encodeOctahedral<7>(n));
}
inline Vec3 decodeNormal(std::uint16_t code) {
    return decodeOctahedral<7>(code & 0x3fffu);
}
inline Vec3 decodeDirectionRaw(std::uint16_t code) {
    return decodeOctahedralRaw<8>(code);
}
inline Vec3 decodeNormalRaw(std::uint16_t code) {
    return decodeOctahedralRaw<7>(code & 0x3fffu);
}

// dot(v / |v|, n) > cosine for a unit n and a non-zero v, without normalising v (cosine >= 0).
inline bool withinCone(const Vec3& v, const Vec3& n, float cosine) {
    float c = dot(v, n);
    return c > 0 && c * c > cosine * cosine * dot(v, v);
}

} // namespace rayproc
