// Evaluating a scene texture at a hit: its mapping, image lookups (filtered, wrapped), bilerp,
// and the scale, mix, direction mix and checkerboard combinations, recursively. Pure functions
// of the scene's texture table.
#pragma once

#include "core/math.h"
#include "scene/scene.h"

namespace rayproc {

// Where a texture is looked up.
struct TextureContext {
    Vec2 uv;              // the surface's (u, v)
    Vec3 p;               // world-space point
    Vec3 n{0, 0, 1};      // the surface's geometric normal (a direction mix's; either side)
    float footprint = 0;  // approximate width of the pixel's footprint in uv units (0: finest)
};

// The colour of Scene::textures[index] (a float texture gives its value in all three channels).
Vec3 evalTexture(const Scene& scene, int index, const TextureContext& ctx);

// How the spectral mode reads a texture's leaves at a path's wavelengths (engine/
// material_bsdf.cpp): a colour through its colour space's upsampling, a constant operand's
// own spectrum at the wavelengths' nearest nanometres. Which spectrum (a reflectance's or an
// unbounded value's) is the reader's choice.
class LaneReader {
public:
    virtual ~LaneReader() = default;
    virtual Vec3 rgb(const Vec3& colour) const = 0;
    virtual Vec3 spectrum(const OperandSpectrum& s) const = 0;
};

// Scene::textures[index] at a path's three wavelengths. A texture with spectra
// (Texture::spectral) combines its operands there, each leaf (an image's texel, a constant)
// read by `lanes`, as pbrt-v4's spectrum textures evaluate theirs; any other is its colour
// read by `lanes` (the same as lanes.rgb(evalTexture(...))).
Vec3 evalTextureLanes(const Scene& scene, int index, const TextureContext& ctx,
                      const LaneReader& lanes);
// The scalar of a float texture (a colour texture gives its first channel).
float evalFloatTexture(const Scene& scene, int index, const TextureContext& ctx);

inline Vec3 evalColor(const Scene& scene, const ColorParam& p, const TextureContext& ctx) {
    return p.textured() ? evalTexture(scene, p.texture, ctx) : p.value;
}
inline float evalFloat(const Scene& scene, const FloatParam& p, const TextureContext& ctx) {
    return p.textured() ? evalFloatTexture(scene, p.texture, ctx) : p.value;
}

} // namespace rayproc
