#include "engine/surface_stage.h"

#include "core/error.h"
#include "engine/glossy_mis.h"
#include "engine/material_bsdf.h"
#include "engine/path_state.h"

#include <cmath>

namespace rayproc {

namespace {
// The hits of a batch by the stages that continue them, and whether the hit being routed was
// reached with all the path's wavelengths (HitList::arrivedWhole, for the mode's handlers).
struct Routes {
    HitList direct, reflect, refract, indirect;
    bool arrivedWhole = false;
};

// Routes hit h of lane i by its material's lobes (scene/material.h, materialLobes):
// `addDirect` light sampling, `handled` diffuse hits to the mode's handlers (the light past a
// glossy bounce theirs), `prepass` the handlers' alone.
void routeByLobes(const Scene& scene, int i, const SurfaceHit& h, bool visible, bool addDirect,
                  bool handled, bool prepass, Routes& r) {
    using namespace kernels;
    const LobeFlags lobes = materialLobes(scene.materials, h.material);
    if (hasLobe(lobes, kLobeDiffuse)) {
        // gi: past a glossy bounce (other than a rough dielectric's on a camera chain, which
        // keeps the hit a visible point) the global map gives all reflected light, direct too.
        const bool direct = addDirect && (!handled || visible);
        if (direct) r.direct.add(i, h);
        if (handled) r.indirect.add(i, h, false, r.arrivedWhole);
        // A coat's reflection of the scene over the diffuse base, mirror or rough, traced by
        // the reflection stage (kernels::sampleCoatReflection).
        if (hasLobe(lobes, LobeFlags(kLobeGlossy | kLobeSpecular)) && !prepass)
            r.reflect.add(i, h, direct);
        return;
    }
    if (hasLobe(lobes, kLobeGlossy)) {
        // Light sampling and one sampled continuation, which takes its MIS share of the light.
        if (prepass) return;
        if (addDirect) r.direct.add(i, h);
        r.reflect.add(i, h, addDirect);
        return;
    }
    // Delta lobes only: a refracting interface's two (reflection and the bent transmission)
    // are both traced by the refraction stage; any other delta BSDF is sampled.
    if (hasLobe(lobes, kLobeTransmission) && !hasLobe(lobes, kLobeStraight)) r.refract.add(i, h);
    else r.reflect.add(i, h);
}
} // namespace

// The sky's radiance where lane i's ray escapes, if it counts the sky (MIS-weighted after a
// glossy bounce whose light the shadow stage sampled too).
void SurfaceStage::addEscaped(const RayBatch& b, int i, ThreadStats& stats) const {
    if (!(b.flags[i] & kFlagCountEnvironment) || !m_rc.lights.hasEnvironment()) return;
    Vec3 d = laneDirection(b, i);
    float mis = (b.flags[i] & kFlagMisEnvironment)
                    ? reflectionEnvironmentWeight(m_rc.policy, m_rc.lights.environment, d,
                                                  b.prevCos[i], b.prevPdf[i])
                    : 1.0f;
    Vec3 sky = m_rc.lights.environment.radiance(d);
    if (m_rc.spectral) {
        const LaneSpectrum l = m_rc.spectral->lane(b.lambdaU[i]);
        sky = m_rc.spectral->toFilm(laneThroughput(b, i) * m_rc.spectral->sky(sky, l), l);
        m_rc.film.add(b.pixel[i], sky * mis, stats);
        return;
    }
    m_rc.film.add(b.pixel[i], laneThroughput(b, i) * sky * mis, stats);
}

// Lane i's hit: its surface, the absorption of the medium it crossed (into the lane's
// throughput, which the stages below read) and, with direct light, the emission it lands on.
SurfaceHit SurfaceStage::resolveHit(RayBatch& b, int i, bool addDirect,
                                    ThreadStats& stats) const {
    Vec3 w = laneThroughput(b, i);
    Vec3 o{b.ox[i], b.oy[i], b.oz[i]}, d = laneDirection(b, i);
    SurfaceHit h =
        m_rc.accel.surface(b.instId[i], b.geomId[i], b.primId[i], b.u[i], b.v[i], o, d, b.t[i]);
    LaneSpectrum l{};
    if (m_rc.spectral) l = m_rc.spectral->lane(b.lambdaU[i]);
    Vec3 absorbed = interiorTransmittance(h, o, d, m_rc.spectral, &l);
    if (absorbed.x != 1.0f || absorbed.y != 1.0f || absorbed.z != 1.0f) {
        w = w * absorbed;
        b.wr[i] = w.x;
        b.wg[i] = w.y;
        b.wb[i] = w.z;
    }
    const bool countEmission = (b.flags[i] & kFlagCountEmission) != 0;
    const bool misEmission = (b.flags[i] & kFlagMisEmission) != 0;
    Vec3 le = addDirect && (countEmission || misEmission) ? emittedRadiance(*h.shape, h.ng, -d)
                                                          : Vec3(0.0f);
    if (!isBlack(le)) {
        // A glossy lobe's sampled ray takes its MIS share of the light samples' emission; an
        // emitter outside the sampled light set no light sample covered.
        float mis = 1.0f;
        int li = countEmission ? -1 : m_rc.lights.indexOf(h.shape, h.instance);
        if (li >= 0)
            mis = reflectionEmissionWeight(m_rc.policy, m_rc.lights, std::size_t(li), o, h.p,
                                           h.ng, b.prevPdf[i]);
        if (m_rc.spectral) {
            le = m_rc.spectral->emitted(*h.shape, m_rc.lights.indexOf(h.shape, h.instance), le, l);
            m_rc.film.add(b.pixel[i], m_rc.spectral->toFilm(w * le, l) * mis, stats);
        } else {
            m_rc.film.add(b.pixel[i], w * le * mis, stats);
        }
    }
    return h;
}

void SurfaceStage::retrace(RayBatch& b, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    Routes r;
    // With diffuse-hit handlers, the light past a non-specular bounce is theirs (gi).
    const bool handled = !m_diffuseHandlers.empty();
    const bool prepass = m_rc.policy.handlersOnly; // gi: the irradiance cache's prepass
    const bool addDirect = m_rc.policy.directLight && !prepass;
    {
        StageTimer timer(stats, StageId::Surface);
        stats.stages[int(StageId::Surface)].raysIn += std::uint64_t(b.count);
        for (int i = 0; i < b.count; ++i) {
            if (!b.hit(i)) {
                if (addDirect) addEscaped(b, i, stats);
                continue;
            }
            SurfaceHit h = resolveHit(b, i, addDirect, stats);
            if (b.flags[i] & kFlagEmissionOnly) continue; // a last vertex's MIS partner
            resolveShading(m_rc.scene, h, -laneDirection(b, i));
            // A dispersive material (a coat's too) keeps the hero wavelength alone for every
            // stage the hit goes to (docs/spectral.md, "Dispersion"); the emission found here,
            // added above, keeps all three.
            r.arrivedWhole = !std::signbit(b.lambdaU[i]);
            if (m_rc.spectral && dispersiveMaterial(m_rc.scene.materials[h.material]))
                b.lambdaU[i] = SpectralRender::terminatedU(b.lambdaU[i]);
            routeByLobes(m_rc.scene, i, h, visiblePoint(b.flags[i]), addDirect, handled, prepass,
                         r);
        }
    }
    // A stage the scene analysis skipped getting work means the analysis is wrong.
    const ShadingPolicy& policy = m_rc.policy;
    RAYPROC_CHECK(policy.shadowStage || r.direct.count == 0);
    RAYPROC_CHECK(policy.reflectionStage || r.reflect.count == 0);
    RAYPROC_CHECK(policy.refractionStage || r.refract.count == 0);
    if (r.direct.count) m_shadow.spawn(b, r.direct, ctx);
    if (r.indirect.count)
        for (DiffuseHitHandler* handler : m_diffuseHandlers) handler->spawn(b, r.indirect, ctx);
    if (r.reflect.count) m_reflection.spawn(b, r.reflect, ctx);
    if (r.refract.count) m_refraction.spawn(b, r.refract, ctx);
}

} // namespace rayproc
