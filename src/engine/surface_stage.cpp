#include "engine/surface_stage.h"

#include "core/error.h"
#include "engine/glossy_mis.h"
#include "engine/material_bsdf.h"
#include "engine/path_state.h"

namespace rayproc {

void SurfaceStage::retrace(RayBatch& b, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    HitList direct, reflect, refract, indirect;
    // With diffuse-hit handlers, the light past a non-specular bounce is theirs (gi).
    const bool handled = !m_diffuseHandlers.empty();
    const bool prepass = m_rc.policy.handlersOnly; // gi: the irradiance cache's prepass
    const bool addDirect = m_rc.policy.directLight && !prepass;
    {
        StageTimer timer(stats, StageId::Surface);
        stats.stages[int(StageId::Surface)].raysIn += std::uint64_t(b.count);
        const auto& materials = m_rc.scene.materials;
        for (int i = 0; i < b.count; ++i) {
            Vec3 w = laneThroughput(b, i);
            bool countEmission = (b.flags[i] & kFlagCountEmission) != 0;
            if (!b.hit(i)) {
                if (addDirect && (b.flags[i] & kFlagCountEnvironment) && m_rc.lights.hasEnvironment()) {
                    Vec3 d = laneDirection(b, i);
                    float mis = (b.flags[i] & kFlagMisEnvironment)
                                    ? reflectionEnvironmentWeight(m_rc.policy, m_rc.lights.environment,
                                                                  d, b.prevCos[i], b.prevPdf[i])
                                    : 1.0f;
                    m_rc.film.add(b.pixel[i], w * m_rc.lights.environment.radiance(d) * mis, stats);
                }
                continue;
            }
            Vec3 o{b.ox[i], b.oy[i], b.oz[i]}, d = laneDirection(b, i);
            SurfaceHit h =
                m_rc.accel.surface(b.instId[i], b.geomId[i], b.primId[i], b.u[i], b.v[i], o, d, b.t[i]);
            Vec3 absorbed = interiorTransmittance(h, o, d);
            if (absorbed.x != 1.0f || absorbed.y != 1.0f || absorbed.z != 1.0f) {
                w = w * absorbed; // the stages below read the lane's throughput
                b.wr[i] = w.x;
                b.wg[i] = w.y;
                b.wb[i] = w.z;
            }
            const bool misEmission = (b.flags[i] & kFlagMisEmission) != 0;
            Vec3 le = addDirect && (countEmission || misEmission)
                          ? emittedRadiance(*h.shape, h.ng, -d)
                          : Vec3(0.0f);
            if (!isBlack(le)) {
                // A glossy lobe's sampled ray takes its MIS share of the light samples'
                // emission; an emitter outside the sampled light set no light sample covered.
                float mis = 1.0f;
                int li = countEmission ? -1 : m_rc.lights.indexOf(h.shape, h.instance);
                if (li >= 0)
                    mis = reflectionEmissionWeight(m_rc.policy, m_rc.lights, std::size_t(li), o,
                                                   h.p, h.ng, b.prevPdf[i]);
                m_rc.film.add(b.pixel[i], w * le * mis, stats);
            }
            if (b.flags[i] & kFlagEmissionOnly) continue; // a last vertex's MIS partner

            h.material = resolveMix(m_rc.scene, h.material, h, -d);
            const MaterialType type = materials[h.material].type;
            const MaterialClass cls = materialClass(materials, h.material);
            switch (type) {
            case MaterialType::Diffuse:
            case MaterialType::DiffuseTransmission:
            case MaterialType::CoatedDiffuse:
                // gi: past a glossy bounce the global map gives all reflected light, direct too.
                if (addDirect && (!handled || countEmission)) direct.add(i, h);
                if (handled) indirect.add(i, h);
                // The coat's reflection of the scene, mirror or rough, traced by the
                // reflection stage (kernels::sampleCoatReflection).
                if (type == MaterialType::CoatedDiffuse && !prepass)
                    reflect.add(i, h, addDirect && (!handled || countEmission));
                break;
            case MaterialType::Glossy:
                if (prepass) break;
                if (addDirect) direct.add(i, h);
                reflect.add(i, h, addDirect);
                break;
            case MaterialType::Dielectric:
                if (cls == MaterialClass::Specular) {
                    refract.add(i, h);
                    break;
                }
                [[fallthrough]]; // rough glass: light sampling and one sampled continuation
            case MaterialType::Conductor:
                if (cls == MaterialClass::Glossy) {
                    if (prepass) break;
                    if (addDirect) direct.add(i, h);
                }
                reflect.add(i, h, cls == MaterialClass::Glossy && addDirect);
                break;
            case MaterialType::Mirror:
            case MaterialType::ThinDielectric: reflect.add(i, h); break;
            case MaterialType::Mix: break; // resolved above
            }
        }
    }
    // A stage the scene analysis skipped getting work means the analysis is wrong.
    const ShadingPolicy& policy = m_rc.policy;
    RAYPROC_CHECK(policy.shadowStage || direct.count == 0);
    RAYPROC_CHECK(policy.reflectionStage || reflect.count == 0);
    RAYPROC_CHECK(policy.refractionStage || refract.count == 0);
    if (direct.count) m_shadow.spawn(b, direct, ctx);
    if (indirect.count)
        for (DiffuseHitHandler* handler : m_diffuseHandlers) handler->spawn(b, indirect, ctx);
    if (reflect.count) m_reflection.spawn(b, reflect, ctx);
    if (refract.count) m_refraction.spawn(b, refract, ctx);
}

} // namespace rayproc
