// pbrt-v4's coated conductor (kernels/layered.h over a Trowbridge-Reitz conductor): its energy
// (albedo <= 1; a smooth coat over a perfect mirror against the closed form of a smooth slab),
// the limit of an index-matched coat (the bare conductor), and reciprocity of the walk's f
// within its noise. The sample weights against f: tests/statistical/coated_conductor_bsdf_test.
#include "statistical/bsdf_test_util.h"

using namespace rayproc;
using namespace rayproc::test;
using namespace rayproc::kernels;

namespace {

constexpr int kAlbedoSamples = 200000;

BsdfParams coatedConductor(float coatAlpha, float baseAlpha, float thickness, Vec3 albedo) {
    BsdfParams b;
    b.kind = BsdfKind::CoatedConductor;
    b.ior = 1.5f;
    b.alphaX = b.alphaY = coatAlpha;
    b.baseAlphaX = b.baseAlphaY = baseAlpha;
    b.eta = Vec3(0.2f, 0.45f, 1.2f); // gold-like
    b.k = Vec3(3.6f, 2.4f, 1.8f);
    b.thickness = thickness;
    b.albedo = albedo;
    b.tangent = Vec3(1.0f, 0.0f, 0.0f);
    return b;
}

std::string label(const BsdfParams& b, float theta) {
    return "coat alpha " + std::to_string(b.alphaX) + ", conductor alpha " +
           std::to_string(b.baseAlphaX) + ", thickness " + std::to_string(b.thickness) +
           ", albedo " + std::to_string(b.albedo.x) + ", theta_o " + std::to_string(theta);
}

} // namespace

TEST_CASE("Coated conductor: directional albedo at most 1", "[bsdf][furnace][coated-conductor]") {
    // Smooth and rough coats over smooth and rough conductors, with and without a scattering
    // slab; a perfect mirror base (k = 1000) is the worst case for energy.
    struct Case {
        float coatAlpha, baseAlpha, thickness, albedo, k;
    };
    const Case cases[] = {{0.0f, 0.3f, 0.01f, 0.0f, 0.0f},
                          {0.3f, 0.0f, 0.01f, 0.0f, 0.0f},
                          {0.2f, 0.2f, 0.1f, 0.8f, 0.0f},
                          {0.3f, 0.4f, 1e-4f, 0.0f, 1000.0f},
                          {0.0f, 0.5f, 1e-4f, 0.0f, 1000.0f}};
    for (const Case& c : cases)
        for (float theta : {0.0f, 45.0f, 80.0f}) {
            BsdfParams b = coatedConductor(c.coatAlpha, c.baseAlpha, c.thickness, Vec3(c.albedo));
            if (c.k > 0) {
                b.eta = Vec3(1.0f);
                b.k = Vec3(c.k);
                b.maxDepth = 100;
            }
            Albedo a = directionalAlbedo(b, direction(theta), kAlbedoSamples, 53);
            for (int ch = 0; ch < 3; ++ch) {
                INFO(label(b, theta) << ", channel " << ch << ": albedo " << a.mean[ch] << " +- "
                                     << a.stdError[ch]);
                CHECK(a.mean[ch] <= 1.0f + 4.0f * a.stdError[ch] + 1e-4f);
                CHECK(a.mean[ch] > 0.05f); // the walk reaches the base and comes back
            }
        }
}

TEST_CASE("Coated conductor: a smooth coat over a perfect mirror, the slab's closed form",
          "[bsdf][furnace][coated-conductor]") {
    // A smooth coat of Fresnel reflectance R(theta_o) over a lossless mirror, with an absorbing
    // slab of optical thickness t: each round trip inside keeps a = exp(-2 t / cos theta_t) and
    // meets the coat from inside at theta_t, where it reflects R again (Fresnel is symmetric
    // under refraction), so the albedo is R + (1 - R)^2 a / (1 - R a) (-> 1 as t -> 0).
    for (float t : {1e-4f, 0.1f, 0.5f})
        for (float theta : {0.0f, 50.0f, 80.0f}) {
            BsdfParams b = coatedConductor(0.0f, 0.0f, t, Vec3(0.0f));
            b.eta = Vec3(1.0f);
            b.k = Vec3(1000.0f);
            b.maxDepth = 200;
            Vec3 wo = direction(theta);
            Albedo a = directionalAlbedo(b, wo, kAlbedoSamples, 59);
            double r = fresnelDielectric(wo.z, b.ior);
            double sinT = std::sqrt(1.0 - double(wo.z) * wo.z) / b.ior;
            double cosT = std::sqrt(1.0 - sinT * sinT);
            double att = std::exp(-2.0 * t / cosT);
            double expected = r + (1 - r) * (1 - r) * att / (1 - r * att);
            INFO("thickness " << t << ", theta_o " << theta << ": albedo " << a.mean.x << " +- "
                              << a.stdError.x << ", closed form " << expected);
            CHECK(std::abs(a.mean.x - expected) <= 4.0f * a.stdError.x + 2e-3);
            if (t < 1e-3f) CHECK(a.mean.x > 0.995f);
        }
}

TEST_CASE("Coated conductor: an index-matched coat is the bare conductor", "[coated-conductor]") {
    // Coat index 1 over a vanishing slab: the walk passes the coat untouched both ways, so f
    // is the rough conductor's (times exp(-2 t / cos) ~ 1), here without noise.
    BsdfParams coated = coatedConductor(0.25f, 0.3f, 1e-5f, Vec3(0.0f));
    coated.ior = 1.0f;
    BsdfParams bare = coated;
    bare.kind = BsdfKind::Conductor;
    bare.alphaX = bare.alphaY = 0.3f;
    int compared = 0;
    for (float to : {10.0f, 40.0f, 75.0f})
        for (float ti : {5.0f, 35.0f, 60.0f, 85.0f}) {
            Vec3 wo = direction(to, 20.0f), wi = direction(ti, 170.0f);
            float pc, pb;
            coated.key = std::uint64_t(to * 100 + ti);
            Vec3 fc = evalBsdf(coated, wo, wi, kUp, kUp, pc);
            Vec3 fb = evalBsdf(bare, wo, wi, kUp, kUp, pb);
            for (int c = 0; c < 3; ++c) {
                INFO("theta_o " << to << ", theta_i " << ti << ", channel " << c << ": coated "
                                << fc[c] << ", bare " << fb[c]);
                CHECK(fc[c] == Approx(fb[c]).epsilon(1e-3).margin(1e-7));
            }
            ++compared;
        }
    CHECK(compared == 12);
    // And the sampled albedo, through sampleBsdf's walk, matches the bare conductor's.
    for (float theta : {0.0f, 60.0f}) {
        Albedo ac = directionalAlbedo(coated, direction(theta), kAlbedoSamples, 61);
        Albedo ab = directionalAlbedo(bare, direction(theta), kAlbedoSamples, 67);
        for (int c = 0; c < 3; ++c) {
            double se = std::sqrt(double(ac.stdError[c]) * ac.stdError[c] +
                                  double(ab.stdError[c]) * ab.stdError[c]);
            INFO("theta_o " << theta << ", channel " << c << ": coated " << ac.mean[c]
                            << ", bare " << ab.mean[c] << " +- " << se);
            CHECK(std::abs(ac.mean[c] - ab.mean[c]) <= 4.0 * se + 1e-3);
        }
    }
}

TEST_CASE("Coated conductor: f is reciprocal within the walk's noise", "[coated-conductor]") {
    // f(wo, wi) |cos i| / |cos i| against f(wi, wo): the mean of 4000 keyed estimates each, a
    // rough coat over a rough conductor with a scattering slab (every strategy of the walk).
    BsdfParams b = coatedConductor(0.3f, 0.2f, 0.1f, Vec3(0.6f, 0.4f, 0.2f));
    b.g = 0.3f;
    const int n = 4000;
    struct Pair {
        float to, po, ti, pi;
    };
    for (Pair pr : {Pair{20, 10, 55, 200}, Pair{70, 0, 30, 90}, Pair{45, 45, 80, 300}}) {
        Vec3 a = direction(pr.to, pr.po), c = direction(pr.ti, pr.pi);
        double s1 = 0, s1q = 0, s2 = 0, s2q = 0;
        for (int k = 0; k < n; ++k) {
            float p;
            b.key = std::uint64_t(k);
            double f1 = evalBsdf(b, a, c, kUp, kUp, p).x / c.z;
            b.key = std::uint64_t(k) + 1000003;
            double f2 = evalBsdf(b, c, a, kUp, kUp, p).x / a.z;
            s1 += f1;
            s1q += f1 * f1;
            s2 += f2;
            s2q += f2 * f2;
        }
        double m1 = s1 / n, m2 = s2 / n;
        double se = std::sqrt((s1q / n - m1 * m1) / n + (s2q / n - m2 * m2) / n);
        INFO("theta " << pr.to << " / " << pr.ti << ": f(wo, wi) " << m1 << ", f(wi, wo) " << m2
                      << ", standard error " << se);
        CHECK(m1 > 0);
        CHECK(std::abs(m1 - m2) <= 4.0 * se);
        CHECK(se < 0.05 * m1); // the check is sharp enough to see a 20% asymmetry
    }
}
