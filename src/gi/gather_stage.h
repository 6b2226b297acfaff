// Gather stage: the second pass of Jensen's method at diffuse surfaces.
// Spawning side, at a diffuse hit reached from the camera through specular surfaces only:
//  - caustics: the caustic photon map's radiance estimate, added directly;
//  - indirect diffuse: Ward's irradiance cache when a usable record exists, else a final
//    gather: M x N ~ `gatherRays` (a record's) or `filmGatherRays` (the film's, in a render
//    pass) cosine-weighted rays, one jittered ray per stratum
//    sin^2(theta) in [j/M, (j+1)/M), phi in [2 pi k/N, 2 pi (k+1)/N) (equal cosine-weighted
//    solid angle each; the layout Ward & Heckbert's gradients read, GatherStrata).
//  In the cache's prepass it only creates records (the gather rays then sum into them, and
//  with gradients also write their stratum's radiance and first-hit distance).
//  At a diffuse hit reached through a glossy bounce it adds the global map's estimate of all
//  reflected light (no final gather there, and no shadow rays: the map holds direct light).
// Retrace side: each gather ray's hit reads the global photon map (no second gather): the
// reflected radiance albedo/pi * E, with E the precomputed (Christensen) or full estimate.
// With GiSettings::gatherDirect (the default) the direct light of delta lights (the sun) and
// of the sky comes from light samples at the hit instead, one per delta light and one of the
// sky, each an occlusion ray (kGatherShadowRay) whose unoccluded contribution this stage
// adds to the gather's pixel or cache record when it comes back; E is then the map without
// those lights' first-landing photons. Area lights' direct light stays the map's: sampled
// at gather hits close to a lamp it made bright specks in cache records.
// At a mirror or glass surface the gather ray continues specularly (one branch, chosen with
// the Fresnel probability; at most maxDepth specular bounces) until it reaches a diffuse
// surface, so light along L ... D S+ D paths is kept; emission reached that way is the caustic
// map's (L S+ D at the gather's origin) and is not added.
#pragma once

#include "engine/hit_list.h"
#include "engine/material_bsdf.h"
#include "engine/render_context.h"
#include "engine/spectral_render.h"
#include "engine/stage.h"
#include "engine/surface_stage.h"
#include "gi/gi_pipeline.h"
#include "kernels/bsdf_params.h"

#include <cstdint>

namespace rayproc {

class PhotonMap;
class IcRequests;
struct GiData;

// Pushes a final-gather ray's first segment (kGatherRay, no specular bounce yet) from
// `origin` along `wi`: the gather stage's own (a record's or the film's gather) and the cache
// refinement's (gi/record_emitter.h), which also pushes its correction rays with it
// (kCorrectionRay, `out` being that kind's batch). `target` is the pixel, or the request slot with
// kFlagGatherRecord; `sample` the camera sample, or the record's stratum.
// `lambdaU`: the ray's wavelength number in spectral mode (a film gather's is its path's).
inline void pushGatherRay(RayBatch& out, const Vec3& origin, const Vec3& wi, std::uint32_t target,
                          std::uint32_t sample, const Vec3& weight, std::uint64_t rngKey,
                          std::uint8_t depth, std::uint8_t flags, float lambdaU) {
    int j = out.push(origin.x, origin.y, origin.z, wi.x, wi.y, wi.z, 0.0f, kInfinity);
    out.lambdaU[j] = lambdaU;
    out.pixel[j] = target;
    out.sample[j] = sample;
    out.wr[j] = weight.x;
    out.wg[j] = weight.y;
    out.wb[j] = weight.z;
    out.rngKey[j] = rngKey;
    out.depth[j] = depth;
    out.specularDepth[j] = 0;
    out.flags[j] = flags;
    out.prevPdf[j] = 0;
    out.prevCos[j] = 0;
}

// Spectral mode: the wavelength number of ray r of a record's `rays` gather rays, `u` the
// record's own number: u + r / rays (mod 1), so the record's rays spread their wavelengths
// evenly (each ray's number is still uniform and independent of its direction).
inline float recordLambdaU(float u, int r, int rays) {
    float v = u + float(r) / float(rays);
    v = v >= 1.0f ? v - 1.0f : v;
    return v < 1.0f ? v : 0x1.fffffep-1f;
}

class GatherStage : public RetraceStage, public DiffuseHitHandler {
public:
    // `requests`: the cache's prepass (new records' gathers go there) or its refinement (the
    // records' gather rays sum there); null in a render pass.
    GatherStage(const RenderContext& rc, const GiData& gi, IcRequests* requests = nullptr)
        : m_rc(rc), m_gi(gi), m_requests(requests) {}
    void spawn(const RayBatch& parent, const HitList& hits, StageContext& ctx) override;
    void retrace(RayBatch& batch, StageContext& ctx) override;
    // The light samples' occlusion rays (kGatherShadowRay).
    void retraceShadows(ShadowBatch& batch, StageContext& ctx) override;

    // What the global map gives where gi reads it; the correction stage takes it away again.
    // Irradiance from `map` (the global map or its scattered photons): precomputed or full;
    // RGB in either mode (a spectral render's maps hold XYZ: converted here).
    Vec3 mapIrradiance(const PhotonMap* map, const Vec3& p, const Vec3& n) const;
    // Radiance an opaque glossy surface at h sends towards wo: the global map's estimate with
    // the BSDF (PhotonMap::radiance), n its facing shading normal. In spectral mode (`lane`)
    // at the lane's wavelengths, with the BSDF at them: each photon weighted by its luminance,
    // times the spectrum of the photons' irradiance over its luminance (lightAt).
    Vec3 glossyRadiance(const kernels::BsdfParams& bsdf, const SurfaceHit& h, const Vec3& wo,
                        const Vec3& n, const LaneSpectrum* lane = nullptr) const;
    // An RGB estimate of light (irradiance, a record's) as the path's radiance carries it: in
    // spectral mode at the lane's wavelengths as an RGB illuminant spectrum (the unbounded
    // sigmoid spectrum of its colour times the colour space's illuminant, as path mode takes
    // emission and skies: so white irradiance is the illuminant's light, which the film turns
    // back into white). A metamer of the true irradiance spectrum (docs/spectral.md).
    Vec3 lightAt(const Vec3& rgb, const LaneSpectrum& lane) const;

private:
    // The light samples at a gather ray's diffuse hit h (lane i of b, at the wavelengths of
    // `lane` in spectral mode), for a Lambertian reflection of factor `reflect` (throughput x
    // albedo / pi): GatherShadow rays.
    std::uint64_t sampleDirect(const RayBatch& b, int i, const SurfaceHit& h, const Vec3& ng,
                               const Vec3& ns, const Vec3& reflect, const LaneSpectrum& lane,
                               StageContext& ctx) const;
    // Adds a light sample's, or a gather ray's, radiance to lane i's pixel or cache record (in
    // spectral mode it is at `lane`'s wavelengths: converted to RGB as the film does).
    template <class Batch>
    void deposit(const Batch& b, int i, const Vec3& radiance, const LaneSpectrum& lane,
                 ThreadStats& stats) const;
    // Adds reflect x E to lane i's pixel: `reflect` the throughput times the BSDF, E an RGB
    // estimate of irradiance (spectral mode: lightAt the lane's wavelengths, then the film's RGB).
    void addReflected(const RayBatch& b, int i, const Vec3& reflect, const Vec3& e,
                      const LaneSpectrum& lane, ThreadStats& stats) const;
    // Adds reflect x light to lane i's pixel, light already at the lane's wavelengths.
    void addReflectedLight(const RayBatch& b, int i, const Vec3& reflect, const Vec3& light,
                           const LaneSpectrum& lane, ThreadStats& stats) const;
    // Light reaching a gather ray straight from an emitter (light set index `light`, or -1; the
    // shape it hit, or nullptr for a light sample) or the sky (-1, nullptr), at the lane's
    // wavelengths in spectral mode.
    Vec3 emissionAt(const Vec3& rgb, int light, const Shape* shape, const LaneSpectrum& lane) const;

    // Lane i's hit, `wl` selected at its wavelengths (spectral mode); at a dispersive material
    // the lane's hero alone from there on (its number marked in `b` and `wl`).
    bool shadeHit(RayBatch& b, int i, LaneShading& wl, Vec3& radiance, float& distance,
                  std::uint64_t& spawned, StageContext& ctx) const;
    void recordGatherEnd(const RayBatch& b, int i, float distance, bool done) const;
    std::uint64_t spawnFinalGather(const RayBatch& b, int i, const SurfaceHit& h, const Vec3& ng,
                                   const Vec3& ns, const Vec3& reflectance, bool prepass,
                                   int thetaCount, int phiCount, StageContext& ctx) const;
    // A photon map's estimate in RGB (a spectral render's maps hold XYZ).
    Vec3 rgbOf(const Vec3& mapValue) const;
    // The caustic map's irradiance (as the map holds it): k-nearest, or within the pass's
    // radius when progressive (the pixel's own with GiSettings::causticPixelRadius).
    Vec3 causticIrradiance(const Vec3& p, const Vec3& n, std::uint32_t pixel) const;
    // The caustic light at a visible point of a path of one wavelength (spectral mode, past
    // dispersive glass), at its lane: through the glass the point depends on the wavelength,
    // and so does the caustic light there, so the map's photons of one wavelength count
    // through a tent kernel over wavelength around the path's (kCausticBandwidthNm); photons
    // of three wavelengths as their colour's spectrum (lightAt). Same radius as
    // causticIrradiance.
    Vec3 causticLightOfOneWavelength(const Vec3& p, const Vec3& n, std::uint32_t pixel,
                                     const LaneSpectrum& lane) const;
    // The caustic estimate's radius logic (k-nearest, fixed, progressive per pixel), over
    // `within(radius, counted)` (an estimate within a radius) and `nearest()` (the k-nearest).
    template <class Within, class Nearest>
    auto causticEstimate(const Vec3& p, std::uint32_t pixel, const Within& within,
                         const Nearest& nearest) const;
    const RenderContext& m_rc;
    const GiData& m_gi;
    IcRequests* m_requests;
};

} // namespace rayproc
