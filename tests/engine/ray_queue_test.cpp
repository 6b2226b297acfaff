// The central queue and its batch pool: recycling, FIFO order per class with secondary rays
// first, size bookkeeping, and concurrent push/pop that neither loses nor duplicates a batch.
#include "engine/ray_queue.h"

#include <catch2/catch.hpp>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <memory>
#include <set>
#include <vector>

using namespace rayproc;

namespace {

// Batches owned by the test; the queue only moves pointers. The id lives in pixel[0].
std::vector<std::unique_ptr<RayBatch>> makeBatches(int n, RayKind kind) {
    std::vector<std::unique_ptr<RayBatch>> v;
    for (int i = 0; i < n; ++i) {
        auto b = std::make_unique<RayBatch>();
        b->kind = kind;
        b->fresh = kind == RayKind::Camera; // as BatchPool::acquire marks emitter work
        b->pixel[0] = std::uint32_t(i);
        v.push_back(std::move(b));
    }
    return v;
}

// The index a test wrote into a batch of rays' first pixel.
std::uint32_t tagOf(WorkBatch* b) { return static_cast<RayBatch*>(b)->pixel[0]; }

} // namespace

TEST_CASE("RayBatch::push fills consecutive lanes, and a ShadowBatch says which rays were blocked",
          "[engine]") {
    auto b = std::make_unique<RayBatch>();
    CHECK(b->count == 0);
    for (int i = 0; i < kBatchSize; ++i) {
        CHECK_FALSE(b->full());
        int lane = b->push(float(i), 1.0f, 2.0f, 0.0f, 0.0f, 1.0f, 0.5f, float(100 + i));
        REQUIRE(lane == i);
    }
    CHECK(b->count == kBatchSize);
    CHECK(b->full());
    for (int i : {0, 1, 77, kBatchSize - 1}) {
        CHECK(b->ox[i] == float(i));
        CHECK(b->oy[i] == 1.0f);
        CHECK(b->oz[i] == 2.0f);
        CHECK(b->dx[i] == 0.0f);
        CHECK(b->dy[i] == 0.0f);
        CHECK(b->dz[i] == 1.0f);
        CHECK(b->tnear[i] == 0.5f);
        CHECK(b->tfar[i] == float(100 + i));
    }
    b->geomId[3] = 0xffffffffu;
    b->geomId[4] = 0;
    CHECK_FALSE(b->hit(3));
    CHECK(b->hit(4));
    auto shadows = std::make_unique<ShadowBatch>();
    CHECK(shadows->type == BatchType::Shadow);
    CHECK(b->type == BatchType::Rays);
    for (int i = 0; i < 7; ++i) shadows->push(0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 1.0f);
    shadows->tfar[5] = -std::numeric_limits<float>::infinity();
    CHECK(shadows->occluded(5));
    CHECK_FALSE(shadows->occluded(6));
    auto photons = std::make_unique<PhotonBatch>();
    CHECK(photons->type == BatchType::Photons);
    photons->push(0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 1.0f);
    photons->geomId[0] = 0xffffffffu;
    CHECK_FALSE(photons->hit(0));
}

TEST_CASE("BatchPool keeps each type's spent batches apart: a released photon batch comes "
          "back only as a photon batch",
          "[engine]") {
    BatchPool pool;
    PhotonBatch* photons = pool.acquire<PhotonBatch>(RayKind::Camera);
    ShadowBatch* shadows = pool.acquire<ShadowBatch>(RayKind::Shadow);
    CHECK(photons->type == BatchType::Photons);
    CHECK(shadows->type == BatchType::Shadow);
    pool.release(photons);
    pool.release(shadows);
    RayBatch* rays = pool.acquire<RayBatch>(RayKind::Reflection);
    CHECK(static_cast<WorkBatch*>(rays) != static_cast<WorkBatch*>(photons));
    CHECK(static_cast<WorkBatch*>(rays) != static_cast<WorkBatch*>(shadows));
    CHECK(pool.acquire<PhotonBatch>(modeRayKind(0)) == photons);
    CHECK(photons->kind == modeRayKind(0));
    CHECK(pool.acquire<ShadowBatch>(RayKind::Shadow) == shadows);
    CHECK(pool.allocated() == 3);
    pool.release(rays);
    pool.release(photons);
    pool.release(shadows);
}

TEST_CASE("BatchPool recycles released batches", "[engine]") {
    BatchPool pool;
    CHECK(pool.allocated() == 0);
    std::set<RayBatch*> first;
    for (int i = 0; i < 4; ++i) {
        RayBatch* b = pool.acquire<RayBatch>(RayKind::Camera);
        b->count = 17; // dirty it: acquire must reset
        first.insert(b);
    }
    CHECK(first.size() == 4);
    CHECK(pool.allocated() == 4);
    for (RayBatch* b : first) pool.release(b);

    std::set<RayBatch*> second;
    for (int i = 0; i < 4; ++i) {
        RayBatch* b = pool.acquire<RayBatch>(RayKind::Shadow);
        CHECK(b->kind == RayKind::Shadow);
        CHECK(b->count == 0);
        second.insert(b);
    }
    CHECK(second == first);       // the same batches came back
    CHECK(pool.allocated() == 4); // and none was allocated anew

    // One more than was ever released needs a new allocation.
    RayBatch* extra = pool.acquire<RayBatch>(RayKind::Reflection);
    CHECK(first.count(extra) == 0);
    CHECK(pool.allocated() == 5);
    pool.release(extra);
    for (RayBatch* b : second) pool.release(b);

    // Many acquire/release cycles never grow the pool beyond what was held at once.
    for (int round = 0; round < 100; ++round) {
        RayBatch* a = pool.acquire<RayBatch>(RayKind::Camera);
        RayBatch* b = pool.acquire<RayBatch>(RayKind::Refraction);
        pool.release(a);
        pool.release(b);
    }
    CHECK(pool.allocated() == 5);
}

TEST_CASE("BatchPool from two threads allocates at most what is held at once", "[engine]") {
    BatchPool pool;
    tbb::task_arena arena(2);
    arena.execute([&] {
        tbb::parallel_for(
            0, 2,
            [&](int) {
                for (int round = 0; round < 2000; ++round) {
                    RayBatch* held[3];
                    for (auto& h : held) h = pool.acquire<RayBatch>(RayKind::Camera);
                    for (auto& h : held) pool.release(h);
                }
            },
            tbb::simple_partitioner());
    });
    CHECK(pool.allocated() >= 3);
    CHECK(pool.allocated() <= 6);
}

TEST_CASE("RayQueue pops secondary rays before camera rays, FIFO within each", "[engine]") {
    auto cams = makeBatches(3, RayKind::Camera);
    auto shadow = makeBatches(2, RayKind::Shadow);
    auto refl = makeBatches(1, RayKind::Reflection);
    auto refr = makeBatches(1, RayKind::Refraction);

    RayQueue q;
    CHECK(q.empty());
    CHECK(q.size() == 0);
    WorkBatch* out = nullptr;
    CHECK_FALSE(q.tryPop(out));

    // Interleaved pushes.
    q.push(cams[0].get());
    q.push(shadow[0].get());
    q.push(cams[1].get());
    q.push(refl[0].get());
    q.push(cams[2].get());
    q.push(refr[0].get());
    q.push(shadow[1].get());
    CHECK_FALSE(q.empty());
    CHECK(q.size() == 7);

    std::vector<RayBatch*> expected = {shadow[0].get(), refl[0].get(), refr[0].get(),
                                       shadow[1].get(), cams[0].get(), cams[1].get(),
                                       cams[2].get()};
    for (std::size_t i = 0; i < expected.size(); ++i) {
        INFO("pop " << i);
        REQUIRE(q.tryPop(out));
        CHECK(out == expected[i]);
        CHECK(q.size() == expected.size() - i - 1);
    }
    CHECK(q.empty());
    CHECK_FALSE(q.tryPop(out));

    // A secondary batch pushed after camera batches still overtakes them.
    q.push(cams[0].get());
    q.push(cams[1].get());
    REQUIRE(q.tryPop(out));
    CHECK(out == cams[0].get());
    q.push(shadow[0].get());
    REQUIRE(q.tryPop(out));
    CHECK(out == shadow[0].get());
    REQUIRE(q.tryPop(out));
    CHECK(out == cams[1].get());
    CHECK(q.empty());
}

TEST_CASE("RayQueue under concurrent push and pop loses and duplicates nothing", "[engine]") {
    constexpr int kCamera = 300, kSecondary = 300, kTotal = kCamera + kSecondary;
    auto cams = makeBatches(kCamera, RayKind::Camera);
    auto secs = makeBatches(kSecondary, RayKind::Shadow);
    std::vector<RayBatch*> all;
    for (int i = 0; i < kTotal; ++i) {
        RayBatch* b = i < kCamera ? cams[i].get() : secs[i - kCamera].get();
        b->pixel[0] = std::uint32_t(i);
        // Alternate the kinds so both inner queues see traffic.
        if (i % 3 == 1) b->kind = RayKind::Reflection;
        all.push_back(b);
    }

    RayQueue q;
    std::vector<std::atomic<int>> seen(kTotal);
    std::atomic<int> pops{0};
    tbb::task_arena arena(2);
    arena.execute([&] {
        // Phase 1: every index pushes its batch, then pops one (any one) and records it.
        tbb::parallel_for(0, kTotal, [&](int i) {
            q.push(all[i]);
            WorkBatch* b = nullptr;
            if (q.tryPop(b)) {
                seen[tagOf(b)].fetch_add(1);
                ++pops;
            }
        });
    });
    // Phase 2: drain.
    WorkBatch* b = nullptr;
    while (q.tryPop(b)) {
        seen[tagOf(b)].fetch_add(1);
        ++pops;
    }
    CHECK(q.empty());
    CHECK(pops.load() == kTotal);
    int missing = 0, duplicated = 0;
    for (auto& s : seen) {
        missing += s.load() == 0;
        duplicated += s.load() > 1;
    }
    CHECK(missing == 0);
    CHECK(duplicated == 0);

    // Ping-pong: two threads pop and push back the same batches many times; afterwards every
    // batch is in the queue exactly once.
    for (RayBatch* x : all) q.push(x);
    arena.execute([&] {
        tbb::parallel_for(
            0, 2,
            [&](int) {
                for (int round = 0; round < 20000; ++round) {
                    WorkBatch* x = nullptr;
                    if (q.tryPop(x)) q.push(x);
                }
            },
            tbb::simple_partitioner());
    });
    CHECK(q.size() == std::size_t(kTotal));
    for (auto& s : seen) s.store(0);
    while (q.tryPop(b)) seen[tagOf(b)].fetch_add(1);
    CHECK(q.empty());
    for (int i = 0; i < kTotal; ++i) {
        INFO("batch " << i);
        CHECK(seen[i].load() == 1);
    }
}
