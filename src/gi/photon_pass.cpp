#include "gi/photon_pass.h"

#include "cluster/cluster.h"
#include "core/ordered_parallel.h"
#include "engine/cancel.h"
#include "engine/engine_settings.h"
#include "engine/phases.h"
#include "engine/pipeline.h"
#include "engine/progress.h"
#include "gi/gi_pipeline.h"
#include "gi/photon_emitter.h"
#include "gi/photon_lists.h"
#include "kernels/random.h"

#include <algorithm>
#include <cstring>
#include <iterator>

namespace rayproc {

KeyedPhotons tracePhotons(const Scene& scene, const EmbreeScene& accel, const LightSet& lights,
                          const GiSettings& s, const EngineSettings& engine, const Cluster& cluster,
                          PhaseLog* phases, const PhotonPassSpec& pass, const FocusRegion& focus,
                          Stats& stats) {
    Film film(1, 1);
    ShadingPolicy policy;
    policy.rouletteEnabled = s.roulette;
    RenderContext rc{scene, accel, lights, policy, film, engine.seed};
    rc.spectral = pass.spectral;
    // The caustic map is read at a visible point, the global map one bounce from it (a final
    // gather, or a camera chain through a glossy reflection): its photons stop one intersection
    // short of maxPhotonDepth D, so that a path through either has at most D scattering events
    // from the light to the visible point, as pbrt-v4's SPPM deposits its photons at up to D.
    PhotonStage stage(rc, pass.caustic,
                      pass.caustic ? s.maxPhotonDepth : std::max(1, s.maxPhotonDepth - 1),
                      s.roughCaustics);
    // photon emitter -> queue -> intersect -> photon stage (stores at diffuse hits, scatters)
    Pipeline pipeline("photons", "photon", accel.root(), engine.packetWidth, stats,
                      engine.threads);
    pipeline.stage("photon", {kPhotonQueue}, stage)
        .timedAs(phases, "photon_tracing");
    PhotonEmitter emitter(lights, scene.worldBounds(), pass.count, engine.seed, pass.tag,
                          !focus.active ? Bounds3{}
                          : pass.caustic ? focus.causticEmissionBounds()
                                         : focus.emissionBounds(),
                          focus.active ? kFocusPhotonShare : 0.0f);
    std::uint64_t first = 0, last = 0;
    shareOf(pass.count, cluster.rank(), cluster.size(), first, last);
    emitter.setRange(first, last);
    emitter.setSpectral(pass.spectral);
    Progress progress(
        pass.label, engine.quiet,
        [&] {
            return double(emitter.photonsEmitted()) /
                   double(std::max<std::uint64_t>(emitter.photonsInRange(), 1));
        },
        [&] { return std::uint64_t(stats.merged().raysTraced); });
    pipeline.run(emitter, [] { return interruptRequested(); });
    progress.finish(!interruptRequested());
    if (interruptRequested()) return {};
    PhaseTimer sortPhase(phases, "photon_sort", PhaseKind::Parallel);
    return stage.takeKeyedPhotons([] { return interruptRequested(); });
}

PhotonList mergePhotonShares(const Cluster& cluster, KeyedPhotons mine) {
    auto stop = [] { return interruptRequested(); };
    if (!cluster.distributed()) return PhotonStage::photonsInKeyOrder(std::move(mine), stop);
    constexpr std::size_t kKey = sizeof(std::uint64_t), kItem = kKey + sizeof(PhotonRecord);
    std::vector<std::uint8_t> bytes(mine.size() * kItem);
    for (std::size_t i = 0; i < mine.size(); ++i) {
        std::memcpy(&bytes[i * kItem], &mine[i].first, kKey);
        std::memcpy(&bytes[i * kItem + kKey], &mine[i].second, sizeof(PhotonRecord));
    }
    mine = {};
    std::vector<std::uint8_t> all = cluster.gatherAll(bytes);
    bytes = {};
    KeyedPhotons keyed(all.size() / kItem);
    for (std::size_t i = 0; i < keyed.size(); ++i) {
        std::memcpy(&keyed[i].first, &all[i * kItem], kKey);
        std::memcpy(&keyed[i].second, &all[i * kItem + kKey], sizeof(PhotonRecord));
    }
    all = {};
    return PhotonStage::photonsInKeyOrder(std::move(keyed), stop);
}

bool stopped(const Cluster& cluster) {
    return cluster.distributed() ? agreeInterrupted(cluster) : interruptRequested();
}

PhotonRounds buildPhotonMap(PhotonMap& map, const Scene& scene, const EmbreeScene& accel,
                            const LightSet& lights, const GiSettings& s,
                            const EngineSettings& engine, const Cluster& cluster,
                            PhaseLog* phases, const PhotonPassSpec& pass,
                            const FocusRegion& focus, Stats& stats, PhotonMap* indirect) {
    // Besides the tracing and sorting: the kd-trees (parallel below their top levels).
    PhaseTimer buildPhase(phases, "photon_map_build", PhaseKind::Parallel);
    map.build({});
    if (indirect) indirect->build({});
    PhotonRounds done;
    if (pass.count == 0 || stopped(cluster)) return done;
    auto inView = [&](const PhotonRecord& p) {
        if (indirect && p.sampledDirect) return false;
        return !focus.active || focus.bounds.contains(p.position);
    };
    std::vector<PhotonList> traced;
    std::size_t& landed = done.inView;
    int& rounds = done.rounds;
    while (rounds < std::max(1, pass.maxRounds)) {
        PhotonPassSpec round = pass;
        if (rounds > 0) {
            round.tag = kernels::hashCombine(pass.tag, std::uint64_t(rounds));
            round.label = "gi photons, another round";
        }
        KeyedPhotons keyed =
            tracePhotons(scene, accel, lights, s, engine, cluster, phases, round, focus, stats);
        PhaseTimer mergePhase(phases, "photon_sort", PhaseKind::Parallel);
        traced.push_back(mergePhotonShares(cluster, std::move(keyed)));
        mergePhase.stop();
        if (stopped(cluster)) return done;
        ++rounds;
        landed += std::size_t(std::count_if(traced.back().begin(), traced.back().end(), inView));
        if (landed >= pass.inViewTarget) break;
    }
    // Each round alone carries the lights' whole power.
    PhotonList photons = joinRounds(traced, rounds > 1 ? float(rounds) : 1.0f);
    double unit = PhotonEmitter::powerUnit(lights, scene.worldBounds());
    if (indirect) indirect->setPowerUnit(unit);
    map.setPowerUnit(unit);
    auto stop = [] { return interruptRequested(); };
    if (!indirect) {
        map.build(std::move(photons), stop);
        return done;
    }
    // The two kd-trees at once: each one's top levels run on one thread.
    PhotonList scattered = scatteredPhotons(photons);
    bool indirectBuilt = true;
    orderedParallelInvoke(
        [&] { indirectBuilt = indirect->build(std::move(scattered), stop); },
        [&] { map.build(std::move(photons), stop); });
    if (!indirectBuilt) map.build({}); // as before: nothing once the indirect map was cut short
    return done;
}

} // namespace rayproc
