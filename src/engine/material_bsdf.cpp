#include "engine/material_bsdf.h"

#include "kernels/random.h"
#include "scene/ior_spectrum.h"
#include "scene/reflectance_spectrum.h"
#include "texture/texture_eval.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rayproc {

namespace {

std::uint32_t floatBits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

// A colour at the lane's wavelengths: its colour space's spectrum as a reflectance or as an
// unbounded value.
Vec3 upsampledAt(const SpectralShading& s, const Vec3& rgb, bool unbounded) {
    return unbounded ? s.render.unbounded(rgb, s.lane) : s.render.albedo(rgb, s.lane);
}

// An RGB parameter at a spectral lane's wavelengths: the precomputed spectrum of a constant,
// the table's of a texel.
Vec3 spectralValue(const SpectralShading& s, const UpsampledRgb& pre, const Vec3& rgb,
                   bool unbounded) {
    if (pre.valid) return SpectralRender::evaluate(pre, s.lane, false);
    return upsampledAt(s, rgb, unbounded);
}

// A texture's leaves at the lane (evalTextureLanes): a colour upsampled as spectralValue does,
// a constant operand's own spectrum (as a reflectance or an unbounded value) at the nearest
// nanometres.
class ShadingLanes final : public LaneReader {
public:
    ShadingLanes(const SpectralShading& s, bool unbounded) : m_s(s), m_unbounded(unbounded) {}
    Vec3 rgb(const Vec3& colour) const override { return upsampledAt(m_s, colour, m_unbounded); }
    Vec3 spectrum(const OperandSpectrum& o) const override {
        const float* v = (m_unbounded ? o.unbounded : o.albedo)->values.values.data();
        return {v[m_s.lane.nm[0]], v[m_s.lane.nm[1]], v[m_s.lane.nm[2]]};
    }

private:
    const SpectralShading& m_s;
    bool m_unbounded;
};

// A texture with spectra (Texture::spectral) at the lane; a reflectance clamped to [0, 1] as
// pbrt-v4's materials clamp what their textures give.
Vec3 spectralTexture(const Scene& scene, int texture, const TextureContext& tc,
                     const SpectralShading& s, bool unbounded) {
    const Vec3 v = evalTextureLanes(scene, texture, tc, ShadingLanes(s, unbounded));
    if (unbounded) return {std::max(v.x, 0.0f), std::max(v.y, 0.0f), std::max(v.z, 0.0f)};
    return {std::clamp(v.x, 0.0f, 1.0f), std::clamp(v.y, 0.0f, 1.0f), std::clamp(v.z, 0.0f, 1.0f)};
}

using MS = SpectralRender::MaterialSpectra;
using Field = UpsampledRgb MS::*;

// A material's parameter, constant or its texture at the hit (constants only without one); with
// `sp` (material index `mi`) a colour at the lane's wavelengths.
struct ParamEval {
    const Scene* scene;
    const TextureContext* tc;
    const SpectralShading* sp = nullptr;
    int mi = 0;
    Vec3 upsample(const Vec3& rgb, Field f, bool unbounded) const {
        return sp ? spectralValue(*sp, sp->render.material(mi).*f, rgb, unbounded) : rgb;
    }
    Vec3 color(const ColorParam& p, Field f, bool unbounded = false) const {
        if (p.textured() && spectralTree(p.texture))
            return spectralTexture(*scene, p.texture, *tc, *sp, unbounded);
        return upsample(scene && tc ? evalColor(*scene, p, *tc) : p.value, f, unbounded);
    }
    // Whether the spectral mode reads `texture` as a tree of spectra (Texture::spectral).
    bool spectralTree(int texture) const {
        return sp && scene && tc && scene->textures[std::size_t(texture)].spectral;
    }
    float operator()(const FloatParam& p) const {
        return scene && tc ? evalFloat(*scene, p, *tc) : p.value;
    }
};

// A conductor's complex index: its eta and k, or pbrt-v4's equivalent of a reflectance r at
// normal incidence (eta = 1, k = 2 sqrt(r) / sqrt(1 - r)).
void conductorIndex(const Material& m, const ParamEval& eval, kernels::BsdfParams& b) {
    if (m.useReflectance) {
        Vec3 r = b.color;
        auto kOf = [](float x) {
            x = std::clamp(x, 0.0f, 0.9999f);
            return 2.0f * std::sqrt(x) / std::sqrt(1.0f - x);
        };
        b.eta = Vec3(1.0f);
        b.k = {kOf(r.x), kOf(r.y), kOf(r.z)};
    } else {
        b.eta = eval.color(m.eta, &MS::eta, true);
        b.k = eval.color(m.k, &MS::k, true);
    }
}

// The slab between a coat and its base (pbrt-v4's LayeredBxDF parameters).
void layerParams(const Material& m, const ParamEval& eval, kernels::BsdfParams& b) {
    b.thickness = std::max(eval(m.thickness), 1e-6f);
    b.albedo = eval.color(m.albedo, &MS::albedo);
    b.g = m.g;
    b.maxDepth = m.maxDepth;
    b.nSamples = m.nSamples;
}

// pbrt-v4's coatedconductor: the coat's alphas are b.alphaX / alphaY; an index of 0 counts as 1,
// as pbrt-v4's material takes it; albedo is clamped to [0, 1] and g to [-1, 1] there too.
void coatedConductorParams(const Material& m, const ParamEval& eval, kernels::BsdfParams& b) {
    b.kind = kernels::BsdfKind::CoatedConductor;
    if (b.ior == 0) b.ior = 1.0f;
    conductorIndex(m, eval, b);
    b.baseAlphaX = roughnessToAlpha(eval(m.conductorURoughness), m.remapRoughness);
    b.baseAlphaY = roughnessToAlpha(eval(m.conductorVRoughness), m.remapRoughness);
    layerParams(m, eval, b);
    b.albedo = {std::clamp(b.albedo.x, 0.0f, 1.0f), std::clamp(b.albedo.y, 0.0f, 1.0f),
                std::clamp(b.albedo.z, 0.0f, 1.0f)};
    b.g = std::clamp(b.g, -1.0f, 1.0f);
}

// Fills the parameters every kind reads from the material's constants and textures; with
// `sp` (material index `mi`) the colours at the lane's wavelengths.
kernels::BsdfParams build(const Scene* scene, const Material& m, const TextureContext* tc,
                          const SpectralShading* sp = nullptr, int mi = 0) {
    const ParamEval eval{scene, tc, sp, mi};
    kernels::BsdfParams b;
    if (m.colorTexture >= 0 && eval.spectralTree(m.colorTexture))
        b.color = spectralTexture(*scene, m.colorTexture, *tc, *sp, false);
    else
        b.color = eval.upsample(m.colorTexture >= 0 && scene && tc
                                    ? evalTexture(*scene, m.colorTexture, *tc)
                                    : m.color,
                                &MS::color, false);
    b.ior = m.ior;
    // pbrt-v4's materials sample their eta at the hero wavelength, an index of 0 (a spectrum
    // past its ends) taken as 1.
    if (sp && dispersiveMaterial(m)) {
        const float n = m.iorSpectrum->at(sp->lane.w.lambda[0]);
        b.ior = n == 0 ? 1.0f : n;
    }
    b.alpha = kernels::ggxAlpha(m.roughness);
    b.alphaX = roughnessToAlpha(eval(m.uRoughness), m.remapRoughness);
    b.alphaY = roughnessToAlpha(eval(m.vRoughness), m.remapRoughness);
    switch (m.type) {
    case MaterialType::Diffuse: b.kind = kernels::BsdfKind::Diffuse; break;
    case MaterialType::Mirror: b.kind = kernels::BsdfKind::Mirror; break;
    case MaterialType::Dielectric: b.kind = kernels::BsdfKind::Dielectric; break;
    case MaterialType::Glossy: b.kind = kernels::BsdfKind::Glossy; break;
    case MaterialType::Conductor:
        b.kind = kernels::BsdfKind::Conductor;
        conductorIndex(m, eval, b);
        break;
    case MaterialType::CoatedDiffuse:
        b.kind = kernels::BsdfKind::CoatedDiffuse;
        layerParams(m, eval, b);
        b.coatWalk = m.coatModel == Material::CoatModel::RandomWalk ||
                     (m.coatModel == Material::CoatModel::Auto && !isBlack(b.albedo));
        break;
    case MaterialType::CoatedConductor: coatedConductorParams(m, eval, b); break;
    case MaterialType::ThinDielectric: b.kind = kernels::BsdfKind::ThinDielectric; break;
    case MaterialType::DiffuseTransmission:
        b.kind = kernels::BsdfKind::DiffuseTransmission;
        b.color = b.color * m.scale;
        b.transmittance = eval.color(m.transmittance, &MS::transmittance) * m.scale;
        break;
    case MaterialType::Mix: b.kind = kernels::BsdfKind::Diffuse; break; // resolved earlier
    }
    return b;
}

TextureContext textureContext(const SurfaceHit& hit) {
    TextureContext tc;
    tc.uv = hit.uv;
    tc.p = hit.p;
    tc.n = hit.ng;
    return tc;
}

} // namespace

int resolveMix(const Scene& scene, int material, const SurfaceHit& hit, const Vec3& wo) {
    for (int depth = 0; depth < 16; ++depth) {
        const Material& m = scene.materials[std::size_t(material)];
        if (m.type != MaterialType::Mix) return material;
        TextureContext tc = textureContext(hit);
        float amount = evalFloat(scene, m.amount, tc);
        if (amount <= 0) {
            material = m.mix[0];
        } else if (amount >= 1) {
            material = m.mix[1];
        } else {
            std::uint64_t h = kernels::hashCombine(
                (std::uint64_t(floatBits(hit.p.x)) << 32) | floatBits(hit.p.y),
                (std::uint64_t(floatBits(hit.p.z)) << 32) | floatBits(wo.x));
            h = kernels::hashCombine(h, (std::uint64_t(floatBits(wo.y)) << 32) | floatBits(wo.z));
            h = kernels::hashCombine(h, std::uint64_t(material));
            float u = float(h >> 40) * 0x1p-24f;
            material = amount < u ? m.mix[0] : m.mix[1];
        }
    }
    return material; // a cycle the loaders reject; never reached for valid scenes
}

namespace {

// The shading frame pbrt-v4 perturbs: a mesh with per-vertex normals shades with dp/du projected
// onto the shading normal's plane and dp/dv = ns x dp/du (the triangle's own dp/dv is not kept),
// other surfaces with their own dp/du and dp/dv; a surface without a tangent gets a unit frame.
void shadingFrame(const SurfaceHit& hit, Vec3& dpdu, Vec3& dpdv) {
    dpdu = hit.dpdu;
    dpdv = hit.dpdv;
    const Vec3& n = hit.ns;
    const bool interpolated =
        hit.shape && hit.shape->type == ShapeType::Mesh && !hit.shape->mesh->normals.empty();
    Vec3 ts = cross(n, dpdu);
    if (dot(ts, ts) > 0 && std::isfinite(dot(ts, ts))) {
        if (interpolated) {
            dpdu = cross(ts, n);
            dpdv = ts;
        }
        if (dot(dpdv, dpdv) > 0) return;
    }
    orthonormalBasis(n, dpdu, dpdv);
}

// pbrt-v4's NormalMap: the image's 2 c - 1, normalised, in the frame (dp/du, ns x dp/du, ns).
void normalMapped(const Scene& scene, int texture, const TextureContext& tc, const Vec3& n,
                  Vec3& dpdu, Vec3& dpdv) {
    Vec3 c = evalTexture(scene, texture, tc);
    Vec3 t = c * 2.0f - Vec3(1.0f);
    if (!(dot(t, t) > 0)) return;
    t = normalize(t);
    Vec3 x = normalize(dpdu - n * dot(n, dpdu)), y = cross(n, x);
    Vec3 ns = x * t.x + y * t.y + n * t.z;
    float ulen = length(dpdu), vlen = length(dpdv);
    Vec3 u = dpdu - ns * dot(ns, dpdu);
    if (!(dot(u, u) > 0)) return;
    dpdu = normalize(u) * ulen;
    dpdv = normalize(cross(ns, dpdu)) * vlen;
}

// pbrt-v4's BumpMap: the displaced surface p + d(u, v) n differentiated by forward differences.
void bumpMapped(const Scene& scene, int texture, const SurfaceHit& hit, const TextureContext& tc,
                const Vec3& n, Vec3& dpdu, Vec3& dpdv) {
    constexpr float kStep = 0.0005f;
    const float d = evalFloatTexture(scene, texture, tc);
    TextureContext shifted = tc;
    shifted.p = hit.p + dpdu * kStep;
    shifted.uv = {tc.uv.x + kStep * hit.uvStep.x, tc.uv.y};
    const float du = evalFloatTexture(scene, texture, shifted);
    shifted.p = hit.p + dpdv * kStep;
    shifted.uv = {tc.uv.x, tc.uv.y + kStep * hit.uvStep.y};
    const float dv = evalFloatTexture(scene, texture, shifted);
    dpdu = dpdu + n * ((du - d) / kStep);
    dpdv = dpdv + n * ((dv - d) / kStep);
}

} // namespace

void resolveShading(const Scene& scene, SurfaceHit& hit, const Vec3& wo) {
    hit.material = resolveMix(scene, hit.material, hit, wo);
    const Material& m = scene.materials[std::size_t(hit.material)];
    if (m.normalMap < 0 && m.displacement < 0) return;
    Vec3 dpdu, dpdv;
    shadingFrame(hit, dpdu, dpdv);
    const TextureContext tc = textureContext(hit);
    if (m.normalMap >= 0) normalMapped(scene, m.normalMap, tc, hit.ns, dpdu, dpdv);
    else bumpMapped(scene, m.displacement, hit, tc, hit.ns, dpdu, dpdv);
    // SetShadingGeometry: the new normal on the geometric normal's side.
    Vec3 ns = cross(dpdu, dpdv);
    float len2 = dot(ns, ns);
    if (!(len2 > 0) || !std::isfinite(len2)) return; // a degenerate frame keeps the old normal
    ns = ns / std::sqrt(len2);
    hit.ns = dot(ns, hit.ng) < 0 ? -ns : ns;
    hit.dpdu = dpdu;
    hit.dpdv = dpdv;
}

kernels::BsdfParams bsdfAt(const Scene& scene, int material, const SurfaceHit& hit,
                           std::uint64_t key, const SpectralShading* spectral) {
    TextureContext tc = textureContext(hit);
    kernels::BsdfParams b =
        build(&scene, scene.materials[std::size_t(material)], &tc, spectral, material);
    b.key = key;
    b.tangent = hit.dpdu; // the kernels make it perpendicular to the shading normal
    return b;
}

bool dispersiveMaterial(const Material& m) {
    switch (m.type) {
    case MaterialType::Dielectric:
    case MaterialType::ThinDielectric:
    case MaterialType::CoatedDiffuse:
    case MaterialType::CoatedConductor: return m.iorSpectrum != nullptr;
    default: return false;
    }
}

bool dispersive(const Scene& scene, int material, const SpectralShading* spectral) {
    return spectral && dispersiveMaterial(scene.materials[std::size_t(material)]);
}

kernels::BsdfParams bsdfOf(const Material& m) { return build(nullptr, m, nullptr); }

} // namespace rayproc
