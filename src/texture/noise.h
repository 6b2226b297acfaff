// pbrt-v4's solid noise (Perlin's gradient noise with pbrt's gradient choice) and the sums of
// its octaves that its fbm, wrinkled, windy and marble textures read, and the polka dots of its
// dots texture. rayproc has no ray differentials, so every octave is summed, as pbrt-v4 does
// where a hit's footprint is zero.
#pragma once

#include "core/math.h"

namespace rayproc {

// Noise in [-1, 1] at p, 0 on the integer lattice; continuous with continuous derivatives.
// Coordinates are taken modulo 2^30 first, as pbrt-v4 does; a point not finite gives 0.
float solidNoise(float x, float y, float z);
inline float solidNoise(const Vec3& p) { return solidNoise(p.x, p.y, p.z); }

// sum over octaves i < octaves of omega^i noise(1.99^i p) (pbrt-v4's FBm without a footprint).
float fbmNoise(const Vec3& p, float omega, int octaves);
// The same of |noise|, plus the clamped octave's 0.2 omega^octaves (pbrt-v4's Turbulence).
float turbulenceNoise(const Vec3& p, float omega, int octaves);

// pbrt-v4's WindyTexture: |fbm(0.1 p, 0.5, 3)| fbm(p, 0.5, 6).
float windyNoise(const Vec3& p);
// pbrt-v4's MarbleTexture's colour: a cubic Bezier spline of nine grey-blue colours at
// 0.5 + 0.5 sin(p'.y + variation fbm(p', omega, octaves)), p' = scale p, times 1.5.
Vec3 marbleColour(const Vec3& p, float scale, float variation, float omega, int octaves);
// pbrt-v4's InsidePolkaDot: whether (s, t) lies in the dot of its unit cell (cells centred
// on the integers; a cell has a dot where noise says so, radius 0.35, shifted by noise).
bool insidePolkaDot(float s, float t);

} // namespace rayproc
