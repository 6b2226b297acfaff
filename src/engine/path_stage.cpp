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
                    float up, bool areaLightsOnly, bool compensated, ShadowBatch& out,
                    const SpectralShading* spectral) {
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
            if (spectral) li = spectral->render.lightValue(pick, li, spectral->lane);
        }
    } else {
        if (areaLightsOnly) return false;
        // Every vertex that samples the sky also sends a BSDF ray that may find it, so an
        // image sky's light samples may leave its below-average part to the BSDF's.
        EnvironmentSample es = lights.environment.sample(u, fs, compensated);
        if (es.valid) {
            wi = es.wi;
            lightPdf = es.pdf;
            li = spectral ? spectral->render.sky(es.weight, spectral->lane) : es.weight;
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
    out.category[out.count - 1] = std::uint32_t(1 + contributionOfLightSample(pick));
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

namespace {

// One batch of path vertices: what each ray found (the sky, an emitter) goes to the film, and
// each surface vertex samples one light and continues by one BSDF sample.
class PathVertices {
public:
    PathVertices(const RenderContext& rc, const PathStage::Outputs& outputs, bool sobol,
                 RayBatch& b, StageContext& ctx)
        : m_rc(rc), m_lights(rc.lights), m_policy(rc.policy), m_outputs(outputs), m_b(b),
          m_ctx(ctx), m_stats(*ctx.stats), m_sobol(sobol), m_seedKey(sampleSeedKey(rc.seed)) {}

    void retraceLane(int i) {
        m_wl.select(m_b.lambdaU[i]);
        Vec3 w = laneThroughput(m_b, i);
        Vec3 o{m_b.ox[i], m_b.oy[i], m_b.oz[i]}, d = laneDirection(m_b, i);
        bool fromDelta = m_b.prevPdf[i] == 0.0f;
        if (!m_b.hit(i)) {
            addSky(i, w, o, d, fromDelta);
            return;
        }
        SurfaceHit h = m_rc.accel.surface(m_b.instId[i], m_b.geomId[i], m_b.primId[i], m_b.u[i],
                                          m_b.v[i], o, d, m_b.t[i]);
        Vec3 wo = -d;
        w = w * interiorTransmittance(h, o, d, m_rc.spectral, &m_wl.lane());
        addEmission(i, h, w, o, wo, fromDelta);
        if (m_b.flags[i] & kFlagEmissionOnly) return; // the last vertex's BSDF sample
        scatter(i, h, w, wo);
    }

    std::uint64_t shadowOut = 0, reflectOut = 0, refractOut = 0;

private:
    // Filed for --stats and the noise breakdown: reached through delta lobes after a
    // non-delta bounce is a caustic. Then added to the film (in spectral mode its RGB).
    void addToFilm(int i, std::size_t category, Vec3 c) {
        if (m_rc.spectral) c = m_rc.spectral->toFilm(c, m_wl.lane());
        fileContribution(m_stats, m_rc.noise, m_lights.lights.size(), m_b.pixel[i], category,
                         c, m_b.depth[i] > m_b.specularDepth[i]);
        m_rc.film.add(m_b.pixel[i], c, m_stats);
    }
    const SpectralShading* spectral() const { return m_wl.shading(); }

    // An escaped ray's sky, MIS-weighted against the sky's light samples.
    void addSky(int i, const Vec3& w, const Vec3& o, const Vec3& d, bool fromDelta) {
        if (!m_lights.hasEnvironment() || (m_b.flags[i] & kFlagSkipEnvironment)) return;
        // A constant sky is sampled cosine-weighted about the previous facing normal, an
        // image sky by its luminance (lighting/environment.h): MIS with that pdf.
        float envPdf = m_lights.environment.cosineSampled()
                           ? std::max(0.0f, m_b.prevCos[i]) * kInvPi
                           : m_lights.environment.pdf(d, Vec3(0.0f), m_policy.skyCompensation);
        float pick = m_lights.sampler.pmf(o, m_lights.lights.size()); // the sky's fixed share
        float mis = fromDelta ? 1.0f : kernels::powerHeuristic(m_b.prevPdf[i], pick * envPdf);
        Vec3 radiance = m_lights.environment.radiance(d);
        if (m_rc.spectral) radiance = m_rc.spectral->sky(radiance, m_wl.lane());
        addToFilm(i, fromDelta ? 0 : contributionOfBsdfHit(m_lights.lights.size()),
                  w * radiance * mis);
    }

    // The emission the ray found, MIS-weighted against the light sample at its origin.
    void addEmission(int i, const SurfaceHit& h, const Vec3& w, const Vec3& o, const Vec3& wo,
                     bool fromDelta) {
        Vec3 le = emittedRadiance(*h.shape, h.ng, wo);
        if (isBlack(le)) return;
        float mis = 1.0f;
        int li = m_lights.indexOf(h.shape, h.instance);
        if (m_rc.spectral)
            le = m_rc.spectral->emitted(*h.shape, li, le, m_wl.lane());
        if (!fromDelta) {
            // The probability that the light sample at the ray's origin had come here.
            float pl = li >= 0 ? m_lights.sampler.pmf(o, std::size_t(li)) *
                                     m_lights.lights[std::size_t(li)].pdf(o, h.p, h.ng)
                               : 0.0f;
            mis = kernels::powerHeuristic(m_b.prevPdf[i], pl);
        }
        addToFilm(i, fromDelta || li < 0 ? 0 : contributionOfBsdfHit(std::size_t(li)),
                  w * le * mis);
    }

    // One light sample and one BSDF sample at the surface vertex.
    void scatter(int i, SurfaceHit& h, const Vec3& w, const Vec3& wo) {
        resolveShading(m_rc.scene, h, wo);
        // A dispersive material keeps the hero wavelength alone, for its light sample and its
        // continuation, which inherit the lane's number.
        m_wl.select(m_b.lambdaU[i], m_rc.scene, h.material);
        m_b.lambdaU[i] = m_wl.u();
        kernels::BsdfParams bsdf =
            bsdfAt(m_rc.scene, h.material, h, kernels::hashCombine(m_b.rngKey[i], kDimLayered),
                   spectral());
        const bool deltaMaterial =
            materialClass(m_rc.scene.materials, h.material) == MaterialClass::Specular;
        // Path mode's own paths take Sobol points, a sequence per (pixel, depth); gi's
        // correction paths their lanes' streams.
        // (The light's pair is drawn also where no light is sampled: pure functions, cheaper
        // three at a time.)
        const SampleNumbers numbers(m_b, i, m_sobol, m_seedKey);
        Vec2 u[3];
        numbers.get2D({kDimPickLobe, kDimLight, kDimBsdf}, u);
        const Vec2 pickLobe = u[0];
        // Next-event estimation: one light (or the sky), MIS-weighted against the BSDF.
        if (!deltaMaterial && m_lights.choiceCount() > 0 &&
            sampleOneLight(m_lights, m_b, i, h, bsdf, wo, w, u[1], pickLobe.x, false,
                           m_policy.skyCompensation, m_ctx.outShadow(m_outputs.shadow), spectral()))
            ++shadowOut;

        // Continue the path by sampling the BSDF.
        // Russian roulette's number: the path's own stream (stratifying it buys nothing).
        switch (spawnBounce(m_policy, m_b, i, h, bsdf, wo, w, u[2], pickLobe.y,
                            kernels::uniform(m_b.rngKey[i], kDimRr), 0, m_outputs, 3, m_ctx)) {
        case Bounce::Reflected: ++reflectOut; break;
        case Bounce::Transmitted: ++refractOut; break;
        case Bounce::None: break;
        }
    }

    const RenderContext& m_rc;
    const LightSet& m_lights;
    const ShadingPolicy& m_policy;
    const PathStage::Outputs& m_outputs;
    RayBatch& m_b;
    StageContext& m_ctx;
    ThreadStats& m_stats;
    const bool m_sobol;
    const std::uint64_t m_seedKey;
    // Spectral mode: the current lane's wavelengths.
    LaneShading m_wl{m_rc.spectral}; // spectral mode: the current lane's wavelengths
};

} // namespace

void PathStage::retrace(RayBatch& b, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::Surface);
    stats.stages[int(StageId::Surface)].raysIn += std::uint64_t(b.count);
    PathVertices vertices(m_rc, m_outputs, m_rc.policy.stratify && m_lowDiscrepancy, b, ctx);
    for (int i = 0; i < b.count; ++i) vertices.retraceLane(i);
    stats.stages[int(StageId::Shadow)].raysOut += vertices.shadowOut;
    stats.stages[int(StageId::Reflection)].raysOut += vertices.reflectOut;
    stats.stages[int(StageId::Refraction)].raysOut += vertices.refractOut;
}

} // namespace rayproc
