#include "engine/reflection_stage.h"

#include "engine/material_bsdf.h"
#include "engine/path_state.h"
#include "engine/sample_numbers.h"
#include "kernels/bsdf.h"
#include "kernels/sampling.h"

namespace rayproc {

namespace {
// The reflection stage's pairs of dimensions (SampleNumbers): the lobe's direction, and the
// choice among a BSDF's lobes.
enum ReflectionDim : std::uint32_t { kDimDirection = 90, kDimLobe = 92 };
} // namespace

void ReflectionStage::spawn(const RayBatch& b, const HitList& hits, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::Reflection);
    stats.stages[int(StageId::Reflection)].raysIn += std::uint64_t(hits.count);
    std::uint64_t spawned = 0;
    const ShadingPolicy& policy = m_rc.policy;
    auto nextDepth = [](std::uint8_t d) { return std::uint8_t(std::min(int(d) + 1, 255)); };
    const std::uint64_t seedKey = sampleSeedKey(m_rc.seed);
    // Whether lane i's sampled ray goes on (Russian roulette reweights w). Past --max-depth a
    // glossy sample the light samples shared by MIS (misPdf > 0) still goes, flagged to collect
    // only the MIS share of the emission or sky it meets: without it the light samples there
    // took the whole lobe, and a near-mirror lobe's rare light sample was a firefly.
    auto nextRay = [&](int i, std::uint8_t& flags, float misPdf, Vec3& w) {
        const bool beyond =
            b.depth[i] + 1 > policy.maxDepth || b.specularDepth[i] + 1 > policy.maxDepth;
        if (beyond) {
            if (!(misPdf > 0)) return false;
            flags |= kFlagEmissionOnly;
        }
        return survivesRoulette(policy, b.rngKey[i], 0, w);
    };
    for (int k = 0; k < hits.count; ++k) {
        int i = hits.lane[k];
        const SurfaceHit& h = hits.hit[k];
        const Material& mat = m_rc.scene.materials[h.material];
        Vec3 wo = -laneDirection(b, i);
        Vec3 ng, ns;
        facingNormals(h, wo, ng, ns);
        Vec3 w = laneThroughput(b, i);
        Vec3 wi;
        std::uint8_t flags = b.flags[i];
        // The sampled lobe's numbers: Sobol points over the pixel's samples, as the light
        // samples' at this hit (the same sequence key, other pairs of dimensions).
        const SampleNumbers numbers(b, i, policy.stratify, seedKey, 1 + std::uint32_t(b.kind));
        // A glossy (non-delta) sample: emitters and the sky are light sampled, so the ray
        // takes them only by its MIS weight (engine/glossy_mis.h); where no light sample
        // covered them (the shadow stage did not run here) wholly (pdf 0). Without MIS it sees
        // no emitter, and the sky only where the shadow stage's sky samples leave it out
        // (glossy classes; a coat's reflection is in the sky samples of its diffuse class).
        // A transmitted ray's sky is never light sampled (sky samples stay above).
        float misPdf = 0;
        auto glossyFlags = [&](float pdf, bool coat, bool transmitted) {
            const bool lit = hits.lightSampled[k];
            flags = std::uint8_t((flags & ~kFlagCountEmission) | kFlagCountEnvironment);
            if (m_rc.policy.glossyMis || !lit) {
                flags |= kFlagMisEmission;
                if (!transmitted) flags |= kFlagMisEnvironment;
                misPdf = lit ? pdf : 0.0f;
            } else if (coat) {
                flags = std::uint8_t(flags & ~kFlagCountEnvironment);
            }
        };
        if (mat.type == MaterialType::Mirror) {
            wi = kernels::reflect(wo, ns);
            if (dot(wi, ng) <= 0) wi = kernels::reflect(wo, ng);
            w = w * mat.color;
        } else if (mat.type != MaterialType::Glossy) {
            // pbrt-v4's materials: one sample of the whole BSDF. A delta lobe continues as a
            // mirror does; a glossy lobe's ray (a rough coat's too) sees only the sky and the
            // surfaces it meets (emitters are light sampled);
            // a diffuse-like sample (a coated base, diffuse transmission) ends here: the
            // shadow stage gave its direct light and gi's gather its indirect light.
            kernels::BsdfParams bsdf =
                bsdfAt(m_rc.scene, h.material, h, kernels::hashCombine(b.rngKey[i], kDimReflect));
            Vec2 u = numbers.get2D(kDimDirection);
            // A coated surface: its coat's reflection alone, mirror or rough; the shadow
            // stage and gi's gather light its base.
            kernels::BsdfSample s =
                mat.type == MaterialType::CoatedDiffuse
                    ? kernels::sampleCoatReflection(bsdf, wo, h.ng, h.ns, u)
                    : kernels::sampleBsdf(bsdf, wo, h.ng, h.ns, u, numbers.get2D(kDimLobe).x);
            if (!s.valid) continue;
            if (!s.delta) {
                if (!s.coat && materialClass(m_rc.scene.materials, h.material) != MaterialClass::Glossy)
                    continue;
                glossyFlags(s.pdf, s.coat, s.transmitted);
            }
            wi = s.wi;
            w = w * s.weight * basicRadianceScale(bsdf, wo, h.ng, s);
            if (s.transmitted) {
                if (!m_rc.policy.refractionStage || !nextRay(i, flags, misPdf, w)) continue;
                Vec3 o = offsetRayOrigin(h, -ng, wi);
                RayBatch& out = ctx.out(RayKind::Refraction);
                spawnRay(out, b, i, o, wi, w, nextDepth(b.depth[i]), nextDepth(b.specularDepth[i]),
                         flags, 0);
                out.prevPdf[out.count - 1] = misPdf;
                ++spawned;
                continue;
            }
        } else { // glossy
            float alpha = kernels::ggxAlpha(mat.roughness);
            Vec2 u = numbers.get2D(kDimDirection);
            Vec3 hv = kernels::toWorld(kernels::ggxSampleHalf(u, alpha), ns);
            wi = kernels::reflect(wo, hv);
            float pdf = kernels::glossyPdf(wo, wi, ns, alpha);
            if (pdf <= 0 || dot(wi, ng) <= 0) continue;
            w = w * kernels::glossyEvalCos(wo, wi, ns, mat.color, alpha) / pdf;
            // The shadow stage does not sample the sky for it (see there): the ray sees it.
            glossyFlags(pdf, false, false);
        }
        if (!nextRay(i, flags, misPdf, w)) continue;
        Vec3 o = offsetRayOrigin(h, ng, wi);
        RayBatch& out = ctx.out(RayKind::Reflection);
        spawnRay(out, b, i, o, wi, w, nextDepth(b.depth[i]), nextDepth(b.specularDepth[i]), flags,
                 0);
        out.prevPdf[out.count - 1] = misPdf;
        out.prevCos[out.count - 1] = dot(wi, ns);
        ++spawned;
    }
    stats.stages[int(StageId::Reflection)].raysOut += spawned;
}

} // namespace rayproc
