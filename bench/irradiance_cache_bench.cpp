// The irradiance cache on its own: lookups per second through the octree (and, for scale,
// brute force) and records inserted per second. Records are uniform random in the unit box
// with radii log-uniform in [0.5, 2] x 1/100 of the box, random normals, a = 0.2 (the default):
// a validity radius of ~1/500 of the box.
//
//   BM_IcLookup/records:N/near:0    queries uniform in the box, random normals: almost every
//                                   lookup fails (the renderer's case on a sparse cache)
//   BM_IcLookup/records:N/near:1    queries within a R_i of a random record, normal within
//                                   ~0.1 rad of its normal: most succeed and blend 1-3 records
//   BM_IcLookupBruteForce/...       the same over every record (only at 10K)
//   BM_IcInsert/records:N/batches:B N records into an empty cache in B insert() calls of N / B
//                                   (each call rebuilds the octree over all records so far)
//
// Counters: lookups/s or records/s (over wall time), hit rate, records used per successful
// lookup, MB (IrradianceCache::memoryBytes).
#include "gi/irradiance_cache.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

namespace rayproc::bench {
namespace {

const Bounds3 kBox{Vec3(0.0f), Vec3(1.0f)};
constexpr int kQueries = 4096;

Vec3 randomUnit(std::mt19937& rng) {
    std::normal_distribution<float> g(0.0f, 1.0f);
    for (;;) {
        Vec3 v(g(rng), g(rng), g(rng));
        if (lengthSquared(v) > 1e-6f) return normalize(v);
    }
}

std::vector<IrradianceRecord> randomRecords(int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f),
        logScale(std::log(0.5f), std::log(2.0f));
    std::vector<IrradianceRecord> records(static_cast<std::size_t>(count));
    for (IrradianceRecord& r : records) {
        r.position = Vec3(unit(rng), unit(rng), unit(rng));
        r.normal = randomUnit(rng);
        r.irradiance = Vec3(unit(rng), unit(rng), unit(rng));
        r.radius = 0.01f * std::exp(logScale(rng));
    }
    return records;
}

struct Queries {
    std::vector<Vec3> points, normals;
};

Queries randomQueries(const std::vector<IrradianceRecord>& records, bool near, float a,
                      unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    Queries q;
    for (int i = 0; i < kQueries; ++i) {
        if (near) {
            const IrradianceRecord& r = records[rng() % records.size()];
            float reach = 0.6f * a * r.radius;
            q.points.push_back(r.position + reach * Vec3(sym(rng), sym(rng), sym(rng)));
            q.normals.push_back(normalize(r.normal + 0.1f * Vec3(sym(rng), sym(rng), sym(rng))));
        } else {
            q.points.push_back(Vec3(unit(rng), unit(rng), unit(rng)));
            q.normals.push_back(randomUnit(rng));
        }
    }
    return q;
}

template <bool kBruteForce>
void icLookup(benchmark::State& state) {
    const int count = int(state.range(0));
    const bool near = state.range(1) != 0;
    IrradianceCacheSettings settings;
    IrradianceCache cache(kBox, settings);
    auto records = randomRecords(count, 1);
    cache.insert(records);
    Queries q = randomQueries(records, near, settings.accuracy, 2);
    std::int64_t lookups = 0, hits = 0, used = 0;
    std::size_t i = 0;
    for (auto _ : state) {
        IrradianceCache::LookupResult out;
        bool found = kBruteForce ? cache.lookupBruteForce(q.points[i], q.normals[i], out)
                                 : cache.lookup(q.points[i], q.normals[i], out);
        benchmark::DoNotOptimize(out);
        hits += found ? 1 : 0;
        used += out.used;
        ++lookups;
        i = (i + 1) % kQueries;
    }
    state.counters["lookups/s"] = benchmark::Counter(double(lookups), benchmark::Counter::kIsRate);
    state.counters["hit rate"] = double(hits) / double(lookups);
    state.counters["used/hit"] = hits > 0 ? double(used) / double(hits) : 0.0;
    state.counters["MB"] = double(cache.memoryBytes()) / 1e6;
}

void icInsert(benchmark::State& state) {
    const int count = int(state.range(0));
    const int batches = int(state.range(1));
    auto records = randomRecords(count, 1);
    std::vector<std::vector<IrradianceRecord>> parts;
    for (int b = 0; b < batches; ++b) {
        parts.emplace_back(records.begin() + std::ptrdiff_t(count) * b / batches,
                           records.begin() + std::ptrdiff_t(count) * (b + 1) / batches);
    }
    std::int64_t inserted = 0;
    for (auto _ : state) {
        IrradianceCache cache(kBox, IrradianceCacheSettings{});
        for (const auto& part : parts) cache.insert(part);
        benchmark::DoNotOptimize(cache.size());
        inserted += count;
    }
    state.counters["records/s"] = benchmark::Counter(double(inserted), benchmark::Counter::kIsRate);
}

BENCHMARK_TEMPLATE(icLookup, false)
    ->Name("BM_IcLookup")
    ->ArgNames({"records", "near"})
    ->ArgsProduct({{10000, 100000}, {0, 1}})
    ->UseRealTime()
    ->MinTime(0.2);
BENCHMARK_TEMPLATE(icLookup, true)
    ->Name("BM_IcLookupBruteForce")
    ->ArgNames({"records", "near"})
    ->ArgsProduct({{10000}, {0, 1}})
    ->UseRealTime()
    ->MinTime(0.2);
BENCHMARK(icInsert)
    ->Name("BM_IcInsert")
    ->ArgNames({"records", "batches"})
    ->ArgsProduct({{10000, 100000}, {1, 10}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.2);

} // namespace
} // namespace rayproc::bench
