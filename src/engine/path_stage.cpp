#include "engine/path_stage.h"

#include "engine/noise_breakdown.h"
#include "engine/path_state.h"
#include "engine/sample_numbers.h"
#include "engine/material_bsdf.h"
#include "kernels/bsdf_sampling.h"
#include "kernels/sampling.h"

namespace rayproc {

namespace {

// Random dimensions of one path vertex.
// (kDimPickLobe: the light choice and the BSDF lobe's, as one pair.)
enum PathDim : std::uint32_t { kDimPickLobe = 19, kDimLight = 21, kDimBsdf = 23, kDimRr = 26,
                               kDimLayered = 27 };

} // namespace

bool sampleOneLight(const LightSet& lights, const RayBatch& b, int i, const SurfaceHit& h,
                    const kernels::BsdfParams& bsdf, const Vec3& wo, const Vec3& w, Vec2 u,
                    float up, bool areaLightsOnly, bool compensated, RayBatch& out) {
    if (lights.choiceCount() == 0) return false;
    const LightSampler::Pick choice = lights.sampler.sample(h.p, up);
    if (!(choice.pmf > 0)) return false;
    const float pickPdf = choice.pmf;
    const std::size_t pick = choice.index;
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
        // Every vertex that samples the sky also sends a BSDF ray that may find it, so an
        // image sky's light samples may leave its below-average part to the BSDF's.
        EnvironmentSample es = lights.environment.sample(u, fs, compensated);
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
    // The shadow stage files the contribution under this choice's light samples (--stats).
    out.rngKey[out.count - 1] = 1 + contributionOfLightSample(pick);
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
    const LightSampler& sampler = lights.sampler;
    const bool sobol = policy.stratify && m_lowDiscrepancy;
    const std::uint64_t seedKey = sampleSeedKey(m_rc.seed);
    std::uint64_t shadowOut = 0, reflectOut = 0, refractOut = 0;
    // Filed for --stats and the noise breakdown: reached through delta lobes after a
    // non-delta bounce is a caustic.
    auto file = [&](int i, std::size_t category, double lum) {
        fileContribution(stats, m_rc.noise, lights.lights.size(), b.pixel[i], category, lum,
                         b.depth[i] > b.specularDepth[i]);
    };

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
                               : lights.environment.pdf(d, Vec3(0.0f), policy.skyCompensation);
            float pick = sampler.pmf(o, lights.lights.size()); // the sky's fixed share
            float mis = fromDelta ? 1.0f : kernels::powerHeuristic(b.prevPdf[i], pick * envPdf);
            Vec3 sky = w * lights.environment.radiance(d) * mis;
            file(i, fromDelta ? 0 : contributionOfBsdfHit(lights.lights.size()), luminance(sky));
            m_rc.film.add(b.pixel[i], sky, stats);
            continue;
        }
        SurfaceHit h = m_rc.accel.surface(b.instId[i], b.geomId[i], b.primId[i], b.u[i], b.v[i], o, d, b.t[i]);
        Vec3 wo = -d;
        w = w * interiorTransmittance(h, o, d);
        Vec3 le = emittedRadiance(*h.shape, h.ng, wo);
        if (!isBlack(le)) {
            float mis = 1.0f;
            int li = lights.indexOf(h.shape, h.instance);
            if (!fromDelta) {
                // The probability that the light sample at the ray's origin had come here.
                float pl = li >= 0 ? sampler.pmf(o, std::size_t(li)) *
                                         lights.lights[std::size_t(li)].pdf(o, h.p, h.ng)
                                   : 0.0f;
                mis = kernels::powerHeuristic(b.prevPdf[i], pl);
            }
            file(i, fromDelta || li < 0 ? 0 : contributionOfBsdfHit(std::size_t(li)),
                 luminance(w * le * mis));
            m_rc.film.add(b.pixel[i], w * le * mis, stats);
        }
        if (b.flags[i] & kFlagEmissionOnly) continue; // the last vertex's BSDF sample

        h.material = resolveMix(m_rc.scene, h.material, h, wo);
        kernels::BsdfParams bsdf = bsdfAt(m_rc.scene, h.material, h,
                                          kernels::hashCombine(b.rngKey[i], kDimLayered));
        const bool deltaMaterial =
            materialClass(m_rc.scene.materials, h.material) == MaterialClass::Specular;
        // Path mode's own paths take Sobol points, a sequence per (pixel, depth); gi's
        // correction paths their lanes' streams.
        const SampleNumbers u(b, i, sobol, seedKey);
        const Vec2 pickLobe = u.get2D(kDimPickLobe);
        // Next-event estimation: one light (or the sky), MIS-weighted against the BSDF.
        if (!deltaMaterial && choices > 0 &&
            sampleOneLight(lights, b, i, h, bsdf, wo, w, u.get2D(kDimLight), pickLobe.x, false,
                           policy.skyCompensation, ctx.out(m_outputs.shadow)))
            ++shadowOut;

        // Continue the path by sampling the BSDF.
        // Russian roulette's number: the path's own stream (stratifying it buys nothing).
        switch (spawnBounce(policy, b, i, h, bsdf, wo, w, u.get2D(kDimBsdf), pickLobe.y,
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
