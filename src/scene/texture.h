// Textures as the scene describes them (pbrt-v4's set): constant, image maps with filtering,
// bilerp, and the combinations scale, mix, direction mix and checkerboard (2D and 3D), with
// pbrt-v4's mappings (uv, spherical, cylindrical, planar; a point for 3D). Evaluated at a hit by
// texture/texture_eval.h; a material or shape parameter refers to one by index.
#pragma once

#include "core/math.h"

#include <array>
#include <memory>
#include <string>

namespace rayproc {

struct ReflectanceSpectrum; // scene/reflectance_spectrum.h
using ReflectanceSpectrumRef = std::shared_ptr<const ReflectanceSpectrum>;

// A combination's constant operand given as a spectrum (pbrt-v4's wavelength/value pairs, an
// `rgb` under another colour space than sRGB), kept for the spectral mode beside the RGB value
// RGB mode combines. `albedo` is the spectrum a reflectance reads (an `rgb`'s RGBAlbedoSpectrum),
// `unbounded` the one any other parameter reads (RGBUnboundedSpectrum); pairs are the same
// spectrum in both, unclamped (the material clamps what it evaluates, as pbrt-v4's do). Both
// null: the operand is its RGB value. The operand's value beside it is RGB mode's as an
// unbounded value (pairs: their value at 587.6 nm); `albedoColour` is its colour as a
// reflectance, which the importer's reflectance copy of the texture combines instead.
struct OperandSpectrum {
    ReflectanceSpectrumRef albedo, unbounded;
    Vec3 albedoColour{0.0f, 0.0f, 0.0f};
    explicit operator bool() const { return unbounded != nullptr; }
};

struct TextureImage; // texture/texture_image.h: decoded pixels and their MIP pyramid

enum class TextureType {
    Constant, Image, Scale, Mix, Checkerboard, Bilerp, DirectionMix,
    Fbm, Wrinkled, Windy, Marble, Dots // pbrt-v4's noise textures (texture/noise.h)
};
// Where a texture is looked up (pbrt-v4's TextureMapping2D, and its 3D point mapping):
// - Uv: (s, t) = (su u + du, sv v + dv);
// - Spherical: p' = textureFromWorld(p), (s, t) = (theta / pi, phi / 2 pi) of p' from the origin;
// - Cylindrical: (s, t) = ((pi + atan2(p'.y, p'.x)) / 2 pi, p'.z);
// - Planar: (s, t) = (du + p' . planarS, dv + p' . planarT);
// - Point: p' itself (a 3D checkerboard).
enum class TextureMapping { Uv, Spherical, Cylindrical, Planar, Point };
enum class TextureWrap { Repeat, Black, Clamp, Octahedral };
enum class TextureFilter { Point, Bilinear, Trilinear, Ewa };

struct Texture {
    std::string name;
    TextureType type = TextureType::Constant;
    bool isFloat = false; // a "float" texture: one channel (the first / the mean)
    Vec3 value{1.0f, 1.0f, 1.0f}; // Constant

    // Image: (s, t) = (su * u + du, sv * v + dv); t is flipped as pbrt-v4 does (image row 0 is
    // t = 1). Values are image * scale, inverted (1 - x) when `invert`.
    std::shared_ptr<const TextureImage> image; // null: the file was missing (value used)
    std::string filename;
    float su = 1, sv = 1, du = 0, dv = 0;
    TextureWrap wrap = TextureWrap::Repeat;
    TextureFilter filter = TextureFilter::Bilinear;
    float scale = 1.0f;
    bool invert = false;

    // Image, Checkerboard and Bilerp: the mapping above; textureFromWorld is the inverse of the
    // transform at the Texture directive (pbrt-v4's textureFromRender), planarS and planarT
    // planar's "v1" and "v2".
    TextureMapping mapping = TextureMapping::Uv;
    Affine textureFromWorld;
    Vec3 planarS{1.0f, 0.0f, 0.0f}, planarT{0.0f, 1.0f, 0.0f};

    // Scale: tex(a) * tex(b). Mix: lerp(amount, tex(a), tex(b)). Checkerboard: tex(a) on even
    // squares (cubes with the Point mapping), tex(b) on odd. DirectionMix: |n . direction|
    // tex(a) + (1 - |n . direction|) tex(b), n the surface's normal and `direction` the world's
    // of its "dir". Operands are texture indices, or -1 for the constants below.
    int a = -1, b = -1, amountTexture = -1;
    Vec3 aValue{1.0f, 1.0f, 1.0f}, bValue{0.0f, 0.0f, 0.0f};
    float amount = 0.5f;
    Vec3 direction{0.0f, 1.0f, 0.0f};
    // Bilerp: the values at (s, t) = (0, 0), (1, 0), (0, 1), (1, 1), bilinear between them
    // (and beyond, as pbrt-v4 does not wrap them).
    std::array<Vec3, 4> corners{};
    // Fbm, Wrinkled, Windy and Marble: noise of the point in the directive's space (the Point
    // mapping); Fbm, Wrinkled and Marble sum `octaves` octaves weighted by omega^i (pbrt-v4's
    // "roughness"), Marble scales the point by noiseScale and its stripes' noise by
    // `variation`. Dots: the 2D mapping; tex(a) inside a dot, tex(b) outside.
    int octaves = 8;
    float omega = 0.5f, noiseScale = 1.0f, variation = 0.2f;

    // The spectral mode's operands: aSpectrum, bSpectrum and cornerSpectra where the constants
    // above were given as spectra; `spectral` when this texture or an operand texture has any.
    // Such a texture is combined at a path's wavelengths (texture/texture_eval.h,
    // evalTextureLanes), as pbrt-v4's spectrum textures are; RGB mode combines the colours.
    OperandSpectrum aSpectrum, bSpectrum;
    std::array<OperandSpectrum, 4> cornerSpectra{};
    bool spectral = false;
};

} // namespace rayproc
