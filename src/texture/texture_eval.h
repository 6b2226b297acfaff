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
// The scalar of a float texture (a colour texture gives its first channel).
float evalFloatTexture(const Scene& scene, int index, const TextureContext& ctx);

inline Vec3 evalColor(const Scene& scene, const ColorParam& p, const TextureContext& ctx) {
    return p.textured() ? evalTexture(scene, p.texture, ctx) : p.value;
}
inline float evalFloat(const Scene& scene, const FloatParam& p, const TextureContext& ctx) {
    return p.textured() ? evalFloatTexture(scene, p.texture, ctx) : p.value;
}

} // namespace rayproc
