#include "engine/path_stage.h"

#include "engine/path_state.h"
#include "engine/material_bsdf.h"
#include "kernels/bsdf_sampling.h"
#include "kernels/sampling.h"

namespace rayproc {

namespace {


// Random dimensions of one path vertex.
enum PathDim : std::uint32_t { kDimLightPick = 20, kDimLight = 21, kDimBsdf = 23, kDimLobe = 25,
                               kDimRr = 26, kDimLayered = 27 };

// Two numbers for dimension pair `dim` of a lane: at the first hit they are stratified over
// the pixel's samples (padded: each pair has its own permutation), deeper they are independent.
Vec2 sample2D(const RayBatch& b, int i, std::uint32_t dim, int spp, std::uint64_t seed) {
    if (b.depth[i] == 0 && spp > 0) { // spp 0: --no-stratification
        std::uint64_t key = kernels::hashCombine(kernels::pathKey(seed, b.pixel[i], 0xfffffffeu), dim);
        return kernels::groupStratified2D(b.sample[i], std::uint32_t(spp), key);
    }
    return {kernels::uniform(b.rngKey[i], dim), kernels::uniform(b.rngKey[i], dim + 1)};
}

} // namespace

bool sampleOneLight(const LightSet& lights, const RayBatch& b, int i, const SurfaceHit& h,
                    const kernels::BsdfParams& bsdf, const Vec3& wo, const Vec3& w, Vec2 u,
                    float up, bool areaLightsOnly, RayBatch& out) {
    const std::size_t choices = lights.choiceCount();
    if (choices == 0) return false;
    const float pickPdf = 1.0f / float(choices);
    std::size_t pick = std::min(std::size_t(up * float(choices)), choices - 1);
    Vec3 fg, fs;
    kernels::facingSide(wo, h.ng, h.ns, fg, fs);
    Vec3 wi;
    float lightPdf = 0;
    Vec3 li;
    bool deltaLight = false;
    LightSample ls;
    if (pick < lights.lights.size()) {
        if (areaLightsOnly && lights.lights[pick].delta()) return false;
        ls = lights.lights[pick].sample(h.p, u);
        if (ls.valid) {
            wi = ls.wi;
            lightPdf = ls.pdf;
            deltaLight = lights.lights[pick].delta();
            li = ls.weight; // radiance / pdf, or irradiance for delta lights
        }
    } else {
        if (areaLightsOnly) return false;
        EnvironmentSample es = lights.environment.sample(u, fs);
        if (es.valid) {
            wi = es.wi;
            lightPdf = es.pdf;
            li = es.weight;
        }
    }
    const bool transmissive = kernels::hasTransmission(bsdf);
    if (!(lightPdf > 0 || deltaLight) || !(dot(wi, fg) > 0 || transmissive)) return false;
    float bsdfPdf;
    Vec3 f = kernels::evalBsdf(bsdf, wo, wi, h.ng, h.ns, bsdfPdf);
    // At the last vertex too a BSDF ray follows, to collect its share.
    float mis = deltaLight ? 1.0f : kernels::powerHeuristic(pickPdf * lightPdf, bsdfPdf);
    Vec3 c = w * f * li * (mis / pickPdf);
    if (isBlack(c)) return false;
    // A transmitted light sample leaves from the other side.
    Vec3 side = dot(wi, fg) > 0 ? fg : -fg;
    spawnShadowRay(out, b, i, h, side, wi, ls.valid ? &ls : nullptr, c);
    return true;
}

Bounce spawnBounce(const ShadingPolicy& policy, const RayBatch& b, int i, const SurfaceHit& h,
                   const kernels::BsdfParams& bsdf, const Vec3& wo, const Vec3& w, Vec2 u,
                   float uc, float ur, std::uint8_t flags, const PathStage::Outputs& outputs,
                   std::uint32_t branch, StageContext& ctx) {
    kernels::BsdfSample bs = kernels::sampleBsdf(bsdf, wo, h.ng, h.ns, u, uc);
    if (!bs.valid) return Bounce::None;
    Vec3 wn = w * bs.weight;
    int depth = b.depth[i] + 1;
    if (!(maxComponent(wn) > 0)) return Bounce::None;
    // Past the last vertex a non-delta sample goes on only to add the MIS share of the
    // emission or sky it finds (as pbrt-v4's path integrator counts it), so the last
    // vertex's light sample need not take the whole weight: a near-mirror lobe's rare
    // light sample was a firefly there.
    if (depth > policy.maxDepth) {
        if (bs.delta) return Bounce::None;
        flags |= kFlagEmissionOnly;
    }
    if (policy.rouletteEnabled && depth > policy.rrStartDepth) {
        // Survival = the throughput itself (at most 1): survivors' weights come back to
        // ~1 and stay bounded. A cap below 1 (it was 0.95) let them grow by a/0.95 per
        // bounce where the albedo a > 0.95 (tests/stress/degenerate_test.cpp, [energy]).
        float q = std::min(1.0f, maxComponent(wn));
        if (ur >= q) return Bounce::None;
        wn = wn / q;
    }
    Vec3 fg, fs;
    kernels::facingSide(wo, h.ng, h.ns, fg, fs);
    Vec3 no = offsetRayOrigin(h, h.ng, bs.wi);
    RayBatch& out = ctx.out(bs.transmitted ? outputs.transmitted : outputs.reflected);
    spawnRay(out, b, i, no, bs.wi, wn, std::uint8_t(std::min(depth, 255)),
             std::uint8_t(std::min(b.specularDepth[i] + (bs.delta ? 1 : 0), 255)), flags, branch);
    int j = out.count - 1;
    // For the MIS weight of the light the ray finds against this vertex's light sample.
    out.prevPdf[j] = bs.delta ? 0.0f : bs.pdf;
    out.prevCos[j] = bs.transmitted ? 0.0f : dot(bs.wi, fs);
    return bs.transmitted ? Bounce::Transmitted : Bounce::Reflected;
}

void PathStage::retrace(RayBatch& b, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::Surface);
    stats.stages[int(StageId::Surface)].raysIn += std::uint64_t(b.count);
    const LightSet& lights = m_rc.lights;
    const ShadingPolicy& policy = m_rc.policy;
    const std::size_t choices = lights.choiceCount();
    const float pickPdf = choices > 0 ? 1.0f / float(choices) : 0.0f;
    const int strata = policy.stratify ? policy.sppTotal : 0;
    std::uint64_t shadowOut = 0, reflectOut = 0, refractOut = 0;

    for (int i = 0; i < b.count; ++i) {
        Vec3 w = laneThroughput(b, i);
        Vec3 o{b.ox[i], b.oy[i], b.oz[i]}, d = laneDirection(b, i);
        bool fromDelta = b.prevPdf[i] == 0.0f;

        if (!b.hit(i)) {
            if (!lights.hasEnvironment() || (b.flags[i] & kFlagSkipEnvironment)) continue;
            // A constant sky is sampled cosine-weighted about the previous facing normal, an
            // image sky by its luminance (lighting/environment.h): MIS with that pdf.
            float envPdf = lights.environment.cosineSampled()
                               ? std::max(0.0f, b.prevCos[i]) * kInvPi
                               : lights.environment.pdf(d, Vec3(0.0f));
            float mis = fromDelta ? 1.0f : kernels::powerHeuristic(b.prevPdf[i], pickPdf * envPdf);
            m_rc.film.add(b.pixel[i], w * lights.environment.radiance(d) * mis, stats);
            continue;
        }
        SurfaceHit h = m_rc.accel.surface(b.instId[i], b.geomId[i], b.primId[i], b.u[i], b.v[i], o, d, b.t[i]);
        Vec3 wo = -d;
        w = w * interiorTransmittance(h, o, d);
        Vec3 le = emittedRadiance(*h.shape, h.ng, wo);
        if (!isBlack(le)) {
            float mis = 1.0f;
            if (!fromDelta) {
                int li = lights.indexOf(h.shape, h.instance);
                float pl = li >= 0 ? pickPdf * lights.lights[std::size_t(li)].pdf(o, h.p, h.ng) : 0.0f;
                mis = kernels::powerHeuristic(b.prevPdf[i], pl);
            }
            m_rc.film.add(b.pixel[i], w * le * mis, stats);
        }
        if (b.flags[i] & kFlagEmissionOnly) continue; // the last vertex's BSDF sample

        h.material = resolveMix(m_rc.scene, h.material, h, wo);
        kernels::BsdfParams bsdf = bsdfAt(m_rc.scene, h.material, h,
                                          kernels::hashCombine(b.rngKey[i], kDimLayered));
        const bool deltaMaterial =
            materialClass(m_rc.scene.materials, h.material) == MaterialClass::Specular;
        // Next-event estimation: one light (or the sky), MIS-weighted against the BSDF.
        if (!deltaMaterial && choices > 0 &&
            sampleOneLight(lights, b, i, h, bsdf, wo, w, sample2D(b, i, kDimLight, strata, m_rc.seed),
                           kernels::uniform(b.rngKey[i], kDimLightPick), false,
                           ctx.out(m_outputs.shadow)))
            ++shadowOut;

        // Continue the path by sampling the BSDF.
        switch (spawnBounce(policy, b, i, h, bsdf, wo, w, sample2D(b, i, kDimBsdf, strata, m_rc.seed),
                            kernels::uniform(b.rngKey[i], kDimLobe),
                            kernels::uniform(b.rngKey[i], kDimRr), 0, m_outputs, 3, ctx)) {
        case Bounce::Reflected: ++reflectOut; break;
        case Bounce::Transmitted: ++refractOut; break;
        case Bounce::None: break;
        }
    }
    stats.stages[int(StageId::Shadow)].raysOut += shadowOut;
    stats.stages[int(StageId::Reflection)].raysOut += reflectOut;
    stats.stages[int(StageId::Refraction)].raysOut += refractOut;
}

} // namespace rayproc
