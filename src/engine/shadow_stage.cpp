#include "engine/shadow_stage.h"

#include "engine/glossy_mis.h"
#include "engine/noise_breakdown.h"
#include "engine/material_bsdf.h"
#include "engine/path_state.h"
#include "engine/sample_numbers.h"
#include "kernels/bsdf.h"
#include "kernels/bsdf_sampling.h"
#include "kernels/sampling.h"

namespace rayproc {

namespace {

// The shadow stage's pairs of dimensions (SampleNumbers): a light's position per light
// (kDimLightPosition + 2 x its stream), the choice among area lights, the sky's direction and
// the cosine-sampled MIS ray's.
enum ShadowDim : std::uint32_t { kDimChoice = 100, kDimSky = 102, kDimMisRay = 104,
                                 kDimLightPosition = 106 };

// BSDF value times the cosine at the receiver (kernels::evalBsdf, as path mode evaluates it:
// nothing on the far side of the geometric surface, so a shading normal cannot let light
// through it).
Vec3 evalCos(const kernels::BsdfParams& bsdf, const SurfaceHit& h, const Vec3& wo,
             const Vec3& wi) {
    float pdf;
    return kernels::evalBsdf(bsdf, wo, wi, h.ng, h.ns, pdf);
}

// One hit as its light samples see it: the BSDF in the facing frame, the path's throughput and
// how each sample's contribution shares the BSDF with the rays other stages spawn.
struct ShadedHit {
    const SurfaceHit& h;
    kernels::BsdfParams bsdf;
    Vec3 wo{}, ng{}, ns{}, w{};
    bool transmits = false;
    // The reflection stage samples this hit's glossy lobe too (past the depth limit a ray that
    // only collects emission): light samples take their MIS share of it (engine/glossy_mis.h).
    bool mis = false;
    // The rest of the BSDF, the part the reflection stage does not sample (a diffuse surface
    // whole, a coated one's base), is lit from area lights by light samples and by one
    // cosine-sampled ray that collects only emission (spawnMisRay), combined by the power
    // heuristic (ShadingPolicy::diffuseMis): the light samples keep the light where it is small
    // or far, the ray takes over where the surface is so close to a light that a sample's
    // 1 / distance^2 would be a firefly. Glossy classes have no rest: the reflection stage
    // samples their whole BSDF.
    bool diffuseMis = false;
    MaterialClass cls = MaterialClass::Diffuse;

    // A light sample through a transmitting surface leaves from its other side.
    Vec3 side(const Vec3& wi) const { return dot(wi, ng) > 0 ? ng : -ng; }
    float cosinePdf(const Vec3& wi) const { return std::max(0.0f, dot(wi, ns)) * kInvPi; }

    // f |cos| split into the sampled lobe and the rest (each channel non-negative against
    // rounding and the stochastic estimates of random-walk coats).
    Vec3 split(const Vec3& wi, Vec3& lobe, float& lobePdf) const {
        Vec3 f = evalCos(bsdf, h, wo, wi);
        lobe = kernels::sampledLobeEvalCos(bsdf, wo, wi, h.ng, h.ns, lobePdf);
        if (!(lobePdf > 0)) lobe = Vec3(0.0f);
        Vec3 r = f - lobe;
        return Vec3(std::max(r.x, 0.0f), std::max(r.y, 0.0f), std::max(r.z, 0.0f));
    }

    // f |cos| for a light sample of density lightPdf, each part weighted by its MIS share.
    Vec3 shaded(const Vec3& wi, float lightPdf, bool areaLight = false) const {
        const bool restMis = diffuseMis && areaLight;
        if (!mis && !restMis) return evalCos(bsdf, h, wo, wi);
        Vec3 lobe;
        float lobePdf = 0;
        Vec3 rest = split(wi, lobe, lobePdf);
        if (restMis) rest = rest * kernels::powerHeuristic(lightPdf, cosinePdf(wi));
        if (mis && lobePdf > 0) lobe = lobe * kernels::powerHeuristic(lightPdf, lobePdf);
        return rest + lobe;
    }
};

// The shadow rays (and diffuse MIS rays) of one parent batch, hit by hit.
class ShadowSpawner {
public:
    ShadowSpawner(const RenderContext& rc, const RayBatch& b, StageContext& ctx)
        : m_rc(rc), m_b(b), m_ctx(ctx), m_lights(rc.lights), m_policy(rc.policy),
          m_choose(choosesLights(rc.policy, rc.lights)), m_seedKey(sampleSeedKey(rc.seed)) {}

    void spawnAt(int i, const SurfaceHit& h) {
        m_wl.select(m_b.lambdaU[i]); // the surface stage marked a dispersive hit's lane
        const ShadedHit s = shadedHit(i, h);
        // Sobol points over the pixel's samples, a hit's n samples of a kind an aligned block
        // of n of them (SampleNumbers::get2D(dim, s, n)).
        const SampleNumbers numbers(m_b, i, m_policy.stratify, m_seedKey,
                                    1 + std::uint32_t(m_b.kind));
        sampleLights(i, s, numbers);
        if (s.diffuseMis) spawnMisRay(i, s, numbers);
        sampleSky(i, s, numbers);
    }

    std::uint64_t spawned() const { return m_spawned; }

private:
    ShadedHit shadedHit(int i, const SurfaceHit& h) const {
        // The BSDF built in place (no copy of its parameters per hit).
        ShadedHit s{.h = h,
                    .bsdf = bsdfAt(m_rc.scene, h.material, h,
                                   kernels::hashCombine(m_b.rngKey[i], kDimLightBase - 2),
                                   m_wl.shading()),
                    .wo = -laneDirection(m_b, i)};
        facingNormals(h, s.wo, s.ng, s.ns);
        s.w = laneThroughput(m_b, i);
        s.transmits = kernels::hasTransmission(s.bsdf);
        s.mis = m_policy.glossyMis;
        s.cls = materialClass(m_rc.scene.materials, h.material);
        s.diffuseMis = m_policy.diffuseMis && m_lights.hasAreaLights() && !s.transmits &&
                       s.cls != MaterialClass::Glossy;
        return s;
    }

    void emitShadow(int i, const SurfaceHit& h, const Vec3& ng, const Vec3& wi,
                    const LightSample* light, const Vec3& contribution) {
        spawnShadowRay(m_ctx.outShadow(RayKind::Shadow), m_b, i, h, ng, wi, light, contribution,
                       m_wl.u());
        ++m_spawned;
    }

    // The area and delta lights' samples.
    void sampleLights(int i, const ShadedHit& s, const SampleNumbers& numbers) {
        if (m_choose) {
            // n samples per area light that matters here, each picking one with the area
            // lights' LightSampler; delta lights take one each below.
            int n = m_lights.areaSamples(s.h.p, m_policy.lightSamples);
            for (int k = 0; k < n; ++k) {
                float u = numbers.get2D(kDimChoice, std::uint32_t(k), std::uint32_t(n)).x;
                LightSampler::Pick pick = m_lights.areaSampler.sample(s.h.p, u);
                if (pick.pmf > 0)
                    sampleLight(i, s, numbers, m_lights.lights[pick.index], k, n, pick.pmf);
            }
        }
        for (const LightSource& light : m_lights.lights) {
            if (m_choose && !light.delta()) continue;
            // A delta light takes one sample and no random numbers.
            int n = lightSampleCount(m_policy, light);
            for (int k = 0; k < n; ++k) sampleLight(i, s, numbers, light, k, n, 1.0f);
        }
    }

    // Sample k of n on `light`, which a sample picks with probability `chosen`. Inlined into
    // both loops of sampleLights, as the lambda it was: each loop keeps its own branches
    // (callgrind's branch simulation, raytrace Cornell box: 14% fewer mispredictions in this
    // stage than with one shared out-of-line copy).
    [[gnu::always_inline]] void sampleLight(int i, const ShadedHit& s, const SampleNumbers& numbers,
                     const LightSource& light, int k, int n, float chosen) {
        Vec2 u = light.delta() ? Vec2{0.5f, 0.5f}
                               : numbers.get2D(kDimLightPosition + 2 * light.stream,
                                               std::uint32_t(k), std::uint32_t(n));
        LightSample ls = light.sample(s.h.p, u);
        if (!ls.valid || (dot(ls.wi, s.ng) <= 0 && !s.transmits)) return;
        float expected = float(n) * chosen; // this light's expected samples here
        float lightPdf = light.delta() ? kInfinity : expected * ls.pdf;
        if (m_rc.spectral)
            ls.weight = m_rc.spectral->lightValue(std::size_t(&light - m_lights.lights.data()),
                                                  ls.weight, m_wl.lane());
        Vec3 c = s.w * s.shaded(ls.wi, lightPdf, !light.delta()) * ls.weight / expected;
        if (isBlack(c)) return;
        emitShadow(i, s.h, s.side(ls.wi), ls.wi, &ls, c);
    }

    // The rest's MIS partner: one cosine-sampled ray that adds only the emission it meets,
    // weighted by the surface stage (reflectionEmissionWeight); the sky stays the sky
    // samples' alone.
    void spawnMisRay(int i, const ShadedHit& s, const SampleNumbers& numbers) {
        Vec3 local = kernels::cosineHemisphere(numbers.get2D(kDimMisRay));
        Vec3 wi = normalize(kernels::toWorld(local, s.ns));
        float pdf = s.cosinePdf(wi);
        Vec3 lobe;
        float lobePdf = 0;
        Vec3 rest = dot(wi, s.ng) > 0 && pdf > 0 ? s.split(wi, lobe, lobePdf) : Vec3(0.0f);
        Vec3 weight = s.w * rest / std::max(pdf, 1e-20f);
        if (isBlack(weight) || !isFinite(weight)) return;
        RayBatch& out = m_ctx.out(RayKind::Reflection);
        spawnRay(out, m_b, i, offsetRayOrigin(s.h, s.ng, wi), wi, weight,
                 std::uint8_t(std::min(int(m_b.depth[i]) + 1, 255)), m_b.specularDepth[i],
                 std::uint8_t(kFlagMisEmission | kFlagEmissionOnly), 0x4d, m_wl.u());
        out.prevPdf[out.count - 1] = pdf;
        out.prevCos[out.count - 1] = dot(wi, s.ns);
        ++m_spawned;
    }

    // The sky lights diffuse surfaces through its samples (cosine-weighted for a constant
    // sky, by luminance for an image: a sun). A glossy lobe's reflection ray sees the sky
    // too: with glossy MIS both count, by their weights; without, the glossy lobe takes the
    // sky from its reflection ray alone.
    void sampleSky(int i, const ShadedHit& s, const SampleNumbers& numbers) {
        if (!m_lights.hasEnvironment() ||
            !(s.cls == MaterialClass::Diffuse || m_policy.ambientEnvironment ||
              (m_policy.glossyMis && s.cls == MaterialClass::Glossy)))
            return;
        if (m_policy.ambientEnvironment) {
            // Preview: unshadowed sky light, the cosine-weighted integral of the BSDF.
            Vec3 sky = m_lights.environment.average();
            if (!m_rc.spectral) {
                m_rc.film.add(m_b.pixel[i], s.w * s.bsdf.color * sky, *m_ctx.stats);
                return;
            }
            sky = m_rc.spectral->sky(sky, m_wl.lane());
            m_rc.film.add(m_b.pixel[i], m_rc.spectral->toFilm(s.w * s.bsdf.color * sky, m_wl.lane()),
                          *m_ctx.stats);
            return;
        }
        int n = m_policy.lightSamples;
        for (int k = 0; k < n; ++k) {
            Vec2 u = numbers.get2D(kDimSky, std::uint32_t(k), std::uint32_t(n));
            EnvironmentSample es = m_lights.environment.sample(u, s.ns);
            Vec3 wi = es.wi;
            if (!es.valid || dot(wi, s.ng) <= 0) continue;
            if (m_rc.spectral) es.weight = m_rc.spectral->sky(es.weight, m_wl.lane());
            Vec3 c = s.w * s.shaded(wi, float(n) * es.pdf) * es.weight / float(n);
            if (isBlack(c)) continue;
            emitShadow(i, s.h, s.ng, wi, nullptr, c);
        }
    }

    const RenderContext& m_rc;
    const RayBatch& m_b;
    StageContext& m_ctx;
    const LightSet& m_lights;
    const ShadingPolicy& m_policy;
    const bool m_choose;
    const std::uint64_t m_seedKey;
    std::uint64_t m_spawned = 0;
    // Spectral mode: the current hit's lane's wavelengths.
    LaneShading m_wl{m_rc.spectral};
};

} // namespace

void ShadowStage::spawn(const RayBatch& b, const HitList& hits, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::Shadow);
    ShadowSpawner spawner(m_rc, b, ctx);
    for (int k = 0; k < hits.count; ++k) spawner.spawnAt(hits.lane[k], hits.hit[k]);
    stats.stages[int(StageId::Shadow)].raysOut += spawner.spawned();
}

void ShadowStage::retraceShadows(ShadowBatch& b, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::Shadow);
    stats.stages[int(StageId::Shadow)].raysIn += std::uint64_t(b.count);
    for (int i = 0; i < b.count; ++i) {
        if (b.occluded(i)) continue;
        Vec3 c = laneThroughput(b, i);
        if (m_rc.spectral) c = m_rc.spectral->toFilm(c, m_rc.spectral->lane(b.lambdaU[i]));
        // Path mode's light samples carry their category (1 + it).
        if (b.category[i] != 0)
            fileContribution(stats, m_rc.noise, m_rc.lights.lights.size(), b.pixel[i],
                             std::size_t(b.category[i] - 1), c, false);
        m_rc.film.add(b.pixel[i], c, stats);
    }
}

} // namespace rayproc
