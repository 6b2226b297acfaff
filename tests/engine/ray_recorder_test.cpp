// The benchmarks' ray recorder (engine/ray_recorder.h): while a scope is active it sees every
// ray the engine hands to Embree, per kind as the statistics count them, before tracing (so a
// replay traces the same rays); it changes nothing in the image; without a scope nothing is
// recorded.
#include "engine/intersect.h"
#include "engine/pipeline.h"
#include "engine/ray_recorder.h"
#include "gi/gi_pipeline.h"
#include "gi/photon_emitter.h"
#include "gi/photon_stage.h"
#include "test_util.h"

#include <cstring>
#include <map>
#include <type_traits>

using namespace rayproc;
using namespace rayproc::test;

namespace {

std::map<RayKind, std::uint64_t> raysByKind(const std::vector<RecordedBatch>& batches) {
    std::map<RayKind, std::uint64_t> n;
    for (const RecordedBatch& b : batches) n[b.kind] += std::uint64_t(b.count);
    return n;
}

bool sameImage(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof a.pixels[0]) == 0;
}

} // namespace

TEST_CASE("the ray recorder sees every traced ray of a render, only while active",
          "[engine][recorder]") {
    auto scene = loadSceneAt("cornell-box", 48, 48);
    EmbreeScene accel(*scene);
    RenderOptions o;
    o.mode = "path";
    o.spp = 2;
    o.threads = 2;

    RayRecorder recorder(2);
    RenderResult recorded;
    {
        RayRecorder::Scope scope(recorder);
        REQUIRE(RayRecorder::active() == &recorder);
        recorded = render(*scene, accel, o);
    }
    REQUIRE(RayRecorder::active() == nullptr);
    std::vector<RecordedBatch> batches = recorder.batches();
    const ThreadStats& t = recorded.stats.totals;
    CHECK(recorder.rayCount() == t.raysTraced);
    auto byKind = raysByKind(batches);
    CHECK(byKind[RayKind::Camera] == t.samples);
    CHECK(byKind[RayKind::Shadow] == t.stages[int(StageId::Occlude)].raysIn);
    CHECK(byKind[RayKind::Camera] + byKind[RayKind::Reflection] + byKind[RayKind::Refraction] ==
          t.stages[int(StageId::Intersect)].raysIn);
    for (const RecordedBatch& b : batches) {
        REQUIRE(b.count > 0);
        REQUIRE(b.ox.size() == std::size_t(b.count));
        REQUIRE(b.tfar.size() == std::size_t(b.count));
    }

    // Whole batches: at most the cap per kind, untraced (shadow rays keep their tfar >= 0).
    auto shadows = recorder.fullBatches<ShadowBatch>(RayKind::Shadow);
    CHECK(recorder.fullBatches<RayBatch>(RayKind::Shadow).empty());
    CHECK(shadows.size() == 2);
    for (const auto& b : shadows)
        for (int i = 0; i < b->count; ++i) CHECK(b->tfar[i] >= 0.0f);
    CHECK(recorder.fullBatches<RayBatch>(RayKind::Camera).size() == 2);

    // Recording changes nothing, and nothing is recorded without a scope.
    RenderResult plain = render(*scene, accel, o);
    CHECK(sameImage(plain.image, recorded.image));
    CHECK(recorder.rayCount() == t.raysTraced);
}

TEST_CASE("recorded rays replayed through bare Embree give the engine's hits",
          "[engine][recorder]") {
    auto scene = loadSceneAt("cornell-box", 32, 32);
    EmbreeScene accel(*scene);
    RenderOptions o;
    o.spp = 1;
    o.threads = 1;
    RayRecorder recorder(1000);
    {
        RayRecorder::Scope scope(recorder);
        render(*scene, accel, o);
    }
    // The whole batches (payload and rays as recorded) traced by the engine, against the
    // compact recording traced ray by ray with rtcIntersect1 / rtcOccluded1.
    std::vector<RecordedBatch> batches = recorder.batches();
    Intersector intersector(accel.root(), 16);
    ThreadStats stats;
    std::size_t compared = 0;
    auto replay = [&](RayKind kind, const auto& full) {
        REQUIRE(!full.empty());
        std::size_t next = 0; // one thread: full batches are the first recorded ones, in order
        for (const RecordedBatch& r : batches) {
            if (r.kind != kind || next >= full.size()) continue;
            auto b = *full[next++];
            REQUIRE(b.count == r.count);
            intersector.trace(b, stats);
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            for (int i = 0; i < r.count; ++i) {
                RTCRayHit rh{};
                rh.ray.org_x = r.ox[i];
                rh.ray.org_y = r.oy[i];
                rh.ray.org_z = r.oz[i];
                rh.ray.dir_x = r.dx[i];
                rh.ray.dir_y = r.dy[i];
                rh.ray.dir_z = r.dz[i];
                rh.ray.tnear = r.tnear[i];
                rh.ray.tfar = r.tfar[i];
                rh.ray.mask = 0xffffffffu;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                if constexpr (std::is_same_v<decltype(b), ShadowBatch>) {
                    CHECK(r.occlusion);
                    rtcOccluded1(accel.root(), &ctx, &rh.ray);
                    CHECK((rh.ray.tfar < 0) == b.occluded(i));
                } else {
                    CHECK_FALSE(r.occlusion);
                    rtcIntersect1(accel.root(), &ctx, &rh);
                    CHECK(rh.hit.geomID == b.geomId[i]);
                    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID)
                        CHECK(rh.hit.primID == b.primId[i]);
                }
                ++compared;
            }
        }
    };
    replay(RayKind::Camera, recorder.fullBatches<RayBatch>(RayKind::Camera));
    replay(RayKind::Shadow, recorder.fullBatches<ShadowBatch>(RayKind::Shadow));
    CHECK(compared > 1000);
}

TEST_CASE("the ray recorder keeps gi's photons whole as photon batches", "[engine][recorder]") {
    auto scene = loadSceneAt("cornell-box", 16, 16);
    EmbreeScene accel(*scene);
    LightSet lights = LightSet::build(*scene, accel);
    Film film(1, 1);
    ShadingPolicy policy;
    RenderContext rc{*scene, accel, lights, policy, film, 1};
    Stats stats;
    PhotonStage stage(rc, /*causticPass=*/false, 8);
    RayRecorder recorder(3);
    {
        RayRecorder::Scope scope(recorder);
        Pipeline pipeline("photons", "photon", accel.root(), 16, stats, 1);
        pipeline.stage("photon", {kPhotonQueue}, stage);
        PhotonEmitter emitter(lights, scene->worldBounds(), 5000, 1, 1);
        pipeline.run(emitter, [] { return false; });
    }
    CHECK(recorder.rayCount() == stats.merged().raysTraced);
    auto photons = recorder.fullBatches<PhotonBatch>(kPhotonRay);
    CHECK(photons.size() == 3);
    CHECK(recorder.fullBatches<RayBatch>(kPhotonRay).empty());
    for (const auto& b : photons) {
        CHECK(b->type == BatchType::Photons);
        CHECK(b->count > 0);
    }
    for (const RecordedBatch& r : recorder.batches()) CHECK_FALSE(r.occlusion);
}
