// Energy conservation of the photon pass: a light inside a closed diffuse sphere of albedo a.
// Every emitted photon reaches the wall, so the power stored at the first bounce is the light's
// power Phi exactly, and each further bounce stores a times the previous one in expectation
// (Russian roulette keeps the estimate unbiased). With at most D stores per path
// (maxPhotonDepth) the expected total stored power is
//   Phi (1 + a + ... + a^(D-1)) = Phi (1 - a^D) / (1 - a)   per channel.
// The photons are traced through the real pipeline (PhotonEmitter -> Pipeline ->
// PhotonStage) and their powers summed as the stage hands them over (floats). The map's RGBE
// encoding is checked separately: here every photon of a bounce has the same power (uniform
// albedo), so its rounding does not cancel but repeats; the decoded sums are checked within
// RGBE's half step of the largest channel, 1/256.
#include "engine/intersect.h"
#include "engine/pipeline.h"
#include "gi/photon_emitter.h"
#include "gi/gi_pipeline.h"
#include "gi/photon_map.h"
#include "gi/photon_stage.h"

#include "../analytic/analytic.h"

#include <cmath>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// Traces `count` global-map photons and returns what the photon stage stored.
PhotonList tracePhotons(const Scene& scene, const EmbreeScene& accel, std::uint32_t count,
                       int maxPhotonDepth, std::uint64_t seed) {
    LightSet lights = LightSet::build(scene, accel);
    Film film(1, 1);
    ShadingPolicy policy;
    RenderContext rc{scene, accel, lights, policy, film, seed};
    Stats stats;
    PhotonStage stage(rc, /*causticPass=*/false, maxPhotonDepth);
    Pipeline pipeline("photons", "photon", accel.root(), 16, stats, 2);
    pipeline.stage("photon", {kPhotonQueue}, stage);
    PhotonEmitter emitter(lights, scene.worldBounds(), count, seed, 1);
    pipeline.run(emitter, [] { return false; });
    return stage.takePhotons();
}

Vec3 storedPower(const PhotonList& photons) {
    double s[3] = {0, 0, 0};
    for (const PhotonRecord& p : photons)
        for (int c = 0; c < 3; ++c) s[c] += p.power[c];
    return Vec3(float(s[0]), float(s[1]), float(s[2]));
}

// The same sum as the built map decodes it (RGBE).
Vec3 decodedPower(const PhotonList& photons) {
    PhotonMap map;
    map.build(photons);
    double s[3] = {0, 0, 0};
    for (std::uint32_t i = 0; i < map.size(); ++i) {
        Vec3 p = map.photon(i).power;
        for (int c = 0; c < 3; ++c) s[c] += p[c];
    }
    return Vec3(float(s[0]), float(s[1]), float(s[2]));
}

// A closed sphere of radius 2 with albedo `albedo`, lit by `light` (JSON) and optionally
// emitting itself.
std::string closedSphere(const Vec3& albedo, const std::string& lights, const std::string& emission) {
    return R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov": 70, "resolution": [8, 8]},
               "materials": {"wall": {"type": "diffuse", "color": )" +
           jsonVec(albedo) + R"(}},
               "lights": )" + lights + R"(,
               "nodes": [{"type": "sphere", "material": "wall", "radius": 2)" + emission + "}]}";
}

} // namespace

TEST_CASE("Photon pass: a point light in a closed sphere stores Phi at the first bounce and "
          "Phi (1 - a^D) / (1 - a) in all",
          "[gi]") {
    const Vec3 albedo(0.5f, 0.8f, 0.2f);
    const Vec3 intensity(1.0f, 2.0f, 3.0f);
    const Vec3 phi = intensity * (4 * kPi);
    auto scene = sceneFromJson(closedSphere(
        albedo, R"([{"type": "point", "position": [0.3, -0.2, 0.1], "intensity": )" + jsonVec(intensity) + "}]", ""));
    EmbreeScene accel(*scene);
    const std::uint32_t n = 200000;

    SECTION("first bounce only: exactly Phi") {
        PhotonList photons = tracePhotons(*scene, accel, n, 1, 7);
        CHECK(photons.size() == n); // every photon hits the wall once and stops
        Vec3 stored = storedPower(photons), decoded = decodedPower(photons);
        for (int c = 0; c < 3; ++c) {
            INFO("channel " << c << ": stored " << stored[c] << ", decoded " << decoded[c]
                            << ", Phi " << phi[c]);
            // Each photon carries Phi / n (float sums of 200,000 equal terms: 1e-4).
            CHECK(std::abs(stored[c] / phi[c] - 1.0f) < 1e-4f);
            CHECK(std::abs(decoded[c] / phi[c] - 1.0f) < 1.0f / 256.0f);
        }
    }

    SECTION("all bounces: the geometric series, within 4 sigma of the random walk") {
        const int depth = 16;
        PhotonList photons = tracePhotons(*scene, accel, n, depth, 7);
        Vec3 stored = storedPower(photons), decoded = decodedPower(photons);
        // Per path and channel the stored sum is (Phi / n) sum_{k=0}^{L} (a / q)^k, where
        // q = max(a) is the roulette's survival probability and P(L >= k) = q^k for k < D:
        // its mean is (Phi / n) sum_k a^k and its variance follows from the distribution of L.
        const float q = maxComponent(albedo);
        for (int c = 0; c < 3; ++c) {
            const double r = albedo[c] / q;
            double mean = 0, second = 0, partial = 0;
            for (int L = 0; L < depth; ++L) {
                partial += std::pow(r, L);               // stores 0..L
                double pL = std::pow(double(q), L) * (L + 1 < depth ? 1.0 - q : 1.0); // exactly L+1 stores
                mean += pL * partial;
                second += pL * partial * partial;
            }
            const double perPhoton = phi[c] / double(n);
            const double expected = phi[c] * (1.0 - std::pow(double(albedo[c]), depth)) / (1.0 - albedo[c]);
            const double sigma = perPhoton * std::sqrt(double(n) * (second - mean * mean));
            INFO("channel " << c << ": stored " << stored[c] << ", expected " << expected
                            << " (closed form; the walk's mean " << mean * perPhoton * n
                            << "), sigma " << sigma << " (" << sigma / expected
                            << " relative), off by " << (stored[c] - expected) / sigma << " sigma");
            INFO("decoded (RGBE) " << decoded[c] << ", " << decoded[c] / expected - 1.0 << " off");
            REQUIRE(std::abs(mean * perPhoton * n / expected - 1.0) < 1e-6); // the series, twice
            CHECK(std::abs(stored[c] - expected) < 4.0 * sigma + 1e-4 * expected);
            CHECK(std::abs(decoded[c] / expected - 1.0) < 1.0 / 256.0 + 4.0 * sigma / expected);
            CHECK(sigma < 0.005 * expected); // tight enough that a 2% energy error fails
        }
    }
}

TEST_CASE("Photon pass: an emitting sphere's inward photons start off the surface and all land "
          "on it",
          "[gi]") {
    // The sphere emits Le on both sides: Phi = 2 pi A Le, half of it inwards. With one store
    // per photon, the inward half is stored exactly once each and the outward half escapes.
    // A photon leaving from the surface point itself could hit its own sphere at t ~ 0: stored
    // at its origin (inward) or wrongly kept (outward). The emitter offsets its origin.
    const Vec3 albedo(0.5f, 0.8f, 0.2f);
    const Vec3 le(1.0f, 1.0f, 2.0f);
    auto scene = sceneFromJson(closedSphere(albedo, "[]",
                                            R"(, "emission": )" + jsonVec(le) + R"(, "two_sided": true)"));
    EmbreeScene accel(*scene);
    const float area = 4 * kPi * 2.0f * 2.0f;
    const Vec3 inward = le * (kPi * area);
    const std::uint32_t n = 100000;
    PhotonList photons = tracePhotons(*scene, accel, n, 1, 3);
    Vec3 stored = storedPower(photons);
    INFO("stored " << stored.x << ", " << stored.y << ", " << stored.z << " of " << photons.size()
                   << " photons; inward flux " << inward.x << ", " << inward.y << ", " << inward.z);
    // Each photon carries 2 Phi_in / n; the stratified side choice sends exactly half inwards.
    for (int c = 0; c < 3; ++c) CHECK(std::abs(stored[c] / inward[c] - 1.0f) < 1e-3f);
    // Every photon reached the wall from the inside: its stored normal (the side it arrived
    // on) faces the centre. One hitting its own sphere at t ~ 0 after leaving inwards would
    // arrive on the outside.
    std::size_t outside = 0;
    for (const PhotonRecord& p : photons)
        if (dot(p.normal, p.position) > 0) ++outside;
    CHECK(outside == 0);
}
