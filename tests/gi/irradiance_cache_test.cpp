// The irradiance cache: Ward's interpolation rules (constant reproduction, the accuracy a, the
// "in front" test, gradient extrapolation), the octree against brute force on thousands of
// random records, determinism under threads, and Ward & Heckbert's gradient estimates on two
// analytic gathers (a sky brighter on one side, a bright wall on one side).
#include "gi/irradiance_cache.h"

#include <catch2/catch.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

using namespace rayproc;

namespace {

const Bounds3 kUnitBox{Vec3(0.0f), Vec3(1.0f)};

IrradianceRecord makeRecord(const Vec3& p, const Vec3& n, const Vec3& e, float radius) {
    IrradianceRecord r;
    r.position = p;
    r.normal = n;
    r.irradiance = e;
    r.radius = radius;
    return r;
}

Vec3 randomUnit(std::mt19937& rng) {
    std::normal_distribution<float> g(0.0f, 1.0f);
    for (;;) {
        Vec3 v(g(rng), g(rng), g(rng));
        if (lengthSquared(v) > 1e-6f) return normalize(v);
    }
}

// Normals from a small set (the six axes, so exactly opposite normals meet) or random ones.
Vec3 randomNormal(std::mt19937& rng) {
    static const Vec3 kAxes[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                  {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    std::uniform_int_distribution<int> pick(0, 9);
    int i = pick(rng);
    return i < 6 ? kAxes[i] : randomUnit(rng);
}

// A normal within about `amount` radians of n.
Vec3 perturbed(const Vec3& n, std::mt19937& rng, float amount) {
    std::uniform_real_distribution<float> s(-amount, amount);
    return normalize(n + Vec3(s(rng), s(rng), s(rng)));
}

struct RandomSet {
    std::vector<IrradianceRecord> records;
    std::vector<Vec3> queryPoints, queryNormals;
};

// Records as a final gather leaves them: most on surfaces (the planes z = 2 facing up, x = 5
// facing both ways, so records with exactly opposite normals sit on top of each other), some
// anywhere in [0, 10]^3 with random normals, 2% outside the world bounds; radii log-uniform
// over two orders of magnitude. Queries: half near a record (within ~a R, on its plane when it
// has one, normal close to its normal or opposite), half anywhere.
RandomSet randomSet(int recordCount, int queryCount, unsigned seed, float a, bool gradients) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> inBox(0.0f, 10.0f), outside(-5.0f, 15.0f),
        logRadius(std::log(0.05f), std::log(5.0f)), unit(0.0f, 1.0f), grad(-0.5f, 0.5f);
    RandomSet set;
    for (int i = 0; i < recordCount; ++i) {
        float kind = unit(rng);
        Vec3 p(inBox(rng), inBox(rng), inBox(rng));
        Vec3 n = randomNormal(rng);
        if (kind < 0.4f) {
            p.z = 2.0f;
            n = Vec3(0, 0, 1);
        } else if (kind < 0.8f) {
            p.x = 5.0f;
            n = Vec3(unit(rng) < 0.5f ? 1.0f : -1.0f, 0.0f, 0.0f);
        } else if (kind < 0.82f) {
            p = Vec3(outside(rng), outside(rng), 12.0f);
        }
        IrradianceRecord r = makeRecord(p, n, Vec3(unit(rng), unit(rng), unit(rng)) * 10.0f,
                                        std::exp(logRadius(rng)));
        if (gradients) {
            for (int c = 0; c < 3; ++c) {
                r.gradT[c] = Vec3(grad(rng), grad(rng), grad(rng));
                r.gradR[c] = Vec3(grad(rng), grad(rng), grad(rng));
            }
        }
        set.records.push_back(r);
    }
    for (int i = 0; i < queryCount; ++i) {
        if (i % 2 == 0) {
            const IrradianceRecord& r = set.records[rng() % set.records.size()];
            float reach = 0.8f * a * r.radius;
            std::uniform_real_distribution<float> off(-reach, reach);
            Vec3 offset(off(rng), off(rng), off(rng));
            if (r.normal == Vec3(0, 0, 1)) offset.z = 0;
            if (std::abs(r.normal.x) == 1.0f) offset.x = 0;
            set.queryPoints.push_back(r.position + offset);
            set.queryNormals.push_back(i % 8 == 0 ? -r.normal : perturbed(r.normal, rng, 0.3f * a));
        } else {
            set.queryPoints.push_back(Vec3(inBox(rng), inBox(rng), inBox(rng)));
            set.queryNormals.push_back(randomNormal(rng));
        }
    }
    return set;
}

bool sameBits(const IrradianceCache::LookupResult& a, const IrradianceCache::LookupResult& b) {
    return a.used == b.used && std::memcmp(&a.weightSum, &b.weightSum, sizeof(float)) == 0 &&
           std::memcmp(&a.irradiance, &b.irradiance, sizeof(Vec3)) == 0;
}

} // namespace

TEST_CASE("Irradiance cache interpolation reproduces a constant irradiance", "[gi]") {
    const Vec3 e(0.3f, 1.7f, 123.456f);
    for (float a : {0.1f, 0.3f, 1.5f}) {
        RandomSet set = randomSet(3000, 4000, 7, a, false);
        for (IrradianceRecord& r : set.records) r.irradiance = e;
        IrradianceCache cache(Bounds3{Vec3(0.0f), Vec3(10.0f)}, {a, true});
        cache.insert(set.records);
        int hits = 0;
        for (std::size_t i = 0; i < set.queryPoints.size(); ++i) {
            IrradianceCache::LookupResult out;
            if (!cache.lookup(set.queryPoints[i], set.queryNormals[i], out)) continue;
            ++hits;
            CHECK(out.irradiance == e); // double accumulation: exact, not just close
            CHECK(out.weightSum > 1.0f / a);
        }
        CHECK(hits > 100);
    }
}

TEST_CASE("Irradiance cache octree lookups equal brute force", "[gi]") {
    const bool gradients = GENERATE(false, true);
    const float a = GENERATE(0.1f, 0.3f, 1.0f);
    RandomSet set = randomSet(5000, 6000, 11 + unsigned(gradients), a, gradients);
    IrradianceCache cache(Bounds3{Vec3(0.0f), Vec3(10.0f)}, {a, gradients});
    // Three inserts, as three passes would make them.
    for (int part = 0; part < 3; ++part) {
        std::vector<IrradianceRecord> chunk(set.records.begin() + part * 5000 / 3,
                                            set.records.begin() + (part + 1) * 5000 / 3);
        cache.insert(chunk);
    }
    REQUIRE(cache.size() == 5000);
    int hits = 0, multiple = 0, mismatches = 0;
    for (std::size_t i = 0; i < set.queryPoints.size(); ++i) {
        IrradianceCache::LookupResult tree, brute;
        bool foundTree = cache.lookup(set.queryPoints[i], set.queryNormals[i], tree);
        bool foundBrute = cache.lookupBruteForce(set.queryPoints[i], set.queryNormals[i], brute);
        if (foundTree != foundBrute || !sameBits(tree, brute)) ++mismatches;
        hits += foundBrute ? 1 : 0;
        multiple += brute.used > 1 ? 1 : 0;
    }
    CHECK(mismatches == 0);
    CHECK(hits > 1500);    // the comparison covers many successful lookups...
    CHECK(multiple > 500); // ...and many that blend several records
}

TEST_CASE("Irradiance cache accuracy parameter bounds the usable distance", "[gi]") {
    const Vec3 up(0, 0, 1);
    const float radius = 2.0f;
    SECTION("a query farther than a R from the only record fails, a closer one succeeds") {
        for (float a : {0.05f, 0.2f, 0.5f}) {
            IrradianceCache cache(kUnitBox, {a, false});
            cache.insert({makeRecord(Vec3(0.5f, 0.5f, 0.5f), up, Vec3(1.0f), radius)});
            IrradianceCache::LookupResult out;
            CHECK_FALSE(cache.lookup(Vec3(0.5f + 1.01f * a * radius, 0.5f, 0.5f), up, out));
            CHECK(out.used == 0);
            CHECK(cache.lookup(Vec3(0.5f + 0.99f * a * radius, 0.5f, 0.5f), up, out));
            CHECK(out.used == 1);
            // The normal term alone: sqrt(1 - cos) >= a fails at the record's own position.
            float angle = std::acos(1.0f - 1.01f * a * a);
            Vec3 tilted(std::sin(angle), 0.0f, std::cos(angle));
            CHECK_FALSE(cache.lookup(Vec3(0.5f, 0.5f, 0.5f), tilted, out));
        }
    }
    SECTION("smaller a uses fewer records at a given distance") {
        // Records on a plane at distances 0.1, 0.2, ..., 1.0 from the query (radius 2).
        std::vector<IrradianceRecord> records;
        for (int i = 1; i <= 10; ++i) {
            records.push_back(
                makeRecord(Vec3(0.1f * float(i), 0.0f, 0.0f), up, Vec3(1.0f), radius));
        }
        int previous = 0;
        for (float a : {0.06f, 0.12f, 0.22f, 0.32f, 0.52f}) {
            IrradianceCache cache(Bounds3{Vec3(-1.0f), Vec3(1.0f)}, {a, false});
            cache.insert(records);
            IrradianceCache::LookupResult out;
            cache.lookup(Vec3(0.0f), up, out);
            // Usable iff 0.1 i / 2 < a.
            CHECK(out.used == std::min(10, int(std::ceil(a * radius / 0.1f)) - 1));
            CHECK(out.used > previous);
            previous = out.used;
        }
    }
    SECTION("the in-front test rejects a record above the query's tangent plane") {
        IrradianceCache cache(kUnitBox, {0.3f, false});
        IrradianceRecord above = makeRecord(Vec3(0.5f, 0.5f, 0.55f), up, Vec3(1.0f), 1.0f);
        IrradianceRecord below = makeRecord(Vec3(0.5f, 0.5f, 0.45f), up, Vec3(2.0f), 1.0f);
        cache.insert({above, below});
        IrradianceCache::LookupResult out;
        // d_i = (p - p_i) . n: -0.05 R for `above` (in front of p, rejected), +0.05 R for
        // `below` (behind p, used).
        REQUIRE(cache.lookup(Vec3(0.5f, 0.5f, 0.5f), up, out));
        CHECK(out.used == 1);
        CHECK(out.irradiance == Vec3(2.0f));
        // Within the tolerance (0.01 R) a record slightly in front is still used.
        IrradianceCache flat(kUnitBox, {0.3f, false});
        flat.insert({makeRecord(Vec3(0.5f, 0.5f, 0.505f), up, Vec3(3.0f), 1.0f)});
        CHECK(flat.lookup(Vec3(0.5f, 0.5f, 0.5f), up, out));
    }
}

TEST_CASE("Irradiance cache lookups are deterministic and thread-safe", "[gi]") {
    RandomSet set = randomSet(4000, 20000, 23, 0.4f, true);
    IrradianceCache first(Bounds3{Vec3(0.0f), Vec3(10.0f)}, {0.4f, true});
    IrradianceCache second(Bounds3{Vec3(0.0f), Vec3(10.0f)}, {0.4f, true});
    first.insert(set.records);
    second.insert(set.records);
    CHECK(first.memoryBytes() == second.memoryBytes());
    const std::size_t n = set.queryPoints.size();
    std::vector<IrradianceCache::LookupResult> serial(n), parallel(n), other(n);
    for (std::size_t i = 0; i < n; ++i) {
        first.lookup(set.queryPoints[i], set.queryNormals[i], serial[i]);
        second.lookup(set.queryPoints[i], set.queryNormals[i], other[i]);
    }
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        first.lookup(set.queryPoints[i], set.queryNormals[i], parallel[i]);
    });
    int differ = 0, differOther = 0, hits = 0;
    for (std::size_t i = 0; i < n; ++i) {
        differ += sameBits(serial[i], parallel[i]) ? 0 : 1;
        differOther += sameBits(serial[i], other[i]) ? 0 : 1;
        hits += serial[i].used > 0 ? 1 : 0;
    }
    CHECK(differ == 0);
    CHECK(differOther == 0);
    CHECK(hits > 1000);
}

TEST_CASE("Irradiance cache gradients reproduce a linear field", "[gi]") {
    // E(p) = E0 + G_c . p on the plane z = 0.5 with normal +z: records with the exact gradient
    // extrapolate to the same value, so any blend of them is the field.
    const Vec3 up(0, 0, 1);
    const Vec3 e0(2.0f, 3.0f, 4.0f);
    const Vec3 g[3] = {{0.5f, -0.25f, 0.0f}, {-1.0f, 0.75f, 0.0f}, {0.125f, 1.5f, 0.0f}};
    auto field = [&](const Vec3& p) {
        return Vec3(e0.x + dot(g[0], p), e0.y + dot(g[1], p), e0.z + dot(g[2], p));
    };
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> coord(0.0f, 1.0f), radius(0.05f, 0.3f);
    std::vector<IrradianceRecord> records;
    for (int i = 0; i < 400; ++i) {
        Vec3 p(coord(rng), coord(rng), 0.5f);
        IrradianceRecord r = makeRecord(p, up, field(p), radius(rng));
        for (int c = 0; c < 3; ++c) r.gradT[c] = g[c];
        records.push_back(r);
    }
    IrradianceCache cache(kUnitBox, {0.5f, true});
    IrradianceCache noGradients(kUnitBox, {0.5f, false});
    cache.insert(records);
    noGradients.insert(records);
    int hits = 0;
    float worstWithout = 0;
    for (int i = 0; i < 2000; ++i) {
        Vec3 p(coord(rng), coord(rng), 0.5f);
        IrradianceCache::LookupResult out, plain;
        if (!cache.lookup(p, up, out)) continue;
        ++hits;
        Vec3 expected = field(p);
        for (int c = 0; c < 3; ++c) CHECK(out.irradiance[c] == Approx(expected[c]).epsilon(1e-5));
        noGradients.lookup(p, up, plain);
        worstWithout = std::max(worstWithout, std::abs(plain.irradiance.x - expected.x));
    }
    CHECK(hits > 1500);
    CHECK(worstWithout > 1e-2f); // without gradients the same blend is visibly off

    SECTION("the rotational gradient follows (n_i x n) . gradR") {
        IrradianceRecord r = makeRecord(Vec3(0.5f), up, Vec3(1.0f, 2.0f, 3.0f), 1.0f);
        r.gradR[0] = Vec3(0.0f, 0.8f, 0.0f); // brighter when the normal turns towards +x
        r.gradR[1] = Vec3(0.4f, 0.0f, 0.0f);
        IrradianceCache single(kUnitBox, {0.5f, true});
        single.insert({r});
        Vec3 n = normalize(Vec3(0.1f, 0.0f, 1.0f)); // n_i x n = (0, sin, 0)
        IrradianceCache::LookupResult out;
        REQUIRE(single.lookup(Vec3(0.5f), n, out));
        float s = n.x;
        CHECK(out.irradiance.x == Approx(1.0f + 0.8f * s).epsilon(1e-6));
        CHECK(out.irradiance.y == Approx(2.0f).epsilon(1e-6));
        CHECK(out.irradiance.z == Approx(3.0f).epsilon(1e-6));
    }
}

TEST_CASE("Irradiance cache: a translational gradient steps at most the split sphere's change",
          "[gi]") {
    // A record of irradiance 1 and radius 1 whose gradient (40 per unit length, as a gather
    // that saw a sunlit gap close by in a few strata gives) is far steeper than the split-sphere
    // model that chose its radius allows: the step to p is limited to E_i |p - p_i| / R_i, up and
    // down; a gradient within the limit is applied exactly.
    const Vec3 up(0, 0, 1);
    IrradianceRecord r = makeRecord(Vec3(0.5f), up, Vec3(1.0f, 2.0f, 0.5f), 1.0f);
    r.gradT[0] = Vec3(40.0f, 0.0f, 0.0f);
    r.gradT[1] = Vec3(-40.0f, 0.0f, 0.0f);
    r.gradT[2] = Vec3(0.25f, 0.0f, 0.0f); // within the limit
    IrradianceCache cache(kUnitBox, {0.5f, true});
    cache.insert({r});
    for (float d : {0.05f, 0.1f, 0.2f}) {
        IrradianceCache::LookupResult out;
        REQUIRE(cache.lookup(Vec3(0.5f + d, 0.5f, 0.5f), up, out));
        INFO("distance " << d);
        CHECK(out.irradiance.x == Approx(1.0f * (1.0f + d)).epsilon(1e-5)); // not 1 + 40 d
        CHECK(out.irradiance.y == Approx(2.0f * (1.0f - d)).epsilon(1e-5)); // not below zero
        CHECK(out.irradiance.z == Approx(0.5f + 0.25f * d).epsilon(1e-5));
    }
}

TEST_CASE("Irradiance cache bookkeeping", "[gi]") {
    IrradianceCache cache(kUnitBox, {});
    IrradianceCache::LookupResult out;
    CHECK_FALSE(cache.lookup(Vec3(0.5f), Vec3(0, 0, 1), out));
    CHECK(cache.size() == 0);
    std::size_t empty = cache.memoryBytes();
    RandomSet set = randomSet(1000, 0, 3, 0.2f, false);
    cache.insert(set.records);
    CHECK(cache.size() == 1000);
    CHECK(cache.records().size() == 1000);
    CHECK(cache.records()[17].position == set.records[17].position);
    CHECK(cache.memoryBytes() > empty + 1000 * sizeof(IrradianceRecord));
    // Empty or degenerate world bounds are slow, never wrong.
    IrradianceCache unbounded(Bounds3{}, {});
    unbounded.insert(set.records);
    for (int i = 0; i < 200; ++i) {
        const IrradianceRecord& r = set.records[std::size_t(i) * 5];
        IrradianceCache::LookupResult a, b;
        CHECK(unbounded.lookup(r.position, r.normal, a) == cache.lookup(r.position, r.normal, b));
        CHECK(a.used == b.used);
    }
}

namespace {

// One sample per stratum, at the stratum's centre, as a gather with jitter 1/2 would take it.
struct Gather {
    int m, nPhi;
    std::vector<Vec3> radiance;
    std::vector<float> distance;
    GatherStrata strata() const { return {m, nPhi, radiance, distance}; }
    Vec3 irradiance() const {
        Vec3 sum(0.0f);
        for (const Vec3& l : radiance) sum += l;
        return sum * (kPi / float(m * nPhi));
    }
};

// trace(direction) -> (radiance, distance) over the hemisphere of the frame (u, v, n).
template <typename Trace>
Gather gather(int m, int nPhi, const Vec3& u, const Vec3& v, const Vec3& n, Trace trace) {
    Gather g{m, nPhi, {}, {}};
    for (int j = 0; j < m; ++j) {
        for (int k = 0; k < nPhi; ++k) {
            float sinTheta = std::sqrt((float(j) + 0.5f) / float(m));
            float cosTheta = std::sqrt(1.0f - sinTheta * sinTheta);
            float phi = 2.0f * kPi * (float(k) + 0.5f) / float(nPhi);
            Vec3 dir = sinTheta * (std::cos(phi) * u + std::sin(phi) * v) + cosTheta * n;
            auto [l, r] = trace(dir);
            g.radiance.push_back(l);
            g.distance.push_back(r);
        }
    }
    return g;
}

} // namespace

TEST_CASE("Irradiance gradients: a sky brighter on one side turns the rotational gradient "
          "towards it",
          "[gi]") {
    // L(omega) = 1 + omega . b with b in the tangent plane: E(n') = pi + 2 pi / 3 (n' . b), so
    // dE / d(rotation vector) = 2 pi / 3 (n x b): turning n towards b brightens it.
    const Vec3 n = normalize(Vec3(1.0f, 2.0f, 3.0f));
    Vec3 u, v;
    orthonormalBasis(n, u, v);
    const Vec3 b = normalize(0.6f * u - 0.8f * v);
    auto sky = [&](const Vec3& dir) {
        float s = dot(dir, b);
        return std::pair{Vec3(1.0f + s, 1.0f, 1.0f - s), kInfinity};
    };
    Gather g = gather(16, 32, u, v, n, sky);
    Vec3 gradT[3], gradR[3];
    IrradianceCache::estimateGradients(g.strata(), u, v, n, gradT, gradR);
    const Vec3 expected = (2.0f * kPi / 3.0f) * cross(n, b);
    CHECK(dot(gradR[0], cross(n, b)) > 0);
    CHECK(length(gradR[0] - expected) < 0.01f * length(expected));
    CHECK(length(gradR[1]) < 1e-4f);                               // uniform channel
    CHECK(length(gradR[2] + expected) < 0.01f * length(expected)); // darker towards b
    for (int c = 0; c < 3; ++c) CHECK(gradT[c] == Vec3(0.0f));     // the sky does not move

    // Used as the record's gradient, it predicts the irradiance a fresh gather finds for a
    // normal tilted towards b.
    const Vec3 tilted = normalize(n + 0.1f * b);
    const Vec3 tiltedU = normalize(u - dot(u, tilted) * tilted);
    Gather fresh = gather(64, 128, tiltedU, cross(tilted, tiltedU), tilted, sky);
    float predicted = g.irradiance().x + dot(cross(n, tilted), gradR[0]);
    CHECK(predicted == Approx(fresh.irradiance().x).epsilon(1e-3));
}

TEST_CASE("Irradiance gradients: a wall close on one side gives a translational gradient", "[gi]") {
    // A wall x = d, 0 <= z <= h, infinite along y, seen from (x, 0, 0) with n = +z. Channel 0:
    // bright wall (1) under a black sky; channel 1: black wall under a white sky. Moving
    // towards the wall (+x) it covers more of the hemisphere.
    const Vec3 u(1, 0, 0), v(0, 1, 0), n(0, 0, 1);
    const float d = 1.0f, h = 1.0f;
    auto scene = [&](float x) {
        return [=](const Vec3& dir) {
            if (dir.x > 0) {
                float t = (d - x) / dir.x;
                if (t * dir.z <= h) return std::pair{Vec3(1.0f, 0.0f, 0.5f), t};
            }
            return std::pair{Vec3(0.0f, 1.0f, 0.5f), kInfinity};
        };
    };
    Gather g = gather(24, 48, u, v, n, scene(0.0f));
    Vec3 gradT[3], gradR[3];
    IrradianceCache::estimateGradients(g.strata(), u, v, n, gradT, gradR);
    // Reference: central difference of a fine quadrature of E.
    const float step = 0.01f;
    float reference = (gather(400, 800, u, v, n, scene(step)).irradiance().x -
                       gather(400, 800, u, v, n, scene(-step)).irradiance().x) /
                      (2.0f * step);
    REQUIRE(reference > 0);
    CHECK(gradT[0].x > 0);
    CHECK(gradT[0].x == Approx(reference).epsilon(0.1));
    CHECK(gradT[1].x == Approx(-gradT[0].x).epsilon(1e-5)); // dark wall: the opposite
    CHECK(std::abs(gradT[0].y) < 1e-3f * gradT[0].x);       // symmetric along the wall
    CHECK(gradT[0].z == 0.0f);                              // in the tangent plane
    CHECK(length(gradT[2]) < 1e-6f);                        // wall and sky equally bright
}
