#include "gi/gather_stage.h"

#include "engine/material_bsdf.h"
#include "engine/path_state.h"
#include "engine/sample_numbers.h"
#include "gi/caustic_pixel_radius.h"
#include "gi/gi_context.h"
#include "gi/irradiance_cache.h"
#include "gi/photon_map.h"
#include "kernels/bsdf_sampling.h"
#include "kernels/pbrt_bsdfs.h"
#include "kernels/sampling.h"

#include <algorithm>
#include <cmath>

namespace rayproc {

namespace {
// A gather ray's flag (the camera's "count emission" bit, which gather rays do not otherwise
// carry): its chain has met a glossy surface, so light it then reaches (an emitter, the sky)
// is in neither the caustic map nor the gather origin's light samples and is added.
constexpr std::uint8_t kFlagPastGlossy = kFlagCountEmission;
// The caustic kernel's half-width over wavelength for a path of one wavelength (nm): its blur
// is the bias it leaves; the photons it counts, a tenth to a fifth of those of every
// wavelength near the middle of the spectrum, its noise.
constexpr float kCausticBandwidthNm = 20.0f;
} // namespace

Vec3 GatherStage::mapIrradiance(const PhotonMap* map, const Vec3& p, const Vec3& n) const {
    const GiData& gi = m_gi;
    if (!map || map->size() == 0) return Vec3(0.0f);
    return rgbOf(gi.settings.precomputedIrradiance && map->hasPrecomputedIrradiance()
                     ? map->irradianceFast(p, n, gi.settings.globalK, gi.globalRadius)
                     : map->irradiance(p, n, gi.settings.globalK, gi.globalRadius));
}

Vec3 GatherStage::rgbOf(const Vec3& mapValue) const {
    return m_rc.spectral ? m_rc.spectral->xyzToRgb(mapValue) : mapValue;
}

Vec3 GatherStage::lightAt(const Vec3& rgb, const LaneSpectrum& lane) const {
    return m_rc.spectral ? m_rc.spectral->illuminant(rgb, lane) : rgb;
}

void GatherStage::addReflected(const RayBatch& b, int i, const Vec3& reflect, const Vec3& e,
                               const LaneSpectrum& lane, ThreadStats& stats) const {
    if (!m_rc.spectral) {
        m_rc.film.add(b.pixel[i], reflect * e, stats);
        return;
    }
    addReflectedLight(b, i, reflect, lightAt(e, lane), lane, stats);
}

void GatherStage::addReflectedLight(const RayBatch& b, int i, const Vec3& reflect,
                                    const Vec3& light, const LaneSpectrum& lane,
                                    ThreadStats& stats) const {
    m_rc.film.add(b.pixel[i], m_rc.spectral->toFilm(reflect * light, lane), stats);
}

Vec3 GatherStage::emissionAt(const Vec3& rgb, int light, const Shape* shape,
                             const LaneSpectrum& lane) const {
    if (!m_rc.spectral || isBlack(rgb)) return rgb;
    if (shape) return m_rc.spectral->emitted(*shape, light, rgb, lane);
    return light >= 0 ? m_rc.spectral->lightValue(std::size_t(light), rgb, lane)
                      : m_rc.spectral->sky(rgb, lane);
}

std::uint64_t GatherStage::sampleDirect(const RayBatch& b, int i, const SurfaceHit& h,
                                        const Vec3& ng, const Vec3& ns, const Vec3& reflect,
                                        const LaneSpectrum& lane, StageContext& ctx) const {
    const LightSet& lights = m_rc.lights;
    const std::uint64_t key = kernels::hashCombine(b.rngKey[i], 0x5d17);
    std::uint64_t spawned = 0;
    auto emit = [&](const Vec3& wi, const LightSample* light, const Vec3& weight) {
        float c = dot(wi, ns);
        if (dot(wi, ng) <= 0 || !(c > 0)) return;
        Vec3 contribution = reflect * weight * c;
        if (isBlack(contribution) || !isFinite(contribution)) return;
        ShadowBatch& out = ctx.outShadow(kGatherShadowRay);
        spawnShadowRay(out, b, i, h, ng, wi, light, contribution);
        out.flags[out.count - 1] = std::uint8_t(b.flags[i] & kFlagGatherRecord);
        ++spawned;
    };
    // One sample per delta light (no random numbers), one of the sky.
    for (std::size_t l = 0; l < lights.lights.size(); ++l) {
        if (!lights.lights[l].delta()) continue;
        LightSample ls = lights.lights[l].sample(h.p, {0.5f, 0.5f});
        if (ls.valid) emit(ls.wi, &ls, emissionAt(ls.weight, int(l), nullptr, lane));
    }
    if (lights.hasEnvironment()) {
        // A film gather of one ray per pixel sample (the default past a few samples) lands
        // once per sample: its sky sample takes the pixel's Sobol points at this depth (a
        // sequence of its own per chain segment), stratified over the passes as the gather's
        // direction is. Several rays per sample would share them (the rays' index is not on
        // the ray), and the prepass's records draw independent numbers: both keep the lane's.
        const bool sobol = m_rc.policy.stratify && !(b.flags[i] & kFlagGatherRecord) &&
                           m_gi.filmGatherTheta * m_gi.filmGatherPhi == 1;
        const Vec2 u = sobol ? SampleNumbers(b, i, true, sampleSeedKey(m_rc.seed),
                                             0x5d17u + b.specularDepth[i])
                                   .get2D(0)
                             : Vec2{kernels::uniform(key, 0), kernels::uniform(key, 1)};
        EnvironmentSample es = lights.environment.sample(u, ns);
        if (es.valid) emit(es.wi, nullptr, emissionAt(es.weight, -1, nullptr, lane));
    }
    return spawned;
}

template <class Batch>
void GatherStage::deposit(const Batch& b, int i, const Vec3& radiance,
                          const LaneSpectrum& lane, ThreadStats& stats) const {
    if (isBlack(radiance)) return;
    const Vec3 l = m_rc.spectral ? m_rc.spectral->toFilm(radiance, lane) : radiance;
    if (b.flags[i] & kFlagGatherRecord) {
        IcRequests& requests = *m_requests;
        requests[b.pixel[i]].add(b.sample[i], l, requests.radianceScale());
    } else {
        m_rc.film.add(b.pixel[i], l, stats);
    }
}

void GatherStage::retraceShadows(ShadowBatch& b, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, kGatherStageId);
    stats.stages[int(kGatherStageId)].raysIn += std::uint64_t(b.count);
    LaneShading wl(m_rc.spectral); // spectral mode: each ray's wavelengths
    for (int i = 0; i < b.count; ++i) {
        if (b.occluded(i)) continue;
        wl.select(b.lambdaU[i]);
        deposit(b, i, laneThroughput(b, i), wl.lane(), stats);
    }
}

Vec3 GatherStage::glossyRadiance(const kernels::BsdfParams& bsdf, const SurfaceHit& h,
                                 const Vec3& wo, const Vec3& n, const LaneSpectrum* lane) const {
    const GiData& gi = m_gi;
    if (!gi.global || gi.global->size() == 0) return Vec3(0.0f);
    auto f = [&](const Vec3& wi) {
        float pdf, c = std::abs(dot(wi, n));
        Vec3 f = kernels::evalBsdf(bsdf, wo, wi, h.ng, h.ns, pdf);
        return c > 1e-4f ? f / c : Vec3(0.0f);
    };
    if (!m_rc.spectral)
        return gi.global->radiance(h.p, n, gi.settings.globalK, gi.globalRadius, f);
    // sum f(wi_i, lambda) Y_i over the photons, times the spectrum of their irradiance E over
    // its luminance Y(E): exact where the photons share one spectrum.
    Vec3 xyz;
    const Vec3 byLuminance = gi.global->luminanceRadiance(h.p, n, gi.settings.globalK,
                                                          gi.globalRadius, 1, f, xyz);
    if (!(xyz.y > 0)) return Vec3(0.0f);
    return byLuminance * lightAt(m_rc.spectral->xyzToRgb(xyz), *lane) / xyz.y;
}

template <class Within, class Nearest>
auto GatherStage::causticEstimate(const Vec3& p, std::uint32_t pixel, const Within& within,
                                  const Nearest& nearest) const {
    const GiData& gi = m_gi;
    if (CausticPixelRadius* pixels = gi.causticPixels) {
        // The first pass estimates with the global first radius and seeds the pixel's own
        // from its k-nearest radius here; later passes use and count the pixel's.
        if (pixels->seeding()) {
            std::uint32_t found = 0;
            float r2 =
                gi.caustic->neighbourRadius2(p, gi.settings.causticK, pixels->maxRadius(), &found);
            pixels->seed(pixel, r2, found);
            return within(gi.causticRadius, nullptr);
        }
        std::uint32_t counted = 0;
        auto e = within(pixels->radius(pixel), &counted);
        pixels->found(pixel, counted);
        return e;
    }
    if (gi.causticFixedRadius) return within(gi.causticRadius, nullptr);
    return nearest();
}

Vec3 GatherStage::causticIrradiance(const Vec3& p, const Vec3& n, std::uint32_t pixel) const {
    const GiData& gi = m_gi;
    if (!gi.caustic || gi.caustic->size() == 0) return Vec3(0.0f);
    return causticEstimate(
        p, pixel,
        [&](float radius, std::uint32_t* counted) {
            return gi.caustic->irradianceWithin(p, n, radius, counted);
        },
        [&] { return gi.caustic->irradiance(p, n, gi.settings.causticK, gi.causticRadius); });
}

Vec3 GatherStage::causticLightOfOneWavelength(const Vec3& p, const Vec3& n, std::uint32_t pixel,
                                              const LaneSpectrum& lane) const {
    const GiData& gi = m_gi;
    if (!gi.caustic || gi.caustic->size() == 0) return Vec3(0.0f);
    const float hero = lane.w.lambda[0];
    // A photon of wavelength l and toXyz weight w (its value over its density, the hero's of
    // a terminated lane: 3 / pdf) is a sample of 3 times the spectral flux at l; the tent
    // kernel K (integral 1) spreads it over wavelength, so (1/3) sum K(hero - l) w over the
    // disc estimates the spectral irradiance at the hero, the lane's first value (the only
    // one its film weighs).
    auto one = [&](float lambda, const Vec3& xyz) {
        const float d = std::abs(lambda - hero);
        if (d >= kCausticBandwidthNm) return 0.0f;
        const float k = (1.0f - d / kCausticBandwidthNm) / kCausticBandwidthNm;
        return k * m_rc.spectral->oneWavelengthWeight(lambda, xyz) * (1.0f / 3.0f);
    };
    auto within = [&](float radius, std::uint32_t* counted) {
        return gi.caustic->irradianceSplit(p, n, radius, one, counted);
    };
    PhotonMap::WavelengthSplit e = causticEstimate(p, pixel, within, [&] {
        return within(std::sqrt(gi.caustic->neighbourRadius2(p, gi.settings.causticK,
                                                             gi.causticRadius)),
                      nullptr);
    });
    return lightAt(rgbOf(e.others), lane) + Vec3(e.oneWavelength);
}

// A new final gather from hit h of lane i (`reflectance`: throughput x albedo): for a cache
// record in the prepass (a request slot), into the film otherwise. Returns the rays spawned.
std::uint64_t GatherStage::spawnFinalGather(const RayBatch& b, int i, const SurfaceHit& h,
                                            const Vec3& ng, const Vec3& ns,
                                            const Vec3& reflectance, bool prepass,
                                            int thetaCount, int phiCount,
                                            StageContext& ctx) const {
    const GiData& gi = m_gi;
    std::uint64_t spawned = 0;
    const int strata = thetaCount * phiCount;
    std::uint32_t target = b.pixel[i];
    std::uint8_t flags = 0;
    Vec3 weight = reflectance / float(strata); // cosine sampling: f cos / pdf = albedo
    Vec3 tu, tv;
    orthonormalBasis(ns, tu, tv);
    IcRequest* request = nullptr;
    if (prepass) {
        std::uint32_t slot = 0;
        request = m_requests->claim(slot);
        if (!request) return 0; // more than the pass can hold
        IcRequest& rq = *request;
        rq.key = (std::uint64_t(b.pixel[i]) << 32) ^ (b.rngKey[i] & 0xffffffffu);
        rq.position = h.p;
        rq.normal = ns;
        rq.origin = offsetRayOrigin(h, ng, ns);
        rq.geometricNormal = ng;
        rq.u = tu;
        rq.v = tv;
        if (gi.strataWanted) {
            rq.strataRadiance.assign(std::size_t(strata), {0, 0, 0});
            rq.strataDistance.assign(std::size_t(strata), 0.0f);
        }
        target = slot;
        flags = kFlagGatherRecord;
        weight = Vec3(1.0f);
    }
    std::uint64_t key = kernels::hashCombine(b.rngKey[i], 0x6a7e);
    Vec3 origin = offsetRayOrigin(h, ng, ns);
    // Spectral mode: a film gather's rays carry the path's wavelengths (their weight is at
    // them); a record's, which carry no path's, each their own (recordLambdaU).
    const float recordU = kernels::uniform(kernels::hashCombine(key, 0x1a3b), 0);
    // A film gather's M N rays are the block sample x M N ... of a Sobol sequence per
    // (pixel, depth) over the whole cosine-weighted hemisphere (engine/sample_numbers.h):
    // stratified within the gather as the strata are when M N is a power of two, and
    // across the pixel's samples, which a gather of one ray per pass (the default at high
    // spp) otherwise is not.
    const bool sobol = !prepass && m_rc.policy.stratify;
    const SampleNumbers numbers(b, i, sobol, sampleSeedKey(m_rc.seed), 0x6a7e);
    // A record's stratum (j, k): sin^2(theta) in [j/M, (j+1)/M), phi in [2 pi k/N,
    // 2 pi (k+1)/N), one jittered ray each (the gradients' layout). sin^2(theta) uniform is
    // the cosine-weighted density (Malley), so every ray carries albedo / (M N) and
    // E = pi / (M N) sum L_jk (GatherStrata).
    for (int r = 0; r < strata; ++r) {
        int j = r / phiCount, kk = r % phiCount;
        // --no-stratification: independent cosine-weighted rays (the cache then interpolates
        // without gradients, which need the strata; see gi.cpp).
        Vec3 l = sobol ? kernels::cosineStratum(0, 0, 1, 1,
                                                numbers.get2D(0, std::uint32_t(r),
                                                              std::uint32_t(strata)),
                                                true)
                       : kernels::cosineStratum(j, kk, thetaCount, phiCount,
                                                {kernels::uniform(key, 2 * std::uint32_t(r)),
                                                 kernels::uniform(key, 2 * std::uint32_t(r) + 1)},
                                                m_rc.policy.stratify);
        Vec3 wi = normalize(tu * l.x + tv * l.y + ns * l.z);
        if (dot(wi, ng) <= 0) {
            // Below the geometric surface (shading normals): the stratum counts as dark,
            // as it does in the film's gathers (weight albedo / (M N), no ray).
            if (request) request->rays.fetch_add(1, std::memory_order_relaxed);
            continue;
        }
        // In the prepass the sample is the stratum (the gradients' layout).
        pushGatherRay(ctx.out(kGatherRay), origin, wi, target,
                      prepass ? std::uint32_t(r) : b.sample[i], weight,
                      kernels::hashCombine(key, std::uint64_t(r)), b.depth[i], flags,
                      prepass ? recordLambdaU(recordU, r, strata) : b.lambdaU[i]);
        ++spawned;
    }
    return spawned;
}

void GatherStage::spawn(const RayBatch& b, const HitList& hits, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, kGatherStageId);
    const GiData& gi = m_gi;
    const GiSettings& s = gi.settings;
    // A record's gather in the prepass; in a render pass a film gather (filmGatherRays).
    const bool prepass = m_requests != nullptr;
    const int thetaCount = prepass ? gi.gatherTheta : gi.filmGatherTheta;
    const int phiCount = prepass ? gi.gatherPhi : gi.filmGatherPhi;
    std::uint64_t spawned = 0;
    LaneShading wl(m_rc.spectral);
    for (int k = 0; k < hits.count; ++k) {
        int i = hits.lane[k];
        const SurfaceHit& h = hits.hit[k];
        Vec3 wo = -laneDirection(b, i);
        wl.select(b.lambdaU[i]);
        // The diffuse albedo (textured; in spectral mode at the lane's wavelengths, which the
        // estimates below are expressed at: the reflectance is applied per wavelength);
        // pbrt-v4's diffuse-like materials count as Lambertian here, a coated one with its
        // diffuse lobe's albedo seen from wo.
        const Vec3 albedo = kernels::lambertianAlbedo(
            bsdfAt(m_rc.scene, h.material, h, 0, wl.shading()), wo, h.ng, h.ns);
        Vec3 w = laneThroughput(b, i);
        Vec3 reflect = w * albedo * kInvPi; // Lambertian: L = albedo / pi * E
        auto add = [&](const Vec3& e) { addReflected(b, i, reflect, e, wl.lane(), stats); };
        Vec3 ng, ns;
        facingNormals(h, wo, ng, ns);
        bool firstDiffuse = visiblePoint(b.flags[i]);
        // Past dispersive glass the point depends on the path's one wavelength (not on a
        // dispersive coat reached with all: HitList::arrivedWhole).
        const bool oneWavelength = std::signbit(b.lambdaU[i]) && !hits.arrivedWhole[k];

        if (!firstDiffuse) {
            ++giCounter(stats, kGiGlobalLookups);
            add(mapIrradiance(gi.global, h.p, ns));
            continue;
        }
        if (s.debugView == GiDebugView::Photons) {
            // The maps themselves at the first diffuse hit: the global map's estimate of all
            // light reflected there (direct included) plus the caustic map's.
            ++giCounter(stats, kGiGlobalLookups);
            Vec3 e = gi.global && gi.global->size() > 0
                         ? gi.global->irradiance(h.p, ns, s.globalK, gi.globalRadius)
                         : Vec3(0.0f);
            e += causticIrradiance(h.p, ns, b.pixel[i]);
            add(rgbOf(e));
            continue;
        }
        if (!prepass && s.caustics && gi.caustic && gi.caustic->size() > 0 &&
            (s.debugView == GiDebugView::None || s.debugView == GiDebugView::Caustics ||
             s.debugView == GiDebugView::IcRecords)) {
            ++giCounter(stats, kGiCausticLookups);
            if (oneWavelength && gi.caustic->hasWavelengths())
                addReflectedLight(b, i, reflect,
                                  causticLightOfOneWavelength(h.p, ns, b.pixel[i], wl.lane()),
                                  wl.lane(), stats);
            else
                add(rgbOf(causticIrradiance(h.p, ns, b.pixel[i])));
        }
        if (s.debugView == GiDebugView::Caustics) continue;
        // A path that dispersive glass left one wavelength sees, through the glass, a point
        // that depends on that wavelength, and needs that wavelength's irradiance there. A
        // record holds irradiance of every wavelength (its rays spread over the spectrum),
        // whose spectrum at the point differs per wavelength behind dispersive glass, and
        // taking it at the path's own wavelength biased the colour (docs/spectral.md,
        // "Dispersion"): such a visible point gathers at its own wavelength instead.
        if (gi.cache && (prepass || !oneWavelength)) {
            ++giCounter(stats, kGiCacheLookups);
            IrradianceCache::LookupResult r;
            if (gi.cache->lookup(h.p, ns, r)) {
                ++giCounter(stats, kGiCacheHits);
                if (!prepass) add(r.irradiance);
                continue;
            }
        }
        spawned += spawnFinalGather(b, i, h, ng, ns, w * albedo, prepass, thetaCount, phiCount,
                                    ctx);
    }
    stats.stages[int(kGatherStageId)].raysOut += spawned;
}

// The radiance gather ray i finds at its hit, added to `radiance` (before its throughput),
// the hit's distance, and its specular continuation; whether the ray goes on.
bool GatherStage::shadeHit(RayBatch& b, int i, LaneShading& wl, Vec3& radiance, float& distance,
                           std::uint64_t& spawned, StageContext& ctx) const {
    ThreadStats& stats = *ctx.stats;
    const GiData& gi = m_gi;
    const int maxSpecular = std::max(0, gi.settings.maxDepth);
    const bool sampleLights = gi.globalIndirect != nullptr; // GiSettings::gatherDirect
    const bool pastGlossy = (b.flags[i] & kFlagPastGlossy) != 0;
    Vec3 o{b.ox[i], b.oy[i], b.oz[i]}, d = laneDirection(b, i);
    SurfaceHit h =
        m_rc.accel.surface(b.instId[i], b.geomId[i], b.primId[i], b.u[i], b.v[i], o, d, b.t[i]);
    // From the hit point, not Embree's t: t of a sphere differs by an ulp between
    // packet widths, and the cache's record radii must not (determinism).
    distance = length(h.p - o);
    if (pastGlossy && !gi.roughCaustics)
        radiance += emissionAt(emittedRadiance(*h.shape, h.ng, -d),
                               m_rc.spectral ? m_rc.lights.indexOf(h.shape, h.instance) : -1,
                               h.shape, wl.lane());
    resolveShading(m_rc.scene, h, -d);
    // A dispersive material (a coat's): the hero alone from here on (docs/spectral.md).
    wl.select(b.lambdaU[i], m_rc.scene, h.material);
    b.lambdaU[i] = wl.u();
    // Emitters are light sampled at the gather's origin, and light reaching it through
    // specular surfaces (a coat's reflection included) straight from an emitter is the
    // caustic map's: neither is added here. At a diffuse surface the global map gives
    // the diffuse reflected radiance (a coated one's base); at an opaque glossy one its
    // radiance estimate with the BSDF (Jensen's; a glossy lobe taken as Lambertian
    // misplaces the light, and traced on it made the irradiance cache's records noisy:
    // a record's few rays that find a light through the lobe). A coat's own reflection,
    // a mirror, glass and rough glass continue the ray by one sample of the lobe (as
    // path mode does), so light along L ... D S+ D paths is not lost.
    const MaterialClass cls = materialClass(m_rc.scene.materials, h.material);
    const bool coated = m_rc.scene.materials[h.material].type == MaterialType::CoatedDiffuse;
    kernels::BsdfParams bsdf =
        bsdfAt(m_rc.scene, h.material, h, kernels::hashCombine(b.rngKey[i], 43), wl.shading());
    const bool transmits = kernels::hasTransmission(bsdf);
    Vec3 ng, ns;
    facingNormals(h, -d, ng, ns);
    if (cls == MaterialClass::Diffuse) {
        ++giCounter(stats, kGiGlobalLookups);
        // The Lambertian BSDF value albedo / pi, times irradiance.
        const Vec3 f = kernels::lambertianAlbedo(bsdf, -d, h.ng, h.ns) * kInvPi;
        radiance += f * lightAt(mapIrradiance(sampleLights ? gi.globalIndirect : gi.global,
                                              h.p, ns),
                                wl.lane());
        if (sampleLights)
            spawned += sampleDirect(b, i, h, ng, ns, laneThroughput(b, i) * f, wl.lane(), ctx);
    } else if (cls == MaterialClass::Glossy && !transmits) {
        ++giCounter(stats, kGiGlobalLookups);
        radiance += glossyRadiance(bsdf, h, -d, ns, &wl.lane());
    }
    const bool continues = cls == MaterialClass::Specular || coated ||
                           (cls == MaterialClass::Glossy && transmits);
    if (continues && b.specularDepth[i] < maxSpecular) {
        Vec2 u{kernels::uniform(b.rngKey[i], 40), kernels::uniform(b.rngKey[i], 41)};
        kernels::BsdfSample smp =
            coated ? kernels::sampleCoatReflection(bsdf, -d, h.ng, h.ns, u)
                   : kernels::sampleBsdf(bsdf, -d, h.ng, h.ns, u,
                                         kernels::uniform(b.rngKey[i], 42));
        Vec3 next =
            laneThroughput(b, i) * smp.weight * basicRadianceScale(bsdf, -d, h.ng, smp);
        // Russian roulette by the bounce's reflectance: a coat reflects a few percent,
        // and chains between coated surfaces (a coated floor under coated plastic) ran to
        // the depth limit, most of gi's gather rays for almost nothing. Survivors are
        // reweighted (unbiased); mirrors and glass (weight ~1) always go on.
        float q = std::min(1.0f, maxComponent(smp.weight));
        if (smp.valid && m_rc.policy.rouletteEnabled && q < 1.0f) {
            if (!(q > 0) || kernels::uniform(b.rngKey[i], 44) >= q) smp.valid = false;
            else next = next / q;
        }
        if (smp.valid && !isBlack(next) && isFinite(next)) {
            std::uint8_t flags = b.flags[i];
            if (cls == MaterialClass::Glossy) flags |= kFlagPastGlossy;
            spawnRay(ctx.out(kGatherRay), b, i, offsetRayOrigin(h, h.ng, smp.wi), smp.wi, next,
                     b.depth[i], std::uint8_t(b.specularDepth[i] + 1), flags, 7, wl.u());
            ++spawned;
            return true;
        }
    }
    return false;
}

// A record's gather ray ended its segment (`done`: and its chain): Ward's distance, the
// stratum's distance for the gradients, the record's ray count.
void GatherStage::recordGatherEnd(const RayBatch& b, int i, float distance, bool done) const {
    IcRequest& rq = (*m_requests)[b.pixel[i]];
    std::uint32_t stratum = b.sample[i];
    if (b.specularDepth[i] == 0) { // the stratum's first segment
        // Ward's R_i: the harmonic mean of the first hits' distances.
        if (std::isfinite(distance) && distance > 0)
            rq.inverseDistance.fetch_add(std::llround(IcRequest::kScale / double(distance)),
                                         std::memory_order_relaxed);
        if (stratum < rq.strataDistance.size()) rq.strataDistance[stratum] = distance;
    }
    if (done) rq.rays.fetch_add(1, std::memory_order_relaxed);
}

void GatherStage::retrace(RayBatch& b, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, kGatherStageId);
    stats.stages[int(kGatherStageId)].raysIn += std::uint64_t(b.count);
    std::uint64_t spawned = 0;
    LaneShading wl(m_rc.spectral); // spectral mode: each ray's wavelengths
    for (int i = 0; i < b.count; ++i) {
        wl.select(b.lambdaU[i]);
        Vec3 radiance(0.0f); // reaching the ray's origin from this hit, before the throughput
        float distance = kInfinity;
        bool done = true;
        const bool pastGlossy = (b.flags[i] & kFlagPastGlossy) != 0;
        if (b.hit(i)) {
            done = !shadeHit(b, i, wl, radiance, distance, spawned, ctx);
        } else if (pastGlossy && !m_gi.roughCaustics && m_rc.lights.hasEnvironment()) {
            radiance = emissionAt(m_rc.lights.environment.radiance(laneDirection(b, i)), -1,
                                  nullptr, wl.lane());
        }
        deposit(b, i, laneThroughput(b, i) * radiance, wl.lane(), stats);
        if (b.flags[i] & kFlagGatherRecord) recordGatherEnd(b, i, distance, done);
    }
    stats.stages[int(kGatherStageId)].raysOut += spawned;
}

} // namespace rayproc
