#include "texture/noise.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace rayproc {

namespace {

// Ken Perlin's permutation of 0..255 ("Improving Noise", SIGGRAPH 2002), which pbrt-v4's
// noise uses; indexed twice its length so sums of two indices need no wrap.
constexpr std::array<unsigned char, 256> kPerm = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,
    103, 30,  69,  142, 8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,
    0,   26,  197, 62,  94,  252, 219, 203, 117, 35,  11,  32,  57,  177, 33,  88,  237, 149,
    56,  87,  174, 20,  125, 136, 171, 168, 68,  175, 74,  165, 71,  134, 139, 48,  27,  166,
    77,  146, 158, 231, 83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,  55,  46,
    245, 40,  244, 102, 143, 54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187,
    208, 89,  18,  169, 200, 196, 135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186,
    3,   64,  52,  217, 226, 250, 124, 123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212,
    207, 206, 59,  227, 47,  16,  58,  17,  182, 189, 28,  42,  223, 183, 170, 213, 119, 248,
    152, 2,   44,  154, 163, 70,  221, 153, 101, 155, 167, 43,  172, 9,   129, 22,  39,  253,
    19,  98,  108, 110, 79,  113, 224, 232, 178, 185, 112, 104, 218, 246, 97,  228, 251, 34,
    242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,  51,  145, 235, 249, 14,  239, 107,
    49,  192, 214, 31,  181, 199, 106, 157, 184, 84,  204, 176, 115, 121, 50,  45,  127, 4,
    150, 254, 138, 236, 205, 93,  222, 114, 67,  29,  24,  72,  243, 141, 128, 195, 78,  66,
    215, 61,  156, 180};

int perm(int i) {
    return kPerm[std::size_t(i & 255)];
}

// The gradient of lattice corner (x, y, z) dotted with the offset (dx, dy, dz) from it: one of
// twelve edge directions (four repeated), chosen by the corner's hash.
float gradient(int x, int y, int z, float dx, float dy, float dz) {
    const int h = perm(perm(perm(x) + y) + z) & 15;
    const float u = h < 8 || h == 12 || h == 13 ? dx : dy;
    const float v = h < 4 || h == 12 || h == 13 ? dy : dz;
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

// 6 t^5 - 15 t^4 + 10 t^3: weights with zero first and second derivatives at 0 and 1.
float fade(float t) {
    const float t3 = t * t * t;
    return 6 * t3 * t * t - 15 * t3 * t + 10 * t3;
}

float lerp(float t, float a, float b) {
    return (1 - t) * a + t * b;
}

} // namespace

float solidNoise(float x, float y, float z) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return 0; // no cell
    x = std::fmod(x, float(1 << 30));
    y = std::fmod(y, float(1 << 30));
    z = std::fmod(z, float(1 << 30));
    const float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
    const float dx = x - fx, dy = y - fy, dz = z - fz;
    const int ix = int(fx) & 255, iy = int(fy) & 255, iz = int(fz) & 255;
    const float w000 = gradient(ix, iy, iz, dx, dy, dz);
    const float w100 = gradient(ix + 1, iy, iz, dx - 1, dy, dz);
    const float w010 = gradient(ix, iy + 1, iz, dx, dy - 1, dz);
    const float w110 = gradient(ix + 1, iy + 1, iz, dx - 1, dy - 1, dz);
    const float w001 = gradient(ix, iy, iz + 1, dx, dy, dz - 1);
    const float w101 = gradient(ix + 1, iy, iz + 1, dx - 1, dy, dz - 1);
    const float w011 = gradient(ix, iy + 1, iz + 1, dx, dy - 1, dz - 1);
    const float w111 = gradient(ix + 1, iy + 1, iz + 1, dx - 1, dy - 1, dz - 1);
    const float wx = fade(dx), wy = fade(dy), wz = fade(dz);
    const float y0 = lerp(wy, lerp(wx, w000, w100), lerp(wx, w010, w110));
    const float y1 = lerp(wy, lerp(wx, w001, w101), lerp(wx, w011, w111));
    return lerp(wz, y0, y1);
}

float fbmNoise(const Vec3& p, float omega, int octaves) {
    float sum = 0, lambda = 1, o = 1;
    for (int i = 0; i < octaves; ++i) {
        sum += o * solidNoise(p * lambda);
        lambda *= 1.99f;
        o *= omega;
    }
    return sum; // the partial octave's weight is smoothstep(0, 0.3, 0.7) = 0
}

float turbulenceNoise(const Vec3& p, float omega, int octaves) {
    float sum = 0, lambda = 1, o = 1;
    for (int i = 0; i < octaves; ++i) {
        sum += o * std::abs(solidNoise(p * lambda));
        lambda *= 1.99f;
        o *= omega;
    }
    return sum + o * 0.2f; // the partial octave: lerp(smoothstep(0, 0.3, 0.7), 0.2, |noise|)
}

float windyNoise(const Vec3& p) {
    const float strength = fbmNoise(p * 0.1f, 0.5f, 3);
    return std::abs(strength) * fbmNoise(p, 0.5f, 6);
}

Vec3 marbleColour(const Vec3& p, float scale, float variation, float omega, int octaves) {
    const Vec3 q = p * scale;
    const float marble = q.y + variation * fbmNoise(q, omega, octaves);
    float t = 0.5f + 0.5f * std::sin(marble);
    static const Vec3 c[] = {{.58f, .58f, .6f}, {.58f, .58f, .6f}, {.58f, .58f, .6f},
                             {.5f, .5f, .5f},   {.6f, .59f, .58f}, {.58f, .58f, .6f},
                             {.58f, .58f, .6f}, {.2f, .2f, .33f},  {.58f, .58f, .6f}};
    constexpr int kSegments = int(std::size(c)) - 3;
    const int first = std::min(int(std::floor(t * float(kSegments))), kSegments - 1);
    t = t * float(kSegments) - float(first);
    // The cubic Bezier of c[first .. first + 3] at t, by de Casteljau's construction.
    const Vec3* k = c + first;
    auto mix = [](const Vec3& a, const Vec3& b, float s) { return a * (1 - s) + b * s; };
    const Vec3 a = mix(k[0], k[1], t), b = mix(k[1], k[2], t), d = mix(k[2], k[3], t);
    return mix(mix(a, b, t), mix(b, d, t), t) * 1.5f;
}

bool insidePolkaDot(float s, float t) {
    const float sCell = std::floor(s + 0.5f), tCell = std::floor(t + 0.5f);
    if (!(solidNoise(sCell + 0.5f, tCell + 0.5f, 0.5f) > 0)) return false;
    constexpr float kRadius = 0.35f, kMaxShift = 0.5f - kRadius;
    const float sCenter = sCell + kMaxShift * solidNoise(sCell + 1.5f, tCell + 2.8f, 0.5f);
    const float tCenter = tCell + kMaxShift * solidNoise(sCell + 4.5f, tCell + 9.8f, 0.5f);
    const float ds = s - sCenter, dt = t - tCenter;
    return ds * ds + dt * dt < kRadius * kRadius;
}

} // namespace rayproc
