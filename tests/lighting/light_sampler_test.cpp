// LightSampler: the light choice of every mode. Its probabilities must sum to one wherever a
// light can shine, sample() must pick each choice as often as pmf() says (chi-square), for a few
// lights (weighed one by one) and for many (the hierarchy), with and without lights that have
// no position; and LightBounds::importance must be a bound: never 0 where its light can light
// the point, 0 behind a one-sided planar light.
#include "lighting/light_sampler.h"

#include "kernels/random.h"
#include "statistical/chi_square.h"
#include "statistical/statistical.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace rayproc;
using namespace rayproc::test;

namespace {

float rand01(std::uint64_t& state) {
    state = kernels::mix64(state + 1);
    return float(state >> 40) * (1.0f / 16777216.0f);
}

Vec3 randomPoint(std::uint64_t& state, float extent) {
    return {extent * (2 * rand01(state) - 1), extent * (2 * rand01(state) - 1),
            extent * (2 * rand01(state) - 1)};
}

// `count` lights scattered in a 10-unit box: spheres (every direction), one-sided and two-sided
// planar lights facing random ways, and spot-like cones; powers over three decades.
std::vector<LightBounds> scatteredLights(int count, std::uint64_t seed) {
    std::vector<LightBounds> out;
    std::uint64_t s = seed;
    for (int i = 0; i < count; ++i) {
        LightBounds b;
        b.center = randomPoint(s, 5);
        b.radius = 0.05f + rand01(s);
        b.phi = std::pow(10.0f, 3 * rand01(s));
        int kind = i % 4;
        if (kind > 0) {
            b.axis = normalize(randomPoint(s, 1) + Vec3(0, 0, 1e-3f));
            b.thetaO = kind == 3 ? 0.5f * rand01(s) : 0.0f;
            b.thetaE = kind == 3 ? 0.2f : 0.5f * kPi;
            b.twoSided = kind == 2;
        }
        b.updateCone();
        out.push_back(b);
    }
    return out;
}

// excludeEvery k > 0: every k-th choice (from the first) is excluded (LightSet::areaSampler's
// case): never picked, pmf 0, the others' pmfs still summing to one.
void checkSampler(int lights, int infinite, int excludeEvery = 0) {
    std::vector<LightBounds> bounds = scatteredLights(lights, 99 + std::uint64_t(lights));
    std::vector<bool> isInfinite(bounds.size(), false);
    for (int k = 0; k < infinite; ++k) {
        bounds.emplace_back();
        isInfinite.push_back(true);
    }
    std::vector<bool> excluded(bounds.size(), false);
    std::size_t excludedBounded = 0;
    for (std::size_t i = 0; excludeEvery > 0 && i < bounds.size(); i += std::size_t(excludeEvery)) {
        excluded[i] = true;
        if (!isInfinite[i]) ++excludedBounded;
    }
    LightSampler sampler;
    sampler.build(bounds, isInfinite, excluded);
    CHECK(sampler.usesHierarchy() ==
          (std::size_t(lights) - excludedBounded > LightSampler::kExhaustiveLimit));
    std::uint64_t state = 7;
    for (int point = 0; point < 6; ++point) {
        Vec3 p = randomPoint(state, 7);
        // The last bin: no choice. Weighing lights one by one never fails where any light can
        // shine; the hierarchy fails where a cluster bounds more than its children do (both
        // children 0 under a parent > 0): a wasted sample, never a biased one.
        std::vector<double> expected(bounds.size() + 1);
        double total = 0;
        for (std::size_t i = 0; i < bounds.size(); ++i) {
            total += expected[i] = sampler.pmf(p, i);
            if (excluded[i]) REQUIRE(expected[i] == 0.0);
        }
        expected.back() = std::max(0.0, 1.0 - total);
        INFO(lights << " lights, " << infinite << " without position, point " << point);
        if (!sampler.usesHierarchy()) REQUIRE(total == Approx(1.0).epsilon(1e-4));
        REQUIRE(total <= 1.0 + 1e-4);
        REQUIRE(total > 0.5);
        const int n = 200000;
        std::vector<double> observed(bounds.size() + 1, 0.0);
        for (int k = 0; k < n; ++k) {
            LightSampler::Pick pick = sampler.sample(p, (float(k) + rand01(state)) / float(n));
            if (!(pick.pmf > 0)) {
                observed.back() += 1;
                continue;
            }
            REQUIRE(!excluded[pick.index]);
            REQUIRE(pick.pmf == Approx(sampler.pmf(p, pick.index)).epsilon(1e-4));
            observed[pick.index] += 1;
        }
        for (double& e : expected) e *= n;
        ChiSquareResult r = chiSquareTest(observed, expected);
        INFO("chi2 " << r.chi2 << " dof " << r.dof << " p " << r.pValue);
        CHECK(r.pValue > testSignificance());
    }
}

} // namespace

TEST_CASE("LightSampler: picks each choice as often as its pmf says, few lights and many",
          "[lighting][lights][statistical]") {
    checkSampler(1, 0);
    checkSampler(5, 0);
    checkSampler(5, 2, 3);
    checkSampler(40, 0);
    checkSampler(40, 1, 3);
    checkSampler(0, 3);
}

TEST_CASE("LightSampler: lights without a position share n / (n + 1), each by its phi",
          "[lighting][lights]") {
    std::vector<LightBounds> bounds = scatteredLights(3, 9);
    std::vector<bool> infinite(3, false);
    for (float phi : {1.0f, 3.0f}) {
        bounds.emplace_back();
        bounds.back().phi = phi;
        infinite.push_back(true);
    }
    LightSampler sampler;
    sampler.build(bounds, infinite);
    Vec3 p(0.5f, 0.2f, -0.3f);
    CHECK(sampler.pmf(p, 3) == Approx(2.0 / 3.0 * 0.25));
    CHECK(sampler.pmf(p, 4) == Approx(2.0 / 3.0 * 0.75));
    // No weights: alike.
    bounds[3].phi = bounds[4].phi = 0;
    sampler.build(bounds, infinite);
    CHECK(sampler.pmf(p, 3) == Approx(1.0 / 3.0));
    checkSampler(3, 2); // and the picks follow pmf()
}

TEST_CASE("LightSampler: effectiveChoices counts the choices that matter at a point",
          "[lighting][lights]") {
    // Lights alike around the point: all of them matter; one of them alone: one.
    auto ring = [](int count, float phiOfFirst, float phiOfRest) {
        std::vector<LightBounds> bounds;
        for (int k = 0; k < count; ++k) {
            LightBounds b;
            float a = 2 * kPi * float(k) / float(count);
            b.center = Vec3(3 * std::cos(a), 3 * std::sin(a), 0);
            b.radius = 0.1f;
            b.phi = k == 0 ? phiOfFirst : phiOfRest;
            b.updateCone();
            bounds.push_back(b);
        }
        return bounds;
    };
    const Vec3 centre(0, 0, 0);
    LightSampler sampler;
    sampler.build(ring(3, 1, 1), std::vector<bool>(3, false));
    CHECK(sampler.effectiveChoices(centre) == Approx(3.0f).epsilon(1e-4));
    sampler.build(ring(3, 1, 0), std::vector<bool>(3, false));
    CHECK(sampler.effectiveChoices(centre) == Approx(1.0f).epsilon(1e-4));
    // Excluded lights do not count.
    sampler.build(ring(4, 1, 1), std::vector<bool>(4, false), {true, false, false, false});
    CHECK(sampler.effectiveChoices(centre) == Approx(3.0f).epsilon(1e-4));
    // Two lights without a position, alike, beside three alike with one: shares 1/3 each
    // (n / (n + 1) = 2/3 for the two) and 1/9 each.
    std::vector<LightBounds> mixed = ring(3, 1, 1);
    mixed.resize(5);
    mixed[3].phi = mixed[4].phi = 1;
    sampler.build(mixed, {false, false, false, true, true});
    const double shares[] = {1.0 / 9, 1.0 / 9, 1.0 / 9, 1.0 / 3, 1.0 / 3};
    double sum = 0, sumSq = 0;
    for (double x : shares) {
        sum += x;
        sumSq += x * x;
    }
    CHECK(sampler.effectiveChoices(centre) == Approx(sum * sum / sumSq).epsilon(1e-4));
    // Many lights: counted over the hierarchy's 2^kEffectiveDepth clusters, alike here.
    sampler.build(ring(64, 1, 1), std::vector<bool>(64, false));
    REQUIRE(sampler.usesHierarchy());
    CHECK(sampler.effectiveChoices(centre) == Approx(16.0f).epsilon(0.05));
    // Nothing can light the point: 0.
    LightBounds facingAway;
    facingAway.center = Vec3(0, 0, 1);
    facingAway.radius = 0.1f;
    facingAway.phi = 1;
    facingAway.axis = Vec3(0, 0, 1);
    facingAway.thetaO = 0;
    facingAway.updateCone();
    sampler.build({facingAway, facingAway}, {false, false});
    CHECK(sampler.effectiveChoices(centre) == 0.0f);
}

TEST_CASE("LightSampler: a cluster's importance bounds its lights', so the hierarchy keeps every "
          "light that can shine", "[lighting][lights]") {
    std::vector<LightBounds> bounds = scatteredLights(64, 5);
    LightSampler sampler;
    sampler.build(bounds, std::vector<bool>(bounds.size(), false));
    REQUIRE(sampler.usesHierarchy());
    std::uint64_t state = 3;
    for (int point = 0; point < 200; ++point) {
        Vec3 p = randomPoint(state, 8);
        for (std::size_t i = 0; i < bounds.size(); ++i)
            if (bounds[i].importance(p) > 0) REQUIRE(sampler.pmf(p, i) > 0);
    }
}

TEST_CASE("LightBounds: importance is 0 only where no emitting point can face the point",
          "[lighting][lights]") {
    // A one-sided unit disk at the origin facing +z, bounded by a sphere of radius 1.
    LightBounds disk;
    disk.radius = 1;
    disk.phi = 1;
    disk.thetaO = 0;
    disk.updateCone();
    std::uint64_t state = 11;
    for (int k = 0; k < 20000; ++k) {
        Vec3 p = randomPoint(state, 4);
        // A point on the disk's plane region that p sees from the front: z > 0 suffices for
        // some point of the disk to face p.
        float w = disk.importance(p);
        if (p.z > 1e-3f) REQUIRE(w > 0);
        // Behind the plane by more than the bound's reach: nothing faces p.
        if (p.z < -1e-3f && std::abs(p.x) < 4 && length(Vec3(p.x, p.y, 0)) > 0) {
            float sinB = 1.0f / length(p);
            if (sinB < 1 && -p.z / length(p) > sinB) REQUIRE(w == 0.0f);
        }
    }
    // Two-sided: both sides are lit.
    disk.twoSided = true;
    CHECK(disk.importance(Vec3(0.3f, 0.2f, -2)) > 0);
    // A full-sphere light weighs power over squared distance, at least its radius.
    LightBounds sphere;
    sphere.center = Vec3(1, 0, 0);
    sphere.radius = 0.5f;
    sphere.phi = 8;
    sphere.updateCone();
    CHECK(sphere.importance(Vec3(5, 0, 0)) == Approx(8.0f / 16.0f));
    CHECK(sphere.importance(Vec3(1.1f, 0, 0)) == Approx(8.0f / 0.25f));
}

TEST_CASE("Light importance: eight lights at a time agree with one at a time to the bit",
          "[lighting][lights][kernels]") {
    std::vector<LightBounds> bounds = scatteredLights(16, 17);
    std::vector<float> c[12];
    for (const LightBounds& b : bounds) {
        float v[12] = {b.center.x, b.center.y, b.center.z, b.radius * b.radius, b.phi, b.axis.x,
                       b.axis.y,   b.axis.z,   b.cosO,     b.sinO,              b.cosE,
                       b.twoSided ? 1.0f : 0.0f};
        for (int k = 0; k < 12; ++k) c[k].push_back(v[k]);
    }
    kernels::BoundsLanes lanes{c[0].data(), c[1].data(), c[2].data(),  c[3].data(),
                               c[4].data(), c[5].data(), c[6].data(),  c[7].data(),
                               c[8].data(), c[9].data(), c[10].data(), c[11].data()};
    std::uint64_t state = 5;
    int zeros = 0;
    for (int point = 0; point < 2000; ++point) {
        Vec3 p = randomPoint(state, 7);
        if (point == 0) p = bounds[3].center; // at a light's centre
        float wide[16];
        kernels::boundsImportance8(p.x, p.y, p.z, lanes, 0, wide);
        kernels::boundsImportance8(p.x, p.y, p.z, lanes, 8, wide + 8);
        for (std::size_t i = 0; i < 16; ++i) {
            REQUIRE(wide[i] == bounds[i].importance(p));
            REQUIRE(std::isfinite(wide[i]));
            zeros += wide[i] == 0;
        }
    }
    CHECK(zeros > 0); // the one-sided lights' backs were among the points
}
