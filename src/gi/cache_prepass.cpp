#include "gi/cache_prepass.h"

#include "cluster/cluster.h"
#include "core/error.h"
#include "engine/camera_emitter.h"
#include "engine/cancel.h"
#include "engine/film.h"
#include "engine/phases.h"
#include "engine/pipeline.h"
#include "engine/progress.h"
#include "engine/reflection_stage.h"
#include "engine/refraction_stage.h"
#include "engine/shadow_stage.h"
#include "engine/surface_stage.h"
#include "gi/gather_stage.h"
#include "gi/gi_context.h"
#include "gi/irradiance_cache.h"
#include "gi/photon_pass.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <tuple>
#include <vector>

namespace rayproc {

namespace {

// A gather the prepass made, as plain values: what a record is made of.
struct MadeGather {
    std::uint64_t key = 0;
    Vec3 position, normal, u, v, origin, geometricNormal;
    std::int64_t radiance[3] = {0, 0, 0};
    std::int64_t inverseDistance = 0;
    std::int32_t rays = 0;
    std::vector<Vec3> strataRadiance;
    std::vector<float> strataDistance;
};

template <typename T>
void putValue(std::vector<std::uint8_t>& out, const T& v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    out.insert(out.end(), p, p + sizeof(T));
}

template <typename T>
T getValue(const std::vector<std::uint8_t>& in, std::size_t& at) {
    T v;
    std::memcpy(&v, &in[at], sizeof(T));
    at += sizeof(T);
    return v;
}

// Every rank's gathers of a prepass level, on every rank (a collective). The order does not
// matter: the caller sorts them.
std::vector<MadeGather> mergeGatherShares(const Cluster& cluster, std::vector<MadeGather> mine) {
    if (!cluster.distributed()) return mine;
    std::vector<std::uint8_t> bytes;
    for (const MadeGather& g : mine) {
        putValue(bytes, g.key);
        for (const Vec3* w : {&g.position, &g.normal, &g.u, &g.v, &g.origin, &g.geometricNormal})
            putValue(bytes, *w);
        for (std::int64_t r : g.radiance) putValue(bytes, r);
        putValue(bytes, g.inverseDistance);
        putValue(bytes, g.rays);
        putValue(bytes, std::uint32_t(g.strataRadiance.size()));
        for (const Vec3& r : g.strataRadiance) putValue(bytes, r);
        putValue(bytes, std::uint32_t(g.strataDistance.size()));
        for (float d : g.strataDistance) putValue(bytes, d);
    }
    mine = {};
    std::vector<std::uint8_t> all = cluster.gatherAll(bytes);
    std::vector<MadeGather> out;
    for (std::size_t at = 0; at < all.size();) {
        MadeGather g;
        g.key = getValue<std::uint64_t>(all, at);
        for (Vec3* w : {&g.position, &g.normal, &g.u, &g.v, &g.origin, &g.geometricNormal})
            *w = getValue<Vec3>(all, at);
        for (std::int64_t& r : g.radiance) r = getValue<std::int64_t>(all, at);
        g.inverseDistance = getValue<std::int64_t>(all, at);
        g.rays = getValue<std::int32_t>(all, at);
        g.strataRadiance.resize(getValue<std::uint32_t>(all, at));
        for (Vec3& r : g.strataRadiance) r = getValue<Vec3>(all, at);
        g.strataDistance.resize(getValue<std::uint32_t>(all, at));
        for (float& d : g.strataDistance) d = getValue<float>(all, at);
        out.push_back(std::move(g));
    }
    return out;
}

// The levels' resolutions: 1/16 of the camera's, then 1/8, 1/4, 1/2 and the full one.
constexpr int kScales[] = {16, 8, 4, 2, 1};

Camera levelCamera(const Camera& full, int scale) {
    Camera cam = full;
    cam.width = std::max(1, (full.width + scale - 1) / scale);
    cam.height = std::max(1, (full.height + scale - 1) / scale);
    return cam;
}

// What the progress line reads: the pixels of the levels done and, while a level runs, its
// emitter (published only while it lives).
struct PrepassProgress {
    double allPixels = 0;
    std::atomic<double> pixelsBefore{0};
    std::atomic<const CameraEmitter*> current{nullptr};
    std::atomic<double> currentPixels{0};

    double fraction() const {
        double f = pixelsBefore.load();
        if (const CameraEmitter* c = current.load())
            f += currentPixels.load() * double(c->unitsEmitted()) /
                 double(std::max<std::uint64_t>(c->unitsPerPass(), 1));
        return f / allPixels;
    }
};

// Traces one level: camera rays at `cam`'s resolution (this rank's tiles), the gather stage
// making a record request wherever the frozen cache has no usable record.
void traceLevel(const Scene& scene, const EmbreeScene& accel, const LightSet& lights,
                const GiData& gi, IcRequests& requests, const Camera& cam, int filmExponent,
                const EngineSettings& engine, const Cluster& cluster, PhaseLog* phases,
                Stats& stats,
                PrepassProgress& progress) {
    Film film(cam.width, cam.height, filmExponent);
    ShadingPolicy policy;
    policy.maxDepth = gi.settings.maxDepth;
    policy.handlersOnly = true;
    policy.stratify = engine.stratification;
    policy.rouletteEnabled = gi.settings.roulette;
    RenderContext rc{scene, accel, lights, policy, film, engine.seed};
    rc.spectral = gi.spectral;
    ShadowStage shadow(rc);
    ReflectionStage reflection(rc);
    RefractionStage refraction(rc);
    GatherStage gather(rc, gi, &requests);
    SurfaceStage surface(rc, shadow, reflection, refraction);
    surface.addDiffuseHandler(gather);
    Pipeline pipeline("cache prepass", "camera", accel.root(), engine.packetWidth, stats,
                      engine.threads);
    pipeline
        .stage("surface",
               {engineRoute(RayKind::Camera), engineRoute(RayKind::Reflection),
                engineRoute(RayKind::Refraction)},
               surface)
        .stage("shadow", {engineRoute(RayKind::Shadow)}, shadow)
        .stage("gather", {kGatherQueue, kGatherShadowQueue}, gather)
        .timedAs(phases, "cache_prepass");
    CameraEmitter camera(rc, &cam);
    camera.setShare(cluster.rank(), cluster.size()); // each rank gathers for its tiles
    camera.beginPass(0, 1);
    progress.currentPixels = double(cam.width) * cam.height;
    progress.current = &camera;
    pipeline.run(camera, [] { return interruptRequested(); });
    progress.current = nullptr;
    progress.pixelsBefore = progress.pixelsBefore.load() + double(cam.width) * cam.height;
}

// traceLevel with room for every gather the level wants. Two slots a pixel hold most levels;
// where smooth glass splits the camera's paths into more visible points (both lobes of every
// interface), the slots ran out and which gathers got one depended on the threads' timing, so
// the records, and the image, did too. The level's wants are the same whatever the timing
// (its lookups read only earlier levels' records), so a level that wanted more is traced
// again with room for exactly that many. Returns whether it did.
bool traceLevelWhole(const Scene& scene, const EmbreeScene& accel, const LightSet& lights,
                     const GiData& gi, IcRequests& requests, const Camera& cam, int filmExponent,
                     const EngineSettings& engine, const Cluster& cluster, PhaseLog* phases,
                     Stats& stats, PrepassProgress& progress) {
    const double pixelsBefore = progress.pixelsBefore.load();
    std::size_t capacity = std::size_t(cam.width) * cam.height * 2;
    for (bool again = false;; again = true) {
        requests.beginLevel(capacity);
        traceLevel(scene, accel, lights, gi, requests, cam, filmExponent, engine, cluster, phases,
                   stats, progress);
        if (requests.wanted() <= capacity || interruptRequested()) return again;
        capacity = requests.wanted();
        progress.pixelsBefore = pixelsBefore; // the level again
    }
}

// The level's gathers as plain values, in slot order.
std::vector<MadeGather> madeGathers(IcRequests& requests) {
    std::vector<MadeGather> made;
    const std::size_t n = requests.claimed();
    for (std::size_t i = 0; i < n; ++i) {
        const IcRequest& r = requests[std::uint32_t(i)];
        if (r.rays.load() <= 0) continue;
        MadeGather g;
        g.key = r.key;
        g.position = r.position;
        g.normal = r.normal;
        g.u = r.u;
        g.v = r.v;
        g.origin = r.origin;
        g.geometricNormal = r.geometricNormal;
        for (int c = 0; c < 3; ++c) g.radiance[c] = r.radiance[c].load();
        g.inverseDistance = r.inverseDistance.load();
        g.rays = r.rays.load();
        g.strataRadiance.resize(r.strataRadiance.size());
        for (std::size_t s = 0; s < r.strataRadiance.size(); ++s)
            for (int c = 0; c < 3; ++c)
                g.strataRadiance[s][c] =
                    float(double(r.strataRadiance[s][std::size_t(c)]) / requests.radianceScale());
        g.strataDistance = r.strataDistance;
        made.push_back(std::move(g));
    }
    return made;
}

// A gather's record: irradiance, the harmonic mean distance as radius (clamped), and with
// strata Ward & Heckbert's gradients.
IrradianceRecord recordOf(const MadeGather& r, const GiData& gi, double radianceScale) {
    double rays = r.rays;
    IrradianceRecord rec;
    rec.position = r.position;
    rec.normal = r.normal;
    rec.gatherOrigin = r.origin;
    rec.geometricNormal = r.geometricNormal;
    rec.gatherRays = r.rays;
    // Cosine-weighted gather: E = pi / N * sum L.
    for (int c = 0; c < 3; ++c)
        rec.irradiance[c] = float(kPi * double(r.radiance[c]) / radianceScale / rays);
    double inv = double(r.inverseDistance) / IcRequest::kScale;
    float harmonic = inv > 0 ? float(rays / inv) : gi.icMaxRadius;
    rec.radius = std::clamp(harmonic, gi.icMinRadius, gi.icMaxRadius);
    if (gi.strataWanted &&
        r.strataRadiance.size() == std::size_t(gi.gatherTheta) * std::size_t(gi.gatherPhi)) {
        // Ward & Heckbert's gradients from the same strata (the irradiance above is
        // pi / (M N) times their sum).
        GatherStrata strata;
        strata.thetaCount = gi.gatherTheta;
        strata.phiCount = gi.gatherPhi;
        strata.radiance = r.strataRadiance;
        strata.distance = r.strataDistance;
        IrradianceCache::estimateGradients(strata, r.u, r.v, r.normal, rec.gradT, rec.gradR);
    }
    return rec;
}

} // namespace

CachePrepassCounts fillIrradianceCache(const Scene& scene, const EmbreeScene& accel,
                                       const LightSet& lights, const GiData& gi,
                                       IrradianceCache& cache, const EngineSettings& engine,
                                       const Cluster& cluster, PhaseLog* phases, Stats& stats) {
    RAYPROC_CHECK(gi.cache == &cache);
    IcRequests requests;
    const int filmExponent = Film::exponentFor(lights.radianceScale(scene.worldBounds()));
    requests.setRadianceScale(IcRequest::radianceScale(filmExponent));
    CachePrepassCounts counts;
    // Progress: the levels weighted by their pixels (the full-resolution level is 3/4 of them).
    PrepassProgress levels;
    for (int scale : kScales) {
        const Camera cam = levelCamera(scene.camera, scale);
        levels.allPixels += double(cam.width) * cam.height;
    }
    Progress progress("gi irradiance cache", engine.quiet, [&] { return levels.fraction(); },
                      [&] { return std::uint64_t(stats.merged().raysTraced); });
    for (int scale : kScales) {
        // The level's own work on this thread: its film and stages, merging, sorting and
        // inserting its records; the gathers are the workers' (cache_prepass).
        PhaseTimer levelPhase(phases, "cache_insert");
        if (stopped(cluster)) break;
        const Camera cam = levelCamera(scene.camera, scale);
        if (traceLevelWhole(scene, accel, lights, gi, requests, cam, filmExponent, engine,
                            cluster, phases, stats, levels))
            ++counts.levelsRetraced;
        // New records (every rank's) in a fixed order, then into the cache.
        std::vector<MadeGather> made = mergeGatherShares(cluster, madeGathers(requests));
        // A level cut short would leave holes in the cache; the render is cancelled anyway.
        if (stopped(cluster)) break;
        std::sort(made.begin(), made.end(), [](const MadeGather& a, const MadeGather& b) {
            if (a.key != b.key) return a.key < b.key;
            return std::tie(a.position.x, a.position.y, a.position.z) <
                   std::tie(b.position.x, b.position.y, b.position.z);
        });
        std::vector<IrradianceRecord> records;
        for (const MadeGather& r : made) records.push_back(recordOf(r, gi, requests.radianceScale()));
        cache.insert(records);
        counts.records += records.size();
    }
    progress.finish(!interruptRequested());
    return counts;
}

} // namespace rayproc
