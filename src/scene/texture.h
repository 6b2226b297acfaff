// Textures as the scene describes them (pbrt-v4's set): constant, image maps with uv mapping and
// filtering, and the combinations scale, mix and checkerboard. Evaluated at a hit by
// texture/texture_eval.h; a material or shape parameter refers to one by index.
#pragma once

#include "core/math.h"

#include <memory>
#include <string>

namespace rayproc {

struct TextureImage; // texture/texture_image.h: decoded pixels and their MIP pyramid

enum class TextureType { Constant, Image, Scale, Mix, Checkerboard };
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

    // Scale: tex(a) * tex(b). Mix: lerp(amount, tex(a), tex(b)). Checkerboard (2D, uv): tex(a)
    // on even squares, tex(b) on odd, with the (su, sv, du, dv) mapping. Operands are texture
    // indices, or -1 for the constants below.
    int a = -1, b = -1, amountTexture = -1;
    Vec3 aValue{1.0f, 1.0f, 1.0f}, bValue{0.0f, 0.0f, 0.0f};
    float amount = 0.5f;
};

} // namespace rayproc
