#include "gi/photon_stage.h"

#include "core/ordered_parallel.h"
#include "engine/material_bsdf.h"
#include "engine/path_state.h"
#include "gi/gi_pipeline.h"
#include "gi/photon_lists.h"
#include "kernels/bsdf_sampling.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace rayproc {

namespace {
enum PhotonDim : std::uint32_t { kDimScatter = 30, kDimLobe = 32, kDimSurvive = 33 };

// Writes the photon that lane i of `parent` scatters into, its random stream keyed as gi has
// always keyed it: the successor's of branch 4 (successorKey, engine/path_state.h).
void spawnPhoton(PhotonBatch& out, const PhotonBatch& parent, int i, const Vec3& origin,
                 const Vec3& dir, const Vec3& power, std::uint8_t depth, std::uint8_t flags,
                 float lambdaU) {
    constexpr std::uint32_t kBranch = 4;
    int j = out.push(origin.x, origin.y, origin.z, dir.x, dir.y, dir.z, 0.0f, kInfinity);
    out.index[j] = parent.index[i];
    out.wr[j] = power.x; out.wg[j] = power.y; out.wb[j] = power.z;
    out.rngKey[j] = successorKey(parent.rngKey[i], kBranch);
    out.depth[j] = depth;
    out.flags[j] = flags;
    out.lambdaU[j] = lambdaU;
}

// std::is_sorted over blocks of `all` on every thread: each block, and its first element
// against the element before it.
template <typename Less>
bool sortedInParallel(const KeyedPhotons& all, const Less& less) {
    constexpr std::size_t kBlock = 65536;
    std::atomic<bool> sorted{true};
    orderedParallelFor(0, all.size(), kBlock, [&](const tbb::blocked_range<std::size_t>& r) {
        const std::size_t first = r.begin() > 0 ? r.begin() - 1 : 0;
        if (!std::is_sorted(all.begin() + std::ptrdiff_t(first),
                            all.begin() + std::ptrdiff_t(r.end()), less))
            sorted.store(false, std::memory_order_relaxed);
    });
    return sorted.load();
}

} // namespace

PhotonRecord PhotonStage::record(const PhotonBatch& b, int i, const SurfaceHit& h, const Vec3& wo,
                                 const Vec3& power, const LaneShading& wl) const {
    Vec3 fg = dot(wo, h.ng) >= 0 ? h.ng : -h.ng;
    // Where a photon from a delta light or the sky first lands it is that light's direct
    // light, which gi's gather samples instead (GiSettings::gatherDirect).
    std::uint32_t sampled = b.depth[i] == 0 && (b.flags[i] & kPhotonDeltaOrSky) ? 1u : 0u;
    // Spectral mode stores the CIE XYZ of its three values (the film's estimate of its
    // colour, before the film's matrix to RGB; non-negative, as RGBE needs).
    const Vec3 stored3 = m_rc.spectral ? m_rc.spectral->toXyz(power, wl.lane()) : power;
    // Past dispersive glass it carries its hero wavelength alone, which the caustic estimate
    // of a path of one wavelength reads (GatherStage).
    const float one = m_rc.spectral && std::signbit(wl.u()) ? wl.lane().w.lambda[0] : 0.0f;
    return PhotonRecord{h.p, stored3, wo, fg, sampled, one};
}

void PhotonStage::retracePhotons(PhotonBatch& b, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, kPhotonStageId);
    stats.stages[int(kPhotonStageId)].raysIn += std::uint64_t(b.count);
    auto& stored = m_stored.local();
    std::uint64_t spawned = 0;
    for (int i = 0; i < b.count; ++i) {
        if (!b.hit(i)) continue;
        Vec3 o{b.ox[i], b.oy[i], b.oz[i]}, d = laneDirection(b, i);
        SurfaceHit h = m_rc.accel.surface(b.instId[i], b.geomId[i], b.primId[i], b.u[i], b.v[i], o, d, b.t[i]);
        Vec3 wo = -d;
        resolveShading(m_rc.scene, h, wo);
        // Spectral mode: the photon's power is at its wavelengths, and so is everything it
        // meets (absorption, the BSDF); past a dispersive interface its hero's alone (wl.u()).
        LaneShading wl(m_rc.spectral);
        wl.select(b.lambdaU[i], m_rc.scene, h.material);
        Vec3 power =
            laneThroughput(b, i) * interiorTransmittance(h, o, d, m_rc.spectral, &wl.lane());
        // Photons are stored where a lookup may read them: at diffuse and glossy surfaces. A
        // caustic photon goes on through a rough dielectric interface as through a smooth one
        // (GiSettings::roughCaustics): the camera's visible points past such interfaces and
        // the surfaces lit through them read it (L S+ D with S rough or smooth glass).
        const MaterialClass cls = materialClass(m_rc.scene.materials, h.material);
        const bool roughInterface = m_roughCaustics && cls == MaterialClass::Glossy &&
                                    m_rc.scene.materials[h.material].type == MaterialType::Dielectric;
        const bool specularSurface = cls == MaterialClass::Specular || roughInterface;
        std::uint8_t flags = b.flags[i];
        if (!specularSurface) {
            bool store = m_causticPass ? (flags & kPhotonSpecular) && !(flags & kPhotonDiffuse) : true;
            if (store) {
                std::uint64_t key = (std::uint64_t(b.index[i]) << 8) | b.depth[i];
                stored.push_back({key, record(b, i, h, wo, power, wl)});
                ++giCounter(stats, kGiPhotonsStored);
            }
            // A caustic path ends at its first diffuse surface, unless a coat over it
            // reflects the photon on (below).
            if (m_causticPass && m_rc.scene.materials[h.material].type != MaterialType::CoatedDiffuse)
                continue;
        }
        int depth = b.depth[i] + 1;
        if (depth >= m_maxDepth) continue;
        kernels::BsdfParams bsdf =
            bsdfAt(m_rc.scene, h.material, h, kernels::hashCombine(b.rngKey[i], kDimLobe + 1),
                   wl.shading());
        Vec2 u{kernels::uniform(b.rngKey[i], kDimScatter), kernels::uniform(b.rngKey[i], kDimScatter + 1)};
        kernels::BsdfSample s = kernels::sampleBsdf(bsdf, wo, h.ng, h.ns, u,
                                                    kernels::uniform(b.rngKey[i], kDimLobe));
        if (!s.valid) continue;
        // Caustic photons go on only by specular scattering: at a coated surface, its coat's.
        if (m_causticPass && !specularSurface && !s.coat) continue;
        // Russian roulette keeps the photon's power; without it (--no-russian-roulette) the
        // power scales by the weight and the photon runs to the maximum depth.
        float q = m_rc.policy.rouletteEnabled ? std::min(1.0f, maxComponent(s.weight)) : 1.0f;
        if (!(maxComponent(s.weight) > 0) || !(q > 0) ||
            (q < 1.0f && kernels::uniform(b.rngKey[i], kDimSurvive) >= q))
            continue;
        Vec3 next = power * s.weight / q;
        // Camera and gather chains through smooth glass carry basic radiance L / n^2 (no
        // eta^2 at either interface: exact when both ends are in air), so a photon stored
        // inside a medium must carry flux / n^2 for its estimate to meet them: 1 / eta^2 at
        // every smooth refraction. Rough transmission already carries it (kernels, f / eta^2).
        // Without it a floor under open water came out n^2 = 1.77 times too bright.
        if (s.transmitted && bsdf.kind == kernels::BsdfKind::Dielectric && !kernels::roughAlphas(bsdf))
            next = next * smoothTransmissionScale(bsdf.ior, dot(wo, h.ng) > 0);
        std::uint8_t nextFlags = std::uint8_t(
            flags | (s.delta || s.coat || roughInterface ? kPhotonSpecular : kPhotonDiffuse));
        spawnPhoton(ctx.outPhotons(kPhotonRay), b, i, offsetRayOrigin(h, h.ng, s.wi), s.wi,
                    next, std::uint8_t(depth), nextFlags, wl.u());
        ++spawned;
    }
    stats.stages[int(kPhotonStageId)].raysOut += spawned;
}

KeyedPhotons PhotonStage::takeKeyedPhotons(const std::function<bool()>& stop) {
    if (stop && stop()) return {};
    // Keys (photon index, depth) are unique, so key order is the only order, whatever thread
    // stored which photon.
    std::vector<std::vector<KeyedPhoton>*> runs;
    for (auto& v : m_stored) runs.push_back(&v);
    KeyedPhotons all = keyedInOrder(std::move(runs));
    if (stop && stop()) return {};
    return all;
}

PhotonList PhotonStage::photonsInKeyOrder(KeyedPhotons all, const std::function<bool()>& stop) {
    // Shares of contiguous index ranges arrive in order; anything else is sorted here.
    auto byKey = [](const auto& a, const auto& b) { return a.first < b.first; };
    if (!sortedInParallel(all, byKey)) tbb::parallel_sort(all.begin(), all.end(), byKey);
    if (stop && stop()) return {};
    PhotonList out(all.size()); // every record written below
    orderedParallelFor(0, all.size(), 65536,
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) out[i] = all[i].second;
                      });
    return out;
}

PhotonList PhotonStage::takePhotons(const std::function<bool()>& stop) {
    KeyedPhotons all = takeKeyedPhotons(stop);
    if (stop && stop()) return {};
    return photonsInKeyOrder(std::move(all), stop);
}

} // namespace rayproc
