// gi mode: Jensen's two-pass photon mapping (Jensen 2001) on the ray processor.
//  1. Photon passes: the photon emitter and the photon stage build the global map (every
//     photon at a diffuse surface) and the caustic map (L S+ D paths only), both sorted into a
//     fixed order, then kd-trees; optionally Christensen's precomputed irradiance.
//  2. Irradiance cache prepass (Ward, Rubinstein & Clear 1988; gi/cache_prepass.h): camera
//     rays at 1/16, 1/8, 1/4, 1/2 and full resolution; where the frozen cache has no usable
//     record, a final gather makes one; each pass's records are inserted sorted by (pixel,
//     path), so the cache does not depend on the thread count.
//  3. The render: direct light with soft shadows exactly as raytrace mode, specular reflection
//     and refraction, caustics from the caustic map, indirect diffuse from the cache (or a
//     final gather where no record is usable).
// Every phase shows progress and stops at an interrupt (docs/architecture.md). Under MPI each
// rank traces a range of photon indices, gathers for its tiles of each cache level and renders
// its tiles; the merges keep the fixed orders above, so the image is one process's
// (docs/distributed.md).
#include "modes/modes.h"
#include "modes/render_plan.h"

#include "cluster/cluster.h"
#include "engine/camera_emitter.h"
#include "engine/cancel.h"
#include "engine/phases.h"
#include "engine/progress.h"
#include "engine/spectral_render.h"
#include "gi/cache_prepass.h"
#include "gi/cache_refinement.h"
#include "gi/focus_region.h"
#include "gi/gi_context.h"
#include "gi/gi_pipeline.h"
#include "gi/gi_render_stages.h"
#include "gi/irradiance_cache.h"
#include "gi/photon_emitter.h"
#include "gi/photon_map.h"
#include "gi/photon_pass.h"
#include "gi/progressive_caustics.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <utility>

namespace rayproc {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

const char* debugViewName(GiDebugView v) {
    switch (v) {
    case GiDebugView::None: return "none";
    case GiDebugView::Photons: return "photons";
    case GiDebugView::IcRecords: return "ic-records";
    case GiDebugView::Caustics: return "caustics";
    case GiDebugView::Indirect: return "indirect";
    }
    return "?";
}

// --debug-view's name of one of gi's views; none for any other (path's noise view).
GiDebugView debugViewNamed(const std::string& name) {
    for (GiDebugView v : {GiDebugView::Photons, GiDebugView::IcRecords, GiDebugView::Caustics,
                          GiDebugView::Indirect})
        if (name == debugViewName(v)) return v;
    return GiDebugView::None;
}

// Christensen's precomputed irradiance at every fourth photon of a map: by default each
// estimate made when a lookup first needs it (GiSettings::lazyIrradiance); eagerly, each rank
// estimates a share and every rank gets all, skipped when interrupted.
void precomputePhotonIrradiance(PhotonMap& map, const GiSettings& s, float radius,
                                const EngineSettings& engine, const Cluster& cluster) {
    constexpr int kStride = 4;
    if (s.lazyIrradiance) {
        map.deferIrradiance(s.globalK, radius, kStride); // the subset's kd-tree only
        return;
    }
    std::atomic<std::size_t> done{0};
    std::uint64_t first = 0, last = 0; // this rank's share, for progress
    shareOf(map.precomputeCount(kStride), cluster.rank(), cluster.size(), first, last);
    double total = double(std::max<std::uint64_t>(last - first, 1));
    Progress progress("gi precomputed irradiance", engine.quiet,
                      [&] { return double(done.load()) / total; }, [] { return std::uint64_t(0); });
    bool complete = map.precomputeIrradiance(s.globalK, radius, kStride, &done,
                                             [] { return interruptRequested(); }, &cluster);
    progress.finish(complete);
}

// The ic-records debug view: the render dimmed to a quarter, and every cache record's position
// projected through the (pinhole) camera marked with kIcRecordMarker at its pixel (records are
// points the camera's rays reached, so nearly all project into the image; occlusion is not
// tested). Returns the number of marked pixels (several records may share one).
std::size_t markIcRecords(Image& image, const Camera& cam, const IrradianceCache& cache) {
    for (float& v : image.pixels) v *= 0.25f;
    kernels::CameraFrame f = cameraFrame(cam);
    std::size_t marked = 0;
    for (const IrradianceRecord& rec : cache.records()) {
        Vec3 d = rec.position - f.origin;
        float z = dot(d, f.forward);
        if (!(z > 0)) continue;
        float sx = dot(d, f.right) / (z * f.tanHalfFovY * f.aspect);
        float sy = dot(d, f.up) / (z * f.tanHalfFovY);
        float fx = 0.5f * (sx + 1.0f) * float(image.width);
        float fy = 0.5f * (1.0f - sy) * float(image.height);
        if (!(fx >= 0 && fy >= 0 && fx < float(image.width) && fy < float(image.height))) continue;
        float* px = image.at(int(fx), int(fy));
        if (px[0] == kIcRecordMarker.x && px[1] == kIcRecordMarker.y && px[2] == kIcRecordMarker.z)
            continue;
        px[0] = kIcRecordMarker.x;
        px[1] = kIcRecordMarker.y;
        px[2] = kIcRecordMarker.z;
        ++marked;
    }
    return marked;
}

using Extras = std::vector<std::pair<std::string, double>>;

// What the gi passes share, before the maps: the settings, the gathers' strata, and lengths
// that scale with the scene, or with the part the camera sees when that is much smaller.
GiData giDataFor(const GiSettings& s, const Scene& scene, const FocusRegion& focus,
                 const EngineSettings& engine, Extras& extras) {
    GiData gi;
    gi.settings = s;
    gatherStrata(s.gatherRays, gi.gatherTheta, gi.gatherPhi);
    gatherStrata(filmGatherRays(s), gi.filmGatherTheta, gi.filmGatherPhi);
    // Gradients need the strata layout: independent gather rays (--no-stratification) have none.
    gi.strataWanted = s.irradianceCache && s.icGradients && engine.stratification;
    float diag = std::max(1e-6f, length((focus.active ? focus.bounds : scene.worldBounds()).diagonal()));
    gi.globalRadius = s.globalRadius > 0 ? s.globalRadius : 0.05f * diag;
    gi.causticRadius = s.causticRadius > 0 ? s.causticRadius : 0.02f * diag;
    gi.icMinRadius = 0.005f * diag;
    gi.icMaxRadius = 0.15f * diag;
    extras.push_back({"gi/focus_active", focus.active ? 1.0 : 0.0});
    extras.push_back({"gi/focus_diagonal", double(diag)});
    return gi;
}

// The first pass's products: the photon maps (the caustic map, with progressive caustics, is
// the per-pass ProgressiveCaustics' instead) and what building them took.
struct GiPhotonMaps {
    PhotonMap global, caustic, gatherMap;
    PhotonRounds rounds;
    std::optional<ProgressiveCaustics> progressive;
    double photonSeconds = 0, precomputeSeconds = 0;
};

// First pass: photons. Each rank traces a range of the photon indices; every rank builds the
// merged maps. Progressive caustics trace the first pass's caustic map here and a new one
// before every later render pass. Then Christensen's precomputed irradiance, and the maps
// into `gi`.
void tracePhotonMaps(GiPhotonMaps& maps, GiData& gi, const Scene& scene,
                     const EmbreeScene& accel, const LightSet& lights, const RenderPlan& plan,
                     const FocusRegion& focus, const EngineSettings& engine,
                     const Cluster& cluster, PhaseLog* phases, Stats& photonStats) {
    const GiSettings& s = gi.settings;
    auto t0 = Clock::now();
    // Direct light at gather hits: only delta lights and the sky are sampled there.
    const bool gatherDirect =
        s.gatherDirect && (lights.hasEnvironment() || lights.hasDeltaLights());
    if (s.photons > 0 && plan.globalMap)
        maps.rounds = buildPhotonMap(maps.global, scene, accel, lights, s, engine, cluster, phases,
                                     {false, std::uint32_t(s.photons), 1, "gi photons",
                                      s.photonRounds, std::size_t(s.photons) / 4, gi.spectral},
                                     focus, photonStats, gatherDirect ? &maps.gatherMap : nullptr);
    const bool causticPass = s.caustics && s.causticPhotons > 0 && plan.causticMap;
    gi.roughCaustics = causticPass && s.roughCaustics;
    if (causticPass && s.progressiveCaustics) {
        maps.progressive.emplace(scene, accel, lights, gi, engine, cluster, phases, focus,
                                 photonStats);
        gi.causticFixedRadius = true;
    } else if (causticPass) {
        buildPhotonMap(maps.caustic, scene, accel, lights, s, engine, cluster, phases,
                       {true, std::uint32_t(s.causticPhotons), 2, "gi caustic photons", 1, 0,
                        gi.spectral},
                       focus,
                       photonStats);
    }
    maps.photonSeconds = secondsSince(t0);
    auto t1 = Clock::now();
    PhaseTimer precomputePhase(phases, "irradiance_precompute", PhaseKind::Parallel);
    if (s.precomputedIrradiance && maps.global.size() > 0 && !stopped(cluster))
        precomputePhotonIrradiance(maps.global, s, gi.globalRadius, engine, cluster);
    if (s.precomputedIrradiance && maps.gatherMap.size() > 0 && !stopped(cluster))
        precomputePhotonIrradiance(maps.gatherMap, s, gi.globalRadius, engine, cluster);
    maps.precomputeSeconds = secondsSince(t1);
    precomputePhase.stop();
    gi.global = &maps.global;
    if (gatherDirect && maps.global.size() > 0) gi.globalIndirect = &maps.gatherMap;
    if (!maps.progressive) gi.caustic = &maps.caustic;
}

void addPhotonExtras(Extras& extras, const GiPhotonMaps& maps, const GiData& gi) {
    extras.push_back({"gi/photon_seconds", maps.photonSeconds});
    extras.push_back({"gi/photons_global", double(maps.global.size())});
    extras.push_back({"gi/photon_rounds", double(maps.rounds.rounds)});
    extras.push_back(
        {"gi/photons_emitted", double(maps.rounds.rounds) * double(gi.settings.photons)});
    extras.push_back({"gi/photons_in_view", double(maps.rounds.inView)});
    extras.push_back({"gi/photons_gather_map", double(maps.gatherMap.size())});
    extras.push_back({"gi/photons_caustic", double(gi.caustic ? gi.caustic->size() : 0)});
    extras.push_back({"gi/photon_map_bytes",
                      double(maps.global.memoryBytes() + maps.gatherMap.memoryBytes() +
                             (gi.caustic ? gi.caustic->memoryBytes() : 0))});
    extras.push_back({"gi/precompute_seconds", maps.precomputeSeconds});
}

// The render passes' shading: raytrace's direct light and specular chains, gi's settings, what
// the scene analysis skips.
ShadingPolicy giRenderPolicy(const GiSettings& s, const EngineSettings& engine,
                             const RenderPlan& plan) {
    ShadingPolicy policy;
    policy.maxDepth = s.maxDepth;
    policy.lightSamples = s.lightSamples;
    policy.directLight = s.debugView == GiDebugView::None || s.debugView == GiDebugView::IcRecords;
    policy.rouletteEnabled = s.roulette;
    applyLightSwitches(engine, policy);
    plan.apply(policy);
    return policy;
}

// What the render passes did: maps read, caustic passes, gathers, refinement, cache lookups.
void addRenderExtras(Extras& extras, const RenderResult& r, const GiPhotonMaps& maps,
                     const GiData& gi, const CacheRefinement* refinement) {
    // Precomputed estimates the render needed (all of them when not lazy).
    extras.push_back({"gi/precomputed_estimates",
                      double(maps.global.precomputedEstimatesMade() +
                             maps.gatherMap.precomputedEstimatesMade())});
    extras.push_back({"gi/precomputed_photons",
                      double(maps.global.precomputedCount() + maps.gatherMap.precomputedCount())});
    if (const ProgressiveCaustics* progressive = maps.progressive ? &*maps.progressive : nullptr) {
        extras.push_back({"gi/caustic_passes", double(progressive->passesTraced())});
        extras.push_back({"gi/caustic_first_radius", double(progressive->firstRadius())});
        extras.push_back({"gi/caustic_last_radius", double(gi.causticRadius)});
        if (const CausticPixelRadius* pixels = progressive->pixelRadius())
            extras.push_back({"gi/caustic_mean_pixel_radius", pixels->meanRadius()});
    }
    const ThreadStats& t = r.stats.totals;
    extras.push_back({"gi/gather_rays", double(t.stages[int(kGatherStageId)].raysOut)});
    extras.push_back({"gi/correction_rays", double(t.stages[int(kCorrectionStageId)].raysOut)});
    extras.push_back({"gi/refine_rays", refinement ? double(refinement->raysGathered()) : 0.0});
    extras.push_back({"gi/ic_correction_rays",
                      refinement ? double(refinement->correctionRays()) : 0.0});
    extras.push_back({"gi/ic_correction_weight",
                      refinement ? refinement->correctionWeight() : 0.0});
    extras.push_back({"gi/ic_correction_smoothing",
                      refinement ? double(refinement->correctionSmoothing()) : 0.0});
    const double cacheLookups = double(giCounter(t, kGiCacheLookups));
    extras.push_back({"gi/cache_lookups", cacheLookups});
    extras.push_back({"gi/cache_hit_rate",
                      cacheLookups > 0 ? double(giCounter(t, kGiCacheHits)) / cacheLookups : 0.0});
    const double lookups = cacheLookups + double(giCounter(t, kGiCausticLookups)) +
                           double(giCounter(t, kGiGlobalLookups));
    double gatherSeconds = t.stages[int(kGatherStageId)].seconds;
    extras.push_back({"gi/lookups_per_second", gatherSeconds > 0 ? lookups / gatherSeconds : 0.0});
}

// --stats lists every pipeline in the order they first ran: the pre-passes' (each with its
// Stats and their totals over the ranks), then the render's.
void prependPipelines(RenderStats& stats,
                      std::initializer_list<std::pair<const Stats*, const ThreadStats*>> passes) {
    std::vector<PipelineRun> all;
    for (auto [counted, totals] : passes)
        for (PipelineRun& p : counted->pipelineRuns(*totals)) all.push_back(std::move(p));
    for (PipelineRun& p : stats.pipelines) all.push_back(std::move(p));
    stats.pipelines = std::move(all);
}

} // namespace

std::string GiSettings::toString() const {
    int thetaCount = 1, phiCount = 1;
    gatherStrata(gatherRays, thetaCount, phiCount);
    std::ostringstream o;
    o << "mode=gi spp=" << spp << " max_depth=" << maxDepth << " light_samples=" << lightSamples
      << " photons=" << photons << " photon_rounds=" << photonRounds
      << " caustic_photons=" << causticPhotons
      << " global_k=" << globalK << " caustic_k=" << causticK << " gather_rays=" << gatherRays
      << " gather_strata=" << thetaCount << "x" << phiCount
      << " film_gather_rays=" << rayproc::filmGatherRays(*this)
      << " ic_accuracy=" << icAccuracy << " ic_refine_rays=" << icRefineRays
      << " ic_correction_rays=" << icCorrectionRays
      << " ic_smoothing=" << (icSmoothing ? "on" : "off")
      << " irradiance_cache=" << (irradianceCache ? "on" : "off")
      << " ic_gradients=" << (icGradients ? "on" : "off")
      << " caustics=" << (caustics ? "on" : "off")
      << " progressive_caustics=" << (progressiveCaustics ? "on" : "off")
      << " caustic_pixel_radius=" << (causticPixelRadius ? "on" : "off")
      << " rough_caustics=" << (roughCaustics ? "on" : "off")
      << " caustic_alpha=" << causticAlpha << " caustic_radius=" << causticRadius
      << " max_photon_depth=" << maxPhotonDepth
      << " precomputed_irradiance=" << (precomputedIrradiance ? "on" : "off")
      << " lazy_irradiance=" << (lazyIrradiance ? "on" : "off")
      << " gather_direct=" << (gatherDirect ? "on" : "off")
      << " map_correction=" << (mapCorrection ? "on" : "off")
      << " roulette=" << (roulette ? "on" : "off")
      << " debug_view=" << debugViewName(debugView);
    return o.str();
}

namespace {

// The irradiance cache's prepass (gi/cache_prepass.h), when the cache is on, and its figures;
// every rank's share of its rays summed.
ThreadStats prepassCache(IrradianceCache& cache, GiData& gi, const Scene& scene,
                         const EmbreeScene& accel, const LightSet& lights, const RenderPlan& plan,
                         const EngineSettings& engine, const Cluster& cluster, PhaseLog* phases,
                         Stats& cacheStats, Extras& extras) {
    const GiSettings& s = gi.settings;
    auto t0 = Clock::now();
    gi.cache = s.irradianceCache ? &cache : nullptr;
    CachePrepassCounts counts;
    if (s.irradianceCache && plan.globalMap && !stopped(cluster))
        counts = fillIrradianceCache(scene, accel, lights, gi, cache, engine, cluster, phases,
                                     cacheStats);
    double cacheSeconds = secondsSince(t0);
    ThreadStats cacheTotals = cacheStats.merged();
    sumToRoot(cluster, cacheTotals);
    extras.push_back({"gi/cache_seconds", cacheSeconds});
    extras.push_back({"gi/cache_records", double(cache.size())});
    extras.push_back({"gi/cache_prepass_gather_rays",
                      double(cacheTotals.stages[int(kGatherStageId)].raysOut)});
    extras.push_back({"gi/cache_prepass_levels_retraced", double(counts.levelsRetraced)});
    return cacheTotals;
}

} // namespace

RenderResult renderGi(const Scene& scene, const EmbreeScene& accel, const GiSettings& s,
                      const EngineSettings& engine, const RenderControl& caller) {
    // The mode's clock starts here: the error log's seconds and --time-limit count the
    // photon passes, the precomputation and the cache's prepass too.
    RenderControl control = caller;
    if (!control.workStart) control.workStart = Clock::now();
    const Cluster& cluster = control.clusterOrAlone();
    // Scene analysis: maps, cache and stages the scene cannot use are skipped.
    PhaseTimer lightPhase(control.phases, "light_set"); // and the scene analysis
    LightSet all = LightSet::build(scene, accel);
    RenderPlan plan = planRender(scene, accel, all, engine, kPlanGi);
    if (!plan.render) return blackRender(scene);
    LightSet lights = plan.sampledLights(all);
    lightPhase.stop();
    PhaseTimer focusPhase(control.phases, "focus_region"); // rays from this thread
    FocusRegion focus = cameraFocusRegion(scene, accel, engine.packetWidth);
    focusPhase.stop();
    Extras extras;
    GiData gi = giDataFor(s, scene, focus, engine, extras);
    // Spectral mode: the pre-passes' conversions; the render pass's job sets up its own from
    // the same scene and lights (the same values).
    std::optional<SpectralRender> spectral;
    if (engine.spectral) gi.spectral = &spectral.emplace(scene, lights);

    Stats photonStats;
    GiPhotonMaps maps;
    tracePhotonMaps(maps, gi, scene, accel, lights, plan, focus, engine, cluster, control.phases,
                    photonStats);
    addPhotonExtras(extras, maps, gi);

    // Cache prepass (gi/cache_prepass.h).
    IrradianceCacheSettings cs;
    cs.accuracy = s.icAccuracy;
    cs.useGradients = s.icGradients;
    IrradianceCache cache(scene.worldBounds(), cs);
    Stats cacheStats;
    const ThreadStats cacheTotals = prepassCache(cache, gi, scene, accel, lights, plan, engine,
                                                 cluster, control.phases, cacheStats, extras);

    // Second pass: the render. Before each render pass: a new caustic map (progressive
    // caustics), the records' new gather rays (cache refinement).
    Stats refineStats;
    std::optional<CacheRefinement> refinement;
    if (s.irradianceCache && (s.icRefineRays > 0 || s.icCorrectionRays > 0) && plan.globalMap &&
        cache.size() > 0 && s.debugView == GiDebugView::None) {
        // The records' sums and each record's neighbours (a k-nearest search per record).
        PhaseTimer setupPhase(control.phases, "refinement_setup", PhaseKind::Parallel);
        refinement.emplace(scene, accel, lights, gi, cache, engine, cluster, control.phases,
                           refineStats);
    }
    // Without diffuse surfaces the gather stage would never get work: not registered.
    std::function<void(int, int)> beforePass;
    if ((maps.progressive || refinement) && plan.globalMap)
        beforePass = [&](int pass, int samples) {
            if (maps.progressive) maps.progressive->beginPass(pass, samples);
            if (refinement && pass > 0) refinement->beginPass(pass);
        };
    const ShadingPolicy policy = giRenderPolicy(s, engine, plan);
    GiRenderStages giStages(gi);
    RenderResult r = runRenderJob("gi", scene, accel, lights, policy, s.spp, engine, control,
                                  RadianceStage::Surface, plan.globalMap ? &giStages : nullptr,
                                  beforePass);
    addRenderExtras(extras, r, maps, gi, refinement ? &*refinement : nullptr);
    if (s.debugView == GiDebugView::IcRecords)
        extras.push_back({"gi/ic_marked_pixels", double(markIcRecords(r.image, scene.camera, cache))});
    // runRenderJob measured its wall time from control.workStart: the pre-passes are in it.
    ThreadStats photonTotals = photonStats.merged();
    sumToRoot(cluster, photonTotals);
    ThreadStats refineTotals = refineStats.merged();
    sumToRoot(cluster, refineTotals);
    r.stats.totals.raysTraced +=
        photonTotals.raysTraced + cacheTotals.raysTraced + refineTotals.raysTraced;
    prependPipelines(r.stats, {{&photonStats, &photonTotals},
                               {&cacheStats, &cacheTotals},
                               {&refineStats, &refineTotals}});
    r.stats.extras = extras;
    return r;
}

GiSettings giSettings(const Scene& scene, const ModeOverrides& cli) {
    GiSettings s;
    applySetting(s.spp, scene.render.spp, cli.spp);
    applySetting(s.maxDepth, scene.render.maxDepth, cli.maxDepth);
    applySetting(s.lightSamples, scene.render.lightSamples, cli.lightSamples);
    s.causticPhotons = defaultCausticPhotons(scene.camera.width, scene.camera.height);
    // A pbrt file's sppm settings (the CLI's --caustic-photons still overrides).
    if (scene.render.photonsPerPass > 0) s.causticPhotons = scene.render.photonsPerPass;
    if (scene.render.photonRadius > 0) s.causticRadius = scene.render.photonRadius;
    if (scene.render.maxPhotonDepth > 0) s.maxPhotonDepth = scene.render.maxPhotonDepth;
    s.roulette = cli.roulette;
    s.debugView = debugViewNamed(cli.debugView);
    return s;
}

} // namespace rayproc
