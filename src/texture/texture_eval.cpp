// pbrt-v4's textures: the mappings of scene/texture.h give (s, t); image maps flip t (image row
// 0 is t = 1), look up texel centres at (s w - 1/2, t h - 1/2) with the wrap mode, filter
// bilinearly (trilinearly between MIP levels when a footprint is known) and apply scale and
// invert; checkerboards alternate on the integer lattice of (s, t), or of the point in 3D.
#include "texture/texture_eval.h"

#include "lighting/sphere_mapping.h"
#include "texture/noise.h"
#include "texture/texture_image.h"

#include <algorithm>
#include <cmath>

namespace rayproc {

namespace {

// Maps a texel coordinate into the image, or returns false where the texel is black.
bool wrapTexel(TextureWrap wrap, int w, int h, int& x, int& y) {
    switch (wrap) {
    case TextureWrap::Repeat:
        x = ((x % w) + w) % w;
        y = ((y % h) + h) % h;
        return true;
    case TextureWrap::Clamp:
        x = std::clamp(x, 0, w - 1);
        y = std::clamp(y, 0, h - 1);
        return true;
    case TextureWrap::Black: return x >= 0 && x < w && y >= 0 && y < h;
    case TextureWrap::Octahedral:
        // Across an edge of the equal-area square the sphere continues mirrored (square
        // images only; another shape clamps).
        if (w == h) {
            wrapEqualAreaPixel(x, y, w);
        } else {
            x = std::clamp(x, 0, w - 1);
            y = std::clamp(y, 0, h - 1);
        }
        return true;
    }
    return false;
}

Vec3 texel(const TextureImage::Level& l, TextureWrap wrap, int x, int y) {
    if (!wrapTexel(wrap, l.width, l.height, x, y)) return Vec3(0.0f);
    const float* p = l.at(x, y);
    return {p[0], p[1], p[2]};
}

// A texel coordinate and its right (or lower) neighbour in an image of size n, repeated: the
// same pair wrapTexel gives them, with at most one division (none inside the image).
void repeatPair(int n, int& c0, int& c1) {
    if (unsigned(c0) >= unsigned(n)) c0 = ((c0 % n) + n) % n;
    c1 = c0 + 1 == n ? 0 : c0 + 1;
}

Vec3 bilinear(const TextureImage::Level& l, TextureWrap wrap, float s, float t) {
    float x = s * float(l.width) - 0.5f, y = t * float(l.height) - 0.5f;
    float fx = std::floor(x), fy = std::floor(y);
    int x0 = int(fx), y0 = int(fy);
    float dx = x - fx, dy = y - fy;
    if (wrap == TextureWrap::Repeat || wrap == TextureWrap::Clamp) {
        // The four texels' addresses wrapped once per axis (texel() wraps each of the four on
        // its own, with two divisions per coordinate); the same texels, so the same sum.
        int x1 = x0 + 1, y1 = y0 + 1;
        if (wrap == TextureWrap::Repeat) {
            repeatPair(l.width, x0, x1);
            repeatPair(l.height, y0, y1);
        } else {
            x0 = std::clamp(x0, 0, l.width - 1), x1 = std::clamp(x1, 0, l.width - 1);
            y0 = std::clamp(y0, 0, l.height - 1), y1 = std::clamp(y1, 0, l.height - 1);
        }
        const float *a = l.at(x0, y0), *b = l.at(x1, y0), *c = l.at(x0, y1), *d = l.at(x1, y1);
        return Vec3(a[0], a[1], a[2]) * ((1 - dx) * (1 - dy)) + Vec3(b[0], b[1], b[2]) * (dx * (1 - dy)) +
               Vec3(c[0], c[1], c[2]) * ((1 - dx) * dy) + Vec3(d[0], d[1], d[2]) * (dx * dy);
    }
    return texel(l, wrap, x0, y0) * ((1 - dx) * (1 - dy)) + texel(l, wrap, x0 + 1, y0) * (dx * (1 - dy)) +
           texel(l, wrap, x0, y0 + 1) * ((1 - dx) * dy) + texel(l, wrap, x0 + 1, y0 + 1) * (dx * dy);
}

Vec3 lookupImage(const Texture& t, float s, float tt, float footprint) {
    const TextureImage& img = *t.image;
    tt = 1.0f - tt;
    if (t.filter == TextureFilter::Point) {
        const TextureImage::Level& l = img.levels[0];
        return texel(l, t.wrap, int(std::floor(s * float(l.width))), int(std::floor(tt * float(l.height))));
    }
    // The MIP level whose texels match the footprint (trilinear and EWA; EWA's anisotropic
    // footprint is approximated by its width). Without a footprint: the finest level.
    float width = footprint * float(std::max(img.width(), img.height()));
    if (t.filter == TextureFilter::Bilinear || !(width > 1.0f))
        return bilinear(img.levels[0], t.wrap, s, tt);
    float level = std::min(std::log2(width), float(img.levels.size() - 1));
    int l0 = int(std::floor(level));
    int l1 = std::min(l0 + 1, int(img.levels.size()) - 1);
    float d = level - float(l0);
    return bilinear(img.levels[std::size_t(l0)], t.wrap, s, tt) * (1 - d) +
           bilinear(img.levels[std::size_t(l1)], t.wrap, s, tt) * d;
}

Vec3 operand(const Scene& scene, int index, const Vec3& value, const TextureContext& ctx) {
    return index >= 0 ? evalTexture(scene, index, ctx) : value;
}

// The texture's (s, t) at the hit (its 2D mapping; the Point mapping has none).
Vec2 mapToSt(const Texture& t, const TextureContext& ctx) {
    constexpr float kInv2Pi = 0.5f * kInvPi;
    if (t.mapping == TextureMapping::Uv || t.mapping == TextureMapping::Point)
        return {t.su * ctx.uv.x + t.du, t.sv * ctx.uv.y + t.dv};
    const Vec3 p = t.textureFromWorld.point(ctx.p);
    switch (t.mapping) {
    case TextureMapping::Uv: break;
    case TextureMapping::Spherical: {
        const Vec3 d = normalize(p);
        float phi = std::atan2(d.y, d.x);
        if (phi < 0) phi += 2 * kPi;
        return {std::acos(std::clamp(d.z, -1.0f, 1.0f)) * kInvPi, phi * kInv2Pi};
    }
    case TextureMapping::Cylindrical: return {(kPi + std::atan2(p.y, p.x)) * kInv2Pi, p.z};
    case TextureMapping::Planar: return {t.du + dot(p, t.planarS), t.dv + dot(p, t.planarT)};
    case TextureMapping::Point: break;
    }
    return {t.su * ctx.uv.x + t.du, t.sv * ctx.uv.y + t.dv};
}

// Whether the checkerboard's square (cube) at the hit is an even one.
bool evenCheck(const Texture& t, const TextureContext& ctx, float s, float tt) {
    if (t.mapping != TextureMapping::Point)
        return (long long)(std::floor(s) + std::floor(tt)) % 2 == 0;
    const Vec3 p = t.textureFromWorld.point(ctx.p);
    return (long long)(std::floor(p.x) + std::floor(p.y) + std::floor(p.z)) % 2 == 0;
}

// A noise texture's value at the hit's point in the directive's space (a float one's in all
// three channels; marble, a colour in pbrt-v4, gives a float its channels' mean).
Vec3 solid(const Texture& t, const TextureContext& ctx) {
    const Vec3 p = t.textureFromWorld.point(ctx.p);
    switch (t.type) {
    case TextureType::Fbm: return Vec3(fbmNoise(p, t.omega, t.octaves));
    case TextureType::Wrinkled: return Vec3(turbulenceNoise(p, t.omega, t.octaves));
    case TextureType::Windy: return Vec3(windyNoise(p));
    default: break;
    }
    const Vec3 c = marbleColour(p, t.noiseScale, t.variation, t.omega, t.octaves);
    return t.isFloat ? Vec3((c.x + c.y + c.z) / 3.0f) : c;
}

float mixAmount(const Scene& scene, const Texture& t, const TextureContext& ctx) {
    return t.amountTexture >= 0 ? evalFloatTexture(scene, t.amountTexture, ctx) : t.amount;
}

Vec3 evaluate(const Scene& scene, const Texture& t, const TextureContext& ctx) {
    const Vec2 st = mapToSt(t, ctx);
    const float s = st.x, tt = st.y;
    switch (t.type) {
    case TextureType::Constant: return t.value;
    case TextureType::Image: {
        if (!t.image) return t.value; // the file was missing: the loader said so
        Vec3 v = lookupImage(t, s, tt, ctx.footprint) * t.scale;
        if (t.invert) v = Vec3(1.0f) - v;
        if (t.isFloat) v = Vec3((v.x + v.y + v.z) / 3.0f);
        return v;
    }
    case TextureType::Scale:
        return operand(scene, t.a, t.aValue, ctx) * operand(scene, t.b, t.bValue, ctx);
    case TextureType::Mix: {
        const float amount = mixAmount(scene, t, ctx);
        return operand(scene, t.a, t.aValue, ctx) * (1 - amount) +
               operand(scene, t.b, t.bValue, ctx) * amount;
    }
    case TextureType::Checkerboard:
        return evenCheck(t, ctx, s, tt) ? operand(scene, t.a, t.aValue, ctx)
                                        : operand(scene, t.b, t.bValue, ctx);
    case TextureType::Bilerp:
        return t.corners[0] * ((1 - s) * (1 - tt)) + t.corners[1] * (s * (1 - tt)) +
               t.corners[2] * ((1 - s) * tt) + t.corners[3] * (s * tt);
    case TextureType::DirectionMix: {
        const float amount = std::abs(dot(ctx.n, t.direction));
        return operand(scene, t.a, t.aValue, ctx) * amount +
               operand(scene, t.b, t.bValue, ctx) * (1 - amount);
    }
    case TextureType::Dots:
        return insidePolkaDot(s, tt) ? operand(scene, t.a, t.aValue, ctx)
                                     : operand(scene, t.b, t.bValue, ctx);
    case TextureType::Fbm:
    case TextureType::Wrinkled:
    case TextureType::Windy:
    case TextureType::Marble: return solid(t, ctx);
    }
    return t.value;
}

// A combination's colour operand at the lanes: its texture's, its own spectrum's or its colour's.
Vec3 laneOperand(const Scene& scene, int index, const Vec3& value, const OperandSpectrum& s,
                 const TextureContext& ctx, const LaneReader& lanes);

// `t` at the lanes: within a tree with spectra every combination combines its operands at the
// lanes (and a combination without spectra of its own too: upsampling is not linear).
Vec3 evaluateLanes(const Scene& scene, const Texture& t, const TextureContext& ctx,
                   const LaneReader& lanes) {
    auto a = [&] { return laneOperand(scene, t.a, t.aValue, t.aSpectrum, ctx, lanes); };
    auto b = [&] { return laneOperand(scene, t.b, t.bValue, t.bSpectrum, ctx, lanes); };
    const Vec2 st = mapToSt(t, ctx);
    const float s = st.x, tt = st.y;
    switch (t.type) {
    case TextureType::Constant:
    case TextureType::Image: return lanes.rgb(evaluate(scene, t, ctx));
    case TextureType::Scale: // "scale" is a float
        return a() * (t.b >= 0 ? evalFloatTexture(scene, t.b, ctx) : t.bValue.x);
    case TextureType::Mix: {
        const float amount = mixAmount(scene, t, ctx);
        return a() * (1 - amount) + b() * amount;
    }
    case TextureType::Checkerboard: return evenCheck(t, ctx, s, tt) ? a() : b();
    case TextureType::Dots: return insidePolkaDot(s, tt) ? a() : b();
    case TextureType::Fbm:
    case TextureType::Wrinkled:
    case TextureType::Windy:
    case TextureType::Marble: return lanes.rgb(evaluate(scene, t, ctx));
    case TextureType::Bilerp: {
        const float w[4] = {(1 - s) * (1 - tt), s * (1 - tt), (1 - s) * tt, s * tt};
        Vec3 v(0.0f);
        for (std::size_t k = 0; k < 4; ++k)
            v += laneOperand(scene, -1, t.corners[k], t.cornerSpectra[k], ctx, lanes) * w[k];
        return v;
    }
    case TextureType::DirectionMix: {
        const float amount = std::abs(dot(ctx.n, t.direction));
        return a() * amount + b() * (1 - amount);
    }
    }
    return lanes.rgb(t.value);
}

Vec3 laneOperand(const Scene& scene, int index, const Vec3& value, const OperandSpectrum& s,
                 const TextureContext& ctx, const LaneReader& lanes) {
    if (index >= 0) return evaluateLanes(scene, scene.textures[std::size_t(index)], ctx, lanes);
    return s ? lanes.spectrum(s) : lanes.rgb(value);
}

} // namespace

Vec3 evalTexture(const Scene& scene, int index, const TextureContext& ctx) {
    return evaluate(scene, scene.textures[std::size_t(index)], ctx);
}

Vec3 evalTextureLanes(const Scene& scene, int index, const TextureContext& ctx,
                      const LaneReader& lanes) {
    const Texture& t = scene.textures[std::size_t(index)];
    return t.spectral ? evaluateLanes(scene, t, ctx, lanes) : lanes.rgb(evaluate(scene, t, ctx));
}

float evalFloatTexture(const Scene& scene, int index, const TextureContext& ctx) {
    Vec3 v = evalTexture(scene, index, ctx);
    return scene.textures[std::size_t(index)].isFloat ? v.x : (v.x + v.y + v.z) / 3.0f;
}

} // namespace rayproc
