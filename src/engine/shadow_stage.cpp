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

// BSDF value times the cosine at the receiver, for the materials lit by light sampling:
// rayproc's diffuse and glossy as they always were, pbrt-v4's through the BSDF kernels.
Vec3 evalCos(const Material& m, const kernels::BsdfParams& bsdf, const SurfaceHit& h,
             const Vec3& wo, const Vec3& wi, const Vec3& n) {
    if (m.type != MaterialType::Diffuse && m.type != MaterialType::Glossy) {
        float pdf;
        return kernels::evalBsdf(bsdf, wo, wi, h.ng, h.ns, pdf);
    }
    float c = dot(wi, n);
    if (c <= 0) return Vec3(0.0f);
    if (m.type == MaterialType::Diffuse) return bsdf.color * (c * kInvPi);
    return kernels::glossyEvalCos(wo, wi, n, bsdf.color, kernels::ggxAlpha(m.roughness));
}

} // namespace

void ShadowStage::spawn(const RayBatch& b, const HitList& hits, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::Shadow);
    std::uint64_t spawned = 0;
    const LightSet& lights = m_rc.lights;
    const ShadingPolicy& policy = m_rc.policy;
    const bool choose = choosesLights(policy, lights);
    const bool sobol = policy.stratify;
    const std::uint64_t seedKey = sampleSeedKey(m_rc.seed);
    auto emitShadow = [&](int i, const SurfaceHit& h, const Vec3& ng, const Vec3& wi,
                          const LightSample* light, const Vec3& contribution) {
        spawnShadowRay(ctx.out(RayKind::Shadow), b, i, h, ng, wi, light, contribution);
        ++spawned;
    };

    for (int k = 0; k < hits.count; ++k) {
        int i = hits.lane[k];
        const SurfaceHit& h = hits.hit[k];
        const Material& mat = m_rc.scene.materials[h.material];
        Vec3 wo = -laneDirection(b, i);
        Vec3 ng, ns;
        facingNormals(h, wo, ng, ns);
        Vec3 w = laneThroughput(b, i);
        std::uint64_t key = b.rngKey[i];
        // Sobol points over the pixel's samples, a hit's n samples of a kind an aligned block
        // of n of them (SampleNumbers::get2D(dim, s, n)).
        const SampleNumbers numbers(b, i, sobol, seedKey, 1 + std::uint32_t(b.kind));
        const kernels::BsdfParams bsdf =
            bsdfAt(m_rc.scene, h.material, h, kernels::hashCombine(key, kDimLightBase - 2));
        const bool transmits = kernels::hasTransmission(bsdf);
        // A light sample through a transmitting surface leaves from its other side.
        auto side = [&](const Vec3& wi) { return dot(wi, ng) > 0 ? ng : -ng; };
        // The reflection stage samples this hit's glossy lobe too (past the depth limit a ray
        // that only collects emission): light samples take their MIS share of it
        // (engine/glossy_mis.h).
        const bool mis = policy.glossyMis;
        // The rest of the BSDF, the part the reflection stage does not sample (a diffuse
        // surface whole, a coated one's base), is lit from area lights by light samples and by
        // one cosine-sampled ray that collects only emission (spawned below), combined by the
        // power heuristic (ShadingPolicy::diffuseMis): the light samples keep the light where
        // it is small or far, the ray takes over where the surface is so close to a light that
        // a sample's 1 / distance^2 would be a firefly.
        // Glossy classes have no rest: the reflection stage samples their whole BSDF.
        const MaterialClass cls = materialClass(m_rc.scene.materials, h.material);
        const bool diffuseMis = policy.diffuseMis && lights.hasAreaLights() && !transmits &&
                                cls != MaterialClass::Glossy;
        auto cosinePdf = [&](const Vec3& wi) { return std::max(0.0f, dot(wi, ns)) * kInvPi; };
        // f |cos| split into the sampled lobe and the rest (each channel non-negative against
        // rounding and the stochastic estimates of random-walk coats).
        auto split = [&](const Vec3& wi, Vec3& lobe, float& lobePdf) {
            Vec3 f = evalCos(mat, bsdf, h, wo, wi, ns);
            lobe = kernels::sampledLobeEvalCos(bsdf, wo, wi, h.ng, h.ns, lobePdf);
            if (!(lobePdf > 0)) lobe = Vec3(0.0f);
            Vec3 r = f - lobe;
            return Vec3(std::max(r.x, 0.0f), std::max(r.y, 0.0f), std::max(r.z, 0.0f));
        };
        auto shaded = [&](const Vec3& wi, float lightPdf, bool areaLight = false) {
            const bool restMis = diffuseMis && areaLight;
            if (!mis && !restMis) return evalCos(mat, bsdf, h, wo, wi, ns);
            Vec3 lobe;
            float lobePdf = 0;
            Vec3 rest = split(wi, lobe, lobePdf);
            if (restMis) rest = rest * kernels::powerHeuristic(lightPdf, cosinePdf(wi));
            if (mis && lobePdf > 0) lobe = lobe * kernels::powerHeuristic(lightPdf, lobePdf);
            return rest + lobe;
        };

        // Sample s of n on `light`, which a sample picks with probability `chosen`.
        auto sampleLight = [&](const LightSource& light, int s, int n, float chosen) {
            Vec2 u = light.delta() ? Vec2{0.5f, 0.5f}
                                   : numbers.get2D(kDimLightPosition + 2 * light.stream,
                                                   std::uint32_t(s), std::uint32_t(n));
            LightSample ls = light.sample(h.p, u);
            if (!ls.valid || (dot(ls.wi, ng) <= 0 && !transmits)) return;
            float expected = float(n) * chosen; // this light's expected samples here
            float lightPdf = light.delta() ? kInfinity : expected * ls.pdf;
            Vec3 c = w * shaded(ls.wi, lightPdf, !light.delta()) * ls.weight / expected;
            if (isBlack(c)) return;
            emitShadow(i, h, side(ls.wi), ls.wi, &ls, c);
        };
        if (choose) {
            // n samples per area light that matters here, each picking one with the area
            // lights' LightSampler; delta lights take one each below.
            int n = lights.areaSamples(h.p, policy.lightSamples);
            for (int s = 0; s < n; ++s) {
                float u = numbers.get2D(kDimChoice, std::uint32_t(s), std::uint32_t(n)).x;
                LightSampler::Pick pick = lights.areaSampler.sample(h.p, u);
                if (pick.pmf > 0) sampleLight(lights.lights[pick.index], s, n, pick.pmf);
            }
        }
        for (const LightSource& light : lights.lights) {
            if (choose && !light.delta()) continue;
            // A delta light takes one sample and no random numbers.
            int n = lightSampleCount(policy, light);
            for (int s = 0; s < n; ++s) sampleLight(light, s, n, 1.0f);
        }

        // The rest's MIS partner: one cosine-sampled ray that adds only the emission it meets,
        // weighted by the surface stage (reflectionEmissionWeight); the sky stays the sky
        // samples' alone.
        if (diffuseMis) {
            Vec3 local = kernels::cosineHemisphere(numbers.get2D(kDimMisRay));
            Vec3 wi = normalize(kernels::toWorld(local, ns));
            float pdf = cosinePdf(wi);
            Vec3 lobe;
            float lobePdf = 0;
            Vec3 rest = dot(wi, ng) > 0 && pdf > 0 ? split(wi, lobe, lobePdf) : Vec3(0.0f);
            Vec3 weight = w * rest / std::max(pdf, 1e-20f);
            if (!isBlack(weight) && isFinite(weight)) {
                RayBatch& out = ctx.out(RayKind::Reflection);
                spawnRay(out, b, i, offsetRayOrigin(h, ng, wi), wi, weight,
                         std::uint8_t(std::min(int(b.depth[i]) + 1, 255)), b.specularDepth[i],
                         std::uint8_t(kFlagMisEmission | kFlagEmissionOnly), 0x4d);
                out.prevPdf[out.count - 1] = pdf;
                out.prevCos[out.count - 1] = dot(wi, ns);
                ++spawned;
            }
        }

        // The sky lights diffuse surfaces through its samples (cosine-weighted for a constant
        // sky, by luminance for an image: a sun). A glossy lobe's reflection ray sees the sky
        // too: with glossy MIS both count, by their weights; without, the glossy lobe takes the
        // sky from its reflection ray alone.
        if (lights.hasEnvironment() &&
            (cls == MaterialClass::Diffuse || policy.ambientEnvironment ||
             (policy.glossyMis && cls == MaterialClass::Glossy))) {
            if (policy.ambientEnvironment) {
                // Preview: unshadowed sky light, the cosine-weighted integral of the BSDF.
                m_rc.film.add(b.pixel[i], w * bsdf.color * lights.environment.average(), stats);
                continue;
            }
            int n = policy.lightSamples;
            for (int s = 0; s < n; ++s) {
                Vec2 u = numbers.get2D(kDimSky, std::uint32_t(s), std::uint32_t(n));
                EnvironmentSample es = lights.environment.sample(u, ns);
                Vec3 wi = es.wi;
                if (!es.valid || dot(wi, ng) <= 0) continue;
                Vec3 c = w * shaded(wi, float(n) * es.pdf) * es.weight / float(n);
                if (isBlack(c)) continue;
                emitShadow(i, h, ng, wi, nullptr, c);
            }
        }
    }
    stats.stages[int(StageId::Shadow)].raysOut += spawned;
}

void ShadowStage::retrace(RayBatch& b, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::Shadow);
    stats.stages[int(StageId::Shadow)].raysIn += std::uint64_t(b.count);
    for (int i = 0; i < b.count; ++i) {
        if (b.occluded(i)) continue;
        // Path mode's light samples carry their category (1 + it) in the key they do not use.
        if (b.rngKey[i] != 0)
            fileContribution(stats, m_rc.noise, m_rc.lights.lights.size(), b.pixel[i],
                             std::size_t(b.rngKey[i] - 1), luminance(laneThroughput(b, i)),
                             false);
        m_rc.film.add(b.pixel[i], laneThroughput(b, i), stats);
    }
}

} // namespace rayproc
