// A scene material at a hit as the BSDF kernels see it: textures evaluated, pbrt-v4's roughness
// remapping and conductor parameterisations applied, a mix material resolved to one of its two.
// Every mode and pass calls this (path mode, the photon pass, gi's gathers, raytrace's stages).
#pragma once

#include "accel/embree_scene.h"
#include "engine/spectral_render.h"
#include "kernels/bsdf_sampling.h"
#include "scene/scene.h"

#include <cstdint>
#include <cstring>
#include <optional>

namespace rayproc {

// The material index a hit shades with: `material` itself, or for a mix material (recursively)
// the one of its two that pbrt-v4's MixMaterial::ChooseMaterial picks, by a hash of the hit
// point and the outgoing direction compared with `amount`.
int resolveMix(const Scene& scene, int material, const SurfaceHit& hit, const Vec3& wo);

// What every stage does with a hit before shading it: the material it shades with
// (resolveMix), and that material's shading normal where it has a bump or normal map
// (`hit.ns`, `hit.dpdu` and `hit.dpdv` replaced as pbrt-v4's BumpMap / NormalMap and
// SetShadingGeometry do; without differentials the bump's finite differences step 0.0005 in u
// and v, pbrt-v4's own fallback, and the normal's derivatives are taken as zero).
void resolveShading(const Scene& scene, SurfaceHit& hit, const Vec3& wo);

// A spectral lane's wavelengths and the conversions at them (engine/spectral_render.h).
struct SpectralShading {
    const SpectralRender& render;
    const LaneSpectrum& lane;
};

// Dispersion (docs/spectral.md): with `spectral`, whether materials[material] is a Dielectric or
// ThinDielectric, or a CoatedDiffuse or CoatedConductor's coat, whose index varies over
// wavelength (Material::iorSpectrum). bsdfAt builds it at the lane's hero wavelength, and the
// path's other wavelengths end there, as pbrt-v4's dielectric and coated materials terminate
// them (SampledWavelengths::TerminateSecondary) on any interaction: every ray a stage spawns
// from such a hit carries SpectralRender::terminatedU of its number (LaneShading::select with
// the material, then u()). Always false in RGB mode.
bool dispersive(const Scene& scene, int material, const SpectralShading* spectral);
// The same for a material, whatever the mode.
bool dispersiveMaterial(const Material& m);
// The wavelength number of the rays spawned at a hit on materials[material] by a lane of number
// u: u, or past a dispersive material SpectralRender::terminatedU(u).
inline float laneNumber(float u, const Scene& scene, int material,
                        const SpectralShading* spectral) {
    return dispersive(scene, material, spectral) ? SpectralRender::terminatedU(u) : u;
}

// A stage's spectral state while it shades one lane after another: the lane's wavelengths and
// the shading that reads them; nothing in RGB mode (no render). Not copyable: the shading
// refers to the lane it holds.
class LaneShading {
public:
    explicit LaneShading(const SpectralRender* render) {
        if (render) m_shading.emplace(SpectralShading{*render, m_lane});
    }
    LaneShading(const LaneShading&) = delete;
    LaneShading& operator=(const LaneShading&) = delete;
    // The lane of wavelength sample u (RayBatch::lambdaU) is shaded next. The same number
    // again (a path vertex's emission, then its scattering) keeps the lane already built; the
    // bits decide, so a terminated number (-0 for 0: SpectralRender::terminatedU) is another.
    void select(float u) {
        if (m_selected && std::memcmp(&u, &m_u, sizeof u) == 0) return;
        m_selected = true;
        m_u = u;
        if (m_shading) m_lane = m_shading->render.lane(u);
    }
    // The lane of wavelength sample u at a hit on scene.materials[material]: past it only
    // the hero wavelength where the material disperses (the number SpectralRender::
    // terminatedU(u), which the rays spawned from the hit take from u()).
    void select(float u, const Scene& scene, int material) {
        select(laneNumber(u, scene, material, shading()));
    }
    float u() const { return m_u; }
    const LaneSpectrum& lane() const { return m_lane; }
    const SpectralShading* shading() const { return m_shading ? &*m_shading : nullptr; }

private:
    LaneSpectrum m_lane{};
    float m_u = 0;
    bool m_selected = false; // m_u and m_lane hold a selected lane
    std::optional<SpectralShading> m_shading;
};

// The BSDF of Scene::materials[material] (not a mix: see resolveMix) at `hit`. `key` seeds the
// stochastic evaluation of layered materials. With `spectral` its colours hold their spectra
// at the lane's wavelengths (reflectances as albedo spectra, eta and k as unbounded ones; the
// dielectric's or coat's ior stays one number: a dispersive one's at the lane's hero
// wavelength).
kernels::BsdfParams bsdfAt(const Scene& scene, int material, const SurfaceHit& hit,
                           std::uint64_t key, const SpectralShading* spectral = nullptr);

// Both steps: the BSDF the hit shades with.
inline kernels::BsdfParams resolveBsdf(const Scene& scene, const SurfaceHit& hit, const Vec3& wo,
                                       std::uint64_t key,
                                       const SpectralShading* spectral = nullptr) {
    return bsdfAt(scene, resolveMix(scene, hit.material, hit, wo), hit, key, spectral);
}

// raytrace's and gi's radiance chains (camera rays, gather rays) carry basic radiance L / n^2
// through glass: smooth refraction takes no eta^2 at either interface (exact while the camera and
// the lights are outside), and gi's photons carry flux / n^2 to meet them (gi/photon_stage.h).
// A rough dielectric's sampled transmission carries f / eta^2 (pbrt-v4's radiance mode); this is
// the factor, eta^2 = (n_t / n_i)^2 for such a sample and 1 for any other, that returns it to
// basic radiance. Without it a floor seen through rough open water in gi was n^2 too dark (the
// eta^2 twice: the chain's and the photons').
inline float basicRadianceScale(const kernels::BsdfParams& b, const Vec3& wo, const Vec3& ng,
                                const kernels::BsdfSample& s) {
    if (!s.transmitted || s.delta || b.kind != kernels::BsdfKind::Dielectric ||
        !kernels::roughAlphas(b))
        return 1.0f;
    float eta = dot(wo, ng) > 0 ? b.ior : 1.0f / b.ior;
    return eta * eta;
}

// The untextured BSDF of a material (constant parameters only; tests, benchmarks).
kernels::BsdfParams bsdfOf(const Material& m);

} // namespace rayproc
