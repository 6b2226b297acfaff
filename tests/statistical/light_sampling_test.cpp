// Chi-square tests of LightSource::sample against LightSource::pdf (the density path mode's
// multiple importance sampling assumes) for the area lights as LightSet::build makes them from
// a scene: a quad (mesh), a sphere seen from outside (uniform cone) and from inside (uniform
// area), and a disk. Directions from a shading point are binned around the direction to the
// light; each bin's expected count integrates pdf(p, q, nq) over the directions whose ray hits
// the light at q. Every sample must also be consistent: weight * pdf = radiance, the sample's
// pdf equals pdf() at the point it picked, and that point lies on the light.
#include "statistical.h"

#include "lighting/light_set.h"
#include "test_util.h"

#include <optional>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// Emitters: a 2 x 2 quad at y = 2 facing down, a sphere, a disk tilted towards the origin.
const char* kLightsScene = R"({
  "nodes": [
    {"type": "quad", "emission": [1, 2, 3], "corners": [[-1, 2, -1], [1, 2, -1], [1, 2, 1], [-1, 2, 1]]},
    {"type": "sphere", "emission": [4, 5, 6], "center": [3, 0.5, 0], "radius": 0.8},
    {"type": "disk", "emission": [2, 2, 1], "center": [0, 0.5, 2], "normal": [0, -0.3, -1], "radius": 0.9}
  ]})";

struct Hit {
    Vec3 q, n;
};

// The first point of the light a ray from p along w meets, if any.
std::optional<Hit> intersectLight(const LightSource& l, const Vec3& p, const Vec3& w) {
    switch (l.kind) {
    case LightSource::Kind::AreaMesh: {
        std::optional<Hit> best;
        float bestT = kInfinity;
        for (std::size_t t = 0; t + 2 < l.triangles.size(); t += 3) {
            const Vec3 &a = l.triangles[t], &b = l.triangles[t + 1], &c = l.triangles[t + 2];
            Vec3 e1 = b - a, e2 = c - a, pv = cross(w, e2);
            float det = dot(e1, pv);
            if (std::abs(det) < 1e-12f) continue;
            Vec3 tv = p - a;
            float u = dot(tv, pv) / det;
            Vec3 qv = cross(tv, e1);
            float v = dot(w, qv) / det;
            float tt = dot(e2, qv) / det;
            if (u < 0 || v < 0 || u + v > 1 || tt <= 0 || tt >= bestT) continue;
            bestT = tt;
            best = Hit{p + w * tt, normalize(cross(e1, e2))};
        }
        return best;
    }
    case LightSource::Kind::AreaSphere: {
        Vec3 oc = p - l.center;
        float b = dot(w, oc), c = lengthSquared(oc) - l.radius * l.radius;
        float disc = b * b - c;
        if (disc < 0) return std::nullopt;
        float s = std::sqrt(disc);
        float t = -b - s > 0 ? -b - s : -b + s;
        if (t <= 0) return std::nullopt;
        Vec3 q = p + w * t;
        return Hit{q, normalize(q - l.center)};
    }
    case LightSource::Kind::AreaDisk: {
        float dn = dot(w, l.normal);
        if (std::abs(dn) < 1e-12f) return std::nullopt;
        float t = dot(l.center - p, l.normal) / dn;
        if (t <= 0) return std::nullopt;
        Vec3 q = p + w * t;
        if (lengthSquared(q - l.center) > l.radius * l.radius) return std::nullopt;
        return Hit{q, l.normal};
    }
    default: return std::nullopt;
    }
}

const LightSource& lightOfKind(const LightSet& set, LightSource::Kind kind) {
    for (const LightSource& l : set.lights)
        if (l.kind == kind) return l;
    FAIL("no light of the requested kind");
    return set.lights.front();
}

// Samples `light` from p; bins around `axis` out to the cone cos >= cosMin, which must hold
// the whole light.
void testLight(const LightSource& light, const Vec3& p, const Vec3& axis, float cosMin,
               std::uint64_t seed, const std::string& label) {
    DirectionHistogram hist(axis, cosMin, kThetaBins, kPhiBins);
    TestRng rng(seed);
    int invalid = 0, weightMismatches = 0, pdfMismatches = 0, offLight = 0;
    for (int i = 0; i < kSamples; ++i) {
        LightSample s = light.sample(p, rng.uniform2());
        if (!s.valid) {
            ++invalid;
            hist.addOutside();
            continue;
        }
        hist.add(s.wi);
        // weight = radiance / pdf.
        Vec3 lw = s.weight * s.pdf;
        if (length(lw - light.radiance) > 1e-4f * length(light.radiance)) ++weightMismatches;
        // The sampled point is on the light, and pdf() agrees with the sample's pdf there.
        std::optional<Hit> h = intersectLight(light, p, s.wi);
        if (!h || std::abs(length(h->q - p) - s.distance) > 1e-3f * s.distance) {
            ++offLight;
            continue;
        }
        float pdf = light.pdf(p, h->q, h->n);
        if (!(std::abs(pdf - s.pdf) <= 1e-3f * s.pdf)) ++pdfMismatches;
    }
    std::vector<double> expected = hist.expected(
        [&](const Vec3& w) -> double {
            std::optional<Hit> h = intersectLight(light, p, w);
            return h ? double(light.pdf(p, h->q, h->n)) : 0.0;
        },
        kSamples);
    ChiSquareResult r = chiSquareTest(hist.counts(), expected);
    INFO(label << ": chi2 " << r.chi2 << ", dof " << r.dof << " (" << r.bins << " bins, "
               << r.pooledBins << " pooled), p-value " << r.pValue << ", significance "
               << testSignificance() << "; failed samples " << invalid
               << ", weight*pdf != radiance " << weightMismatches << ", pdf mismatches "
               << pdfMismatches << ", samples off the light " << offLight);
    CHECK(r.pValue > testSignificance());
    CHECK(invalid == 0);
    CHECK(weightMismatches == 0);
    CHECK(pdfMismatches == 0);
    CHECK(offLight == 0);
}

// The cosine of the widest angle between `axis` and the direction from p to any of `points`,
// less a margin.
float coneOf(const Vec3& p, const Vec3& axis, const std::vector<Vec3>& points) {
    float c = 1;
    for (const Vec3& q : points) c = std::min(c, dot(normalize(q - p), axis));
    return std::max(-1.0f, c - 0.02f);
}

} // namespace

TEST_CASE("Chi-square: area light sampling follows LightSource::pdf", "[statistical]") {
    auto scene = sceneFromJson(kLightsScene);
    EmbreeScene accel(*scene);
    LightSet set = LightSet::build(*scene, accel);
    REQUIRE(set.lights.size() == 3);
    const Vec3 p(0.3f, 0.0f, 0.2f);

    SECTION("quad") {
        const LightSource& quad = lightOfKind(set, LightSource::Kind::AreaMesh);
        Vec3 axis = normalize(Vec3(0, 2, 0) - p);
        testLight(quad, p, axis, coneOf(p, axis, quad.triangles), 11, "quad");
    }
    SECTION("sphere from outside") {
        const LightSource& sphere = lightOfKind(set, LightSource::Kind::AreaSphere);
        Vec3 toC = sphere.center - p;
        float sinMax = sphere.radius / length(toC);
        float cosMax = std::sqrt(1 - sinMax * sinMax);
        // The bins end at the cone the sphere subtends, the support of the sampled density.
        testLight(sphere, p, normalize(toC), cosMax - 1e-3f, 12, "sphere from outside");
    }
    SECTION("sphere from inside") {
        // Uniform area sampling seen from an off-centre point inside: every direction. The
        // inside only emits if the sphere is two-sided (as the inside-out furnace's).
        LightSource sphere = lightOfKind(set, LightSource::Kind::AreaSphere);
        sphere.twoSided = true;
        Vec3 inside = sphere.center + Vec3(0.3f, 0.2f, -0.1f);
        testLight(sphere, inside, Vec3(0, 0, 1), -1.0f, 13, "sphere from inside");
    }
    SECTION("disk") {
        const LightSource& disk = lightOfKind(set, LightSource::Kind::AreaDisk);
        Vec3 axis = normalize(disk.center - p);
        std::vector<Vec3> rim;
        Vec3 t, b;
        orthonormalBasis(disk.normal, t, b);
        for (int i = 0; i < 64; ++i) {
            float a = 2 * kPi * float(i) / 64;
            rim.push_back(disk.center + (t * std::cos(a) + b * std::sin(a)) * disk.radius);
        }
        testLight(disk, p, axis, coneOf(p, axis, rim), 14, "disk");
    }
}
