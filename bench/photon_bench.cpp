// The photon map (src/gi/photon_map.h): building the kd-tree, k-nearest queries, irradiance
// estimates and Christensen's precomputed irradiance lookups.
//
// The photons are a Cornell-box-like room: uniform over the six inner faces of a unit cube,
// normals pointing inwards, directions cosine-distributed, powers random. Queries are other
// random points on the faces with their face's normal (what a final-gather ray's hit asks),
// cycled from a set of 65,536. maxDistance is 0.1, several times the radius that holds 50
// photons here (about 0.014 in the 500K map), so k decides the radius, as in a render.
//
//   BM_PhotonBuild/photons:1000000            build() of 1M photons (input copy excluded)
//   BM_PhotonNearest/photons:500000/k:50      nearest(): queries/s on one thread
//   BM_PhotonIrradiance/photons:500000/k:50   irradiance(): estimates/s
//   BM_PhotonIrradianceFast/photons:500000/k:50/stride:4   irradianceFast() after precompute
//   BM_PhotonPrecompute/photons:500000/k:50/stride:4       precomputeIrradiance() on every core
#include "gi/photon_map.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace rayproc::bench {
namespace {

constexpr float kMaxDistance = 0.1f;
constexpr int kQueryCount = 65536;

struct SurfacePoint {
    Vec3 p, n;
};

// A uniformly random point on the inside of the unit cube [0,1]^3, with its inward normal.
SurfacePoint randomOnRoom(std::mt19937& rng) {
    std::uniform_real_distribution<float> uni(0, 1);
    int face = int(rng() % 6), axis = face / 2;
    float side = float(face % 2);
    Vec3 p(uni(rng), uni(rng), uni(rng));
    p[axis] = side;
    Vec3 n(0);
    n[axis] = side == 0 ? 1.0f : -1.0f;
    return {p, n};
}

PhotonList roomPhotons(int count) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> uni(0, 1);
    PhotonList photons;
    photons.reserve(std::size_t(count));
    for (int i = 0; i < count; ++i) {
        SurfacePoint s = randomOnRoom(rng);
        Vec3 t, b;
        orthonormalBasis(s.n, t, b);
        float r = std::sqrt(uni(rng)), a = 2 * kPi * uni(rng);
        Vec3 dir = normalize(t * (r * std::cos(a)) + b * (r * std::sin(a)) +
                             s.n * std::sqrt(std::max(0.0f, 1 - r * r)));
        Vec3 power = Vec3(uni(rng), uni(rng), uni(rng)) * (3.0f / float(count));
        photons.push_back({s.p, power, dir, s.n});
    }
    return photons;
}

const std::vector<SurfacePoint>& queries() {
    static const std::vector<SurfacePoint> q = [] {
        std::mt19937 rng(2);
        std::vector<SurfacePoint> v;
        for (int i = 0; i < kQueryCount; ++i) v.push_back(randomOnRoom(rng));
        return v;
    }();
    return q;
}

// Maps built once per (size, stride) for the query benchmarks; stride 0: no precomputation.
const PhotonMap& roomMap(int photons, int k, int stride) {
    static std::mutex mutex; // benchmark threads ask at the same time
    static std::map<std::tuple<int, int, int>, std::unique_ptr<PhotonMap>> maps;
    std::lock_guard lock(mutex);
    auto& m = maps[{photons, stride == 0 ? 0 : k, stride}];
    if (!m) {
        m = std::make_unique<PhotonMap>();
        m->build(roomPhotons(photons));
        if (stride > 0) m->precomputeIrradiance(k, kMaxDistance, stride);
    }
    return *m;
}

void setRate(benchmark::State& state, const char* name) {
    state.counters[name] =
        benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}

void build(benchmark::State& state) {
    PhotonList photons = roomPhotons(int(state.range(0)));
    PhotonMap map;
    for (auto _ : state) {
        state.PauseTiming();
        PhotonList copy = photons;
        state.ResumeTiming();
        map.build(std::move(copy));
        benchmark::DoNotOptimize(map.size());
    }
    state.counters["bytes/photon"] = double(map.memoryBytes()) / double(map.size());
    state.counters["photons/s"] = benchmark::Counter(
        double(state.iterations()) * double(state.range(0)), benchmark::Counter::kIsRate);
}

void nearestQueries(benchmark::State& state) {
    const PhotonMap& map = roomMap(int(state.range(0)), 0, 0);
    int k = int(state.range(1));
    const auto& q = queries();
    PhotonMap::Neighbours nb;
    std::size_t i = 0, found = 0;
    for (auto _ : state) {
        map.nearest(q[i++ % q.size()].p, k, kMaxDistance, nb);
        found += nb.index.size();
    }
    setRate(state, "queries/s");
    state.counters["found"] = benchmark::Counter(double(found) / double(state.iterations()),
                                                 benchmark::Counter::kAvgThreads);
}

void irradianceQueries(benchmark::State& state) {
    const PhotonMap& map = roomMap(int(state.range(0)), 0, 0);
    int k = int(state.range(1));
    const auto& q = queries();
    std::size_t i = 0;
    for (auto _ : state) {
        const SurfacePoint& s = q[i++ % q.size()];
        benchmark::DoNotOptimize(map.irradiance(s.p, s.n, k, kMaxDistance));
    }
    setRate(state, "estimates/s");
}

void irradianceFastQueries(benchmark::State& state) {
    int k = int(state.range(1));
    const PhotonMap& map = roomMap(int(state.range(0)), k, int(state.range(2)));
    const auto& q = queries();
    std::size_t i = 0;
    for (auto _ : state) {
        const SurfacePoint& s = q[i++ % q.size()];
        benchmark::DoNotOptimize(map.irradianceFast(s.p, s.n, k, kMaxDistance));
    }
    setRate(state, "lookups/s");
}

void precompute(benchmark::State& state) {
    PhotonMap map;
    map.build(roomPhotons(int(state.range(0))));
    for (auto _ : state)
        map.precomputeIrradiance(int(state.range(1)), kMaxDistance, int(state.range(2)));
    state.counters["estimates/s"] = benchmark::Counter(
        double(state.iterations()) * double(map.precomputedCount()), benchmark::Counter::kIsRate);
}

BENCHMARK(build)
    ->Name("BM_PhotonBuild")
    ->ArgName("photons")
    ->Arg(100000)
    ->Arg(1000000)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.2);
BENCHMARK(nearestQueries)
    ->Name("BM_PhotonNearest")
    ->ArgNames({"photons", "k"})
    ->Args({500000, 50})
    ->Args({500000, 200})
    ->Args({1000000, 50})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(0.2);
BENCHMARK(nearestQueries)
    ->Name("BM_PhotonNearest")
    ->ArgNames({"photons", "k"})
    ->Args({500000, 50})
    ->Threads(2)
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(0.2);
BENCHMARK(irradianceQueries)
    ->Name("BM_PhotonIrradiance")
    ->ArgNames({"photons", "k"})
    ->Args({500000, 50})
    ->Args({500000, 200})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(0.2);
BENCHMARK(irradianceFastQueries)
    ->Name("BM_PhotonIrradianceFast")
    ->ArgNames({"photons", "k", "stride"})
    ->Args({500000, 50, 4})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(0.2);
BENCHMARK(precompute)
    ->Name("BM_PhotonPrecompute")
    ->ArgNames({"photons", "k", "stride"})
    ->Args({500000, 50, 4})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.2);

} // namespace
} // namespace rayproc::bench
