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

std::uint8_t nextDepth(std::uint8_t d) { return std::uint8_t(std::min(int(d) + 1, 255)); }

// One hit's sampled continuation: direction, throughput, the ray's flags and the pdf MIS
// weighs its emission with (0: none).
struct Bounce {
    Vec3 wi, w;
    std::uint8_t flags;
    float misPdf = 0;
    bool transmitted = false;
};

// The continuations of one parent batch's reflecting hits.
class ReflectionSpawner {
public:
    ReflectionSpawner(const RenderContext& rc, const RayBatch& b, const HitList& hits,
                      StageContext& ctx)
        : m_rc(rc), m_policy(rc.policy), m_b(b), m_hits(hits), m_ctx(ctx),
          m_seedKey(sampleSeedKey(rc.seed)) {}

    void spawnAt(int k) {
        const int i = m_hits.lane[k];
        const SurfaceHit& h = m_hits.hit[k];
        const Material& mat = m_rc.scene.materials[h.material];
        Vec3 wo = -laneDirection(m_b, i);
        Vec3 ng, ns;
        facingNormals(h, wo, ng, ns);
        Bounce r{Vec3(), laneThroughput(m_b, i), m_b.flags[i]};
        // The sampled lobe's numbers: Sobol points over the pixel's samples, as the light
        // samples' at this hit (the same sequence key, other pairs of dimensions).
        const SampleNumbers numbers(m_b, i, m_policy.stratify, m_seedKey,
                                    1 + std::uint32_t(m_b.kind));
        m_wl.select(m_b.lambdaU[i]); // the surface stage marked a dispersive hit's lane
        if (!sampleMaterial(k, h, mat, wo, numbers, r)) return;
        if (r.transmitted) {
            if (!m_policy.refractionStage || !nextRay(i, r)) return;
            RayBatch& out = m_ctx.out(RayKind::Refraction);
            spawnRay(out, m_b, i, offsetRayOrigin(h, -ng, r.wi), r.wi, r.w,
                     nextDepth(m_b.depth[i]), nextDepth(m_b.specularDepth[i]), r.flags, 0,
                     m_wl.u());
            out.prevPdf[out.count - 1] = r.misPdf;
            ++m_spawned;
            return;
        }
        if (!nextRay(i, r)) return;
        RayBatch& out = m_ctx.out(RayKind::Reflection);
        spawnRay(out, m_b, i, offsetRayOrigin(h, ng, r.wi), r.wi, r.w, nextDepth(m_b.depth[i]),
                 nextDepth(m_b.specularDepth[i]), r.flags, 0, m_wl.u());
        out.prevPdf[out.count - 1] = r.misPdf;
        out.prevCos[out.count - 1] = dot(r.wi, ns);
        ++m_spawned;
    }

    std::uint64_t spawned() const { return m_spawned; }

private:
    // One sample of the whole BSDF (kernels::sampleBsdf, as path mode samples it). A delta lobe
    // continues as a mirror does; a glossy lobe's ray (a rough coat's too) sees only the sky and
    // the surfaces it meets (emitters are light sampled); a diffuse-like sample (a coated base,
    // diffuse transmission) ends here (false): the shadow stage gave its direct light and gi's
    // gather its indirect light.
    bool sampleMaterial(int k, const SurfaceHit& h, const Material& mat, const Vec3& wo,
                        const SampleNumbers& numbers, Bounce& r) const {
        const int i = m_hits.lane[k];
        kernels::BsdfParams bsdf =
            bsdfAt(m_rc.scene, h.material, h, kernels::hashCombine(m_b.rngKey[i], kDimReflect),
                   m_wl.shading());
        Vec2 u = numbers.get2D(kDimDirection);
        // A coated surface: its coat's reflection alone, mirror or rough; the shadow
        // stage and gi's gather light its base.
        kernels::BsdfSample s =
            mat.type == MaterialType::CoatedDiffuse
                ? kernels::sampleCoatReflection(bsdf, wo, h.ng, h.ns, u)
                : kernels::sampleBsdf(bsdf, wo, h.ng, h.ns, u, numbers.get2D(kDimLobe).x);
        if (!s.valid) return false;
        if (!s.delta) {
            if (!s.coat && materialClass(m_rc.scene.materials, h.material) != MaterialClass::Glossy)
                return false;
            glossyFlags(k, s.pdf, s.coat, s.transmitted,
                        bsdf.kind == kernels::BsdfKind::Dielectric && !s.coat, r);
        }
        r.wi = s.wi;
        r.w = r.w * s.weight * basicRadianceScale(bsdf, wo, h.ng, s);
        r.transmitted = s.transmitted;
        return true;
    }

    // A glossy (non-delta) sample: emitters and the sky are light sampled, so the ray takes
    // them only by its MIS weight (engine/glossy_mis.h); where no light sample covered them
    // (the shadow stage did not run here) wholly (pdf 0). Without MIS it sees no emitter, and
    // the sky only where the shadow stage's sky samples leave it out (glossy classes; a coat's
    // reflection is in the sky samples of its diffuse class). A transmitted ray's sky is never
    // light sampled (sky samples stay above). A rough dielectric's sample keeps a camera chain
    // a visible chain (kFlagVisibleChain); any other glossy one ends it.
    void glossyFlags(int k, float pdf, bool coat, bool transmitted, bool dielectric,
                     Bounce& r) const {
        const bool lit = m_hits.lightSampled[k];
        const bool visible = dielectric && visiblePoint(r.flags);
        r.flags = std::uint8_t((r.flags & ~(kFlagCountEmission | kFlagVisibleChain)) |
                               kFlagCountEnvironment | (visible ? kFlagVisibleChain : 0));
        if (m_policy.glossyMis || !lit) {
            r.flags |= kFlagMisEmission;
            if (!transmitted) r.flags |= kFlagMisEnvironment;
            r.misPdf = lit ? pdf : 0.0f;
        } else if (coat) {
            r.flags = std::uint8_t(r.flags & ~kFlagCountEnvironment);
        }
    }

    // Whether lane i's sampled ray goes on (Russian roulette reweights w). Past --max-depth a
    // glossy sample the light samples shared by MIS (misPdf > 0) still goes, flagged to collect
    // only the MIS share of the emission or sky it meets: without it the light samples there
    // took the whole lobe, and a near-mirror lobe's rare light sample was a firefly.
    bool nextRay(int i, Bounce& r) const {
        const bool beyond =
            m_b.depth[i] + 1 > m_policy.maxDepth || m_b.specularDepth[i] + 1 > m_policy.maxDepth;
        if (beyond) {
            if (!(r.misPdf > 0)) return false;
            r.flags |= kFlagEmissionOnly;
        }
        return survivesRoulette(m_policy, m_b.rngKey[i], 0, r.w);
    }

    const RenderContext& m_rc;
    const ShadingPolicy& m_policy;
    const RayBatch& m_b;
    const HitList& m_hits;
    StageContext& m_ctx;
    const std::uint64_t m_seedKey;
    std::uint64_t m_spawned = 0;
    // Spectral mode: the current hit's lane's wavelengths.
    LaneShading m_wl{m_rc.spectral};
};

} // namespace

void ReflectionStage::spawn(const RayBatch& b, const HitList& hits, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::Reflection);
    stats.stages[int(StageId::Reflection)].raysIn += std::uint64_t(hits.count);
    ReflectionSpawner spawner(m_rc, b, hits, ctx);
    for (int k = 0; k < hits.count; ++k) spawner.spawnAt(k);
    stats.stages[int(StageId::Reflection)].raysOut += spawner.spawned();
}

} // namespace rayproc
