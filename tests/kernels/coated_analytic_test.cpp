// The closed-form coated diffuse (kernels/coated_analytic.h) measured against pbrt-v4's random
// walk (kernels/layered.h) run deep enough to converge (maxDepth 100): the directional albedos
// agree; with a white base and no absorption the smooth coat is exactly lossless; its sampling
// follows its pdf (chi-square), and a sample's weight and pdf are evalBsdf's. And the walk on a
// smooth clear coat against the layered closed form computed from Hecht's Fresnel equations in
// the test (a truth outside rayproc's code; issue 38 item 3).
#include "hecht_fresnel.h"
#include "statistical/bsdf_test_util.h"

using namespace rayproc;
using namespace rayproc::test;
using namespace rayproc::kernels;

namespace {

BsdfParams coated(float alpha, const Vec3& base, float thickness, bool walk) {
    BsdfParams b;
    b.kind = BsdfKind::CoatedDiffuse;
    b.color = base;
    b.ior = 1.5f;
    b.alphaX = b.alphaY = alpha;
    b.thickness = thickness;
    b.maxDepth = 100;
    b.coatWalk = walk;
    b.key = 99;
    return b;
}

} // namespace

TEST_CASE("Analytic coat: a smooth coat over a white base without absorption is lossless",
          "[bsdf][furnace]") {
    for (float theta : {0.0f, 45.0f, 80.0f}) {
        Albedo a = directionalAlbedo(coated(0.0f, Vec3(1.0f), 1e-7f, false), direction(theta),
                                     200000, 7);
        INFO("theta_o " << theta << ": albedo " << a.mean.x << " +- " << a.stdError.x);
        CHECK(std::abs(a.mean.x - 1.0f) < 0.005f + 4 * a.stdError.x);
    }
}

TEST_CASE("Analytic coat against pbrt-v4's random walk at depth 100", "[bsdf][furnace]") {
    // Smooth coats: the closed form is the walk's limit, so the albedos agree closely. Rough
    // coats keep the smooth coat's transmission factors and so miss the energy a rough interface
    // loses at each crossing (single-scattering microfacets): measured at 45 degrees, the
    // closed form is 5% above the walk at alpha 0.1 and 26% above it at alpha 0.3 (red channel);
    // the bounds below are those figures plus a margin, so a change in either model shows.
    struct Case {
        float alpha, theta, thickness, tolerance;
    };
    const Case cases[] = {{0.0f, 0.0f, 0.01f, 0.01f},  {0.0f, 60.0f, 0.01f, 0.01f},
                          {0.0f, 30.0f, 0.2f, 0.02f},  {0.05f, 30.0f, 0.01f, 0.02f},
                          {0.1f, 45.0f, 0.01f, 0.06f}, {0.3f, 45.0f, 0.01f, 0.28f}};
    for (const Case& c : cases)
        for (Vec3 base : {Vec3(0.8f, 0.5f, 0.1f)}) {
            Vec3 wo = direction(c.theta);
            Albedo analytic = directionalAlbedo(coated(c.alpha, base, c.thickness, false), wo,
                                                200000, 11);
            Albedo walk = directionalAlbedo(coated(c.alpha, base, c.thickness, true), wo,
                                            200000, 13);
            for (int ch = 0; ch < 3; ++ch) {
                INFO("alpha " << c.alpha << ", theta_o " << c.theta << ", thickness "
                              << c.thickness << ", channel " << ch << ": analytic "
                              << analytic.mean[ch] << ", walk " << walk.mean[ch] << " +- "
                              << walk.stdError[ch]);
                CHECK(std::abs(analytic.mean[ch] - walk.mean[ch]) <=
                      c.tolerance * walk.mean[ch] + 4 * (walk.stdError[ch] + analytic.stdError[ch]));
            }
        }
}

TEST_CASE("Chi-square: the analytic rough coat's sampling follows its pdf", "[bsdf][statistical]") {
    for (float alpha : {0.05f, 0.3f})
        for (float theta : {20.0f, 70.0f}) {
            BsdfParams b = coated(alpha, Vec3(0.6f, 0.4f, 0.2f), 0.01f, false);
            Vec3 wo = direction(theta);
            ChiRun run = chiSquareRun(b, wo, kUp, 0.0f, std::uint64_t(7 + theta + 100 * alpha));
            checkChiRun(run, "analytic coat alpha " + std::to_string(alpha) + ", theta_o " +
                                 std::to_string(theta));
        }
}

TEST_CASE("Analytic coat: the diffuse lobe's albedo gi uses is the integral of f_d cos",
          "[bsdf][gi]") {
    // A fine midpoint rule over the hemisphere (theta and phi) of CoatedAnalytic::diffuse
    // against diffuseAlbedo's 16 strata in sin^2 theta, for absorbing and clear coats.
    for (float thickness : {0.0f, 0.01f, 0.3f}) {
        for (float cosO : {1.0f, 0.7f, 0.2f}) {
            CoatedAnalytic c = coatedAnalyticOf(coated(0.0f, Vec3(0.8f, 0.5f, 0.2f), thickness, false));
            Vec3 wo(std::sqrt(1 - cosO * cosO), 0, cosO);
            constexpr int kTheta = 400, kPhi = 8; // f_d does not depend on phi
            Vec3 sum(0.0f);
            for (int i = 0; i < kTheta; ++i) {
                float theta = (float(i) + 0.5f) / kTheta * (kPi / 2);
                for (int j = 0; j < kPhi; ++j) {
                    float phi = (float(j) + 0.5f) / kPhi * 2 * kPi;
                    Vec3 wi(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                            std::cos(theta));
                    sum += c.diffuse(wo, wi) *
                           (wi.z * std::sin(theta) * (kPi / 2 / kTheta) * (2 * kPi / kPhi));
                }
            }
            Vec3 albedo = c.diffuseAlbedo(cosO);
            INFO("thickness " << thickness << " cos_o " << cosO << ": " << albedo.x
                              << " quadrature " << sum.x);
            for (int k = 0; k < 3; ++k) CHECK(albedo[k] == Approx(sum[k]).epsilon(5e-3));
            // Below the base's reflectance: the coat loses light on the way in and out.
            CHECK(albedo.x < 0.8f);
        }
    }
}

TEST_CASE("pbrt-v4's walk through a smooth clear coat returns the layered closed form",
          "[bsdf][furnace]") {
    // A smooth dielectric interface (n = 1.5) over a Lambertian base of reflectance R, without
    // absorption: light reflects F(theta_o) at the coat; the rest reaches the base, whose
    // diffuse light leaves through the coat with probability 1 - F_int per arrival and is
    // reflected back to the base otherwise, so the directional albedo is
    //   A = F(theta_o) + (1 - F(theta_o)) R (1 - F_int) / (1 - R F_int),
    // F_int the cosine-weighted mean of the internal reflectance (Weidlich & Wilkie 2007 and
    // the textbook plastic; here F and F_int come from Hecht's Fresnel equations, F_int
    // integrated by the test: 0.5963 for n = 1.5, where Egan & Hilgeman's fit, which the
    // closed-form BSDF of kernels/coated_analytic.h uses, gives 0.5968). The walk (maxDepth 100)
    // is rayproc's port of pbrt-v4's; this holds it, and so the coated model on smooth coats,
    // to 1% of a truth computed outside rayproc's code. Rough coats have no such truth here
    // (docs/testing.md, issue 38 item 3).
    const double n = 1.5;
    double fInt = 0;
    constexpr int kSteps = 100000;
    for (int i = 0; i < kSteps; ++i) {
        double theta = (i + 0.5) / kSteps * (kPi / 2);
        fInt += test::fresnelHecht(theta, n, 1.0) * 2 * std::sin(theta) * std::cos(theta) *
                (kPi / 2) / kSteps;
    }
    CHECK(fInt == Approx(0.5963).margin(2e-4));
    const Vec3 base(0.8f, 0.5f, 0.1f);
    for (float theta : {0.0f, 45.0f, 75.0f}) {
        const double f = test::fresnelHecht(double(theta) * kPi / 180, 1.0, n);
        Albedo walk = directionalAlbedo(coated(0.0f, base, 1e-7f, true), direction(theta),
                                        200000, 17);
        for (int ch = 0; ch < 3; ++ch) {
            const double r = base[ch];
            const double expected = f + (1 - f) * r * (1 - fInt) / (1 - r * fInt);
            INFO("theta_o " << theta << ", channel " << ch << ": walk " << walk.mean[ch] << " +- "
                            << walk.stdError[ch] << ", closed form " << expected);
            CHECK(std::abs(walk.mean[ch] - expected) <= 0.01 * expected + 4 * walk.stdError[ch]);
        }
    }
}

// evalCos computes what its lobes share once (docs/performance.md, "Path mode's cost per
// vertex"): it must stay the sum of diffuse() and specular() and the mixture of their pdfs, to
// the bit, so that images do not change.
TEST_CASE("Analytic coat: evalCos is its lobes' sum to the bit", "[bsdf]") {
    TestRng rng(11);
    for (float alpha : {0.0f, 0.05f, 0.3f, 0.8f}) {
        CoatedAnalytic c;
        c.eta = 1.45f;
        c.mf.alphaX = alpha;
        c.mf.alphaY = alpha * 0.7f;
        c.base = {0.7f, 0.4f, 0.2f};
        c.thickness = 0.05f;
        for (int k = 0; k < 2000; ++k) {
            Vec3 wo = cosineHemisphere(rng.uniform2());
            Vec3 wi = cosineHemisphere(rng.uniform2());
            if (wo.z <= 0 || wi.z <= 0) continue;
            float ps = c.specularProbability(wo);
            Vec3 f = c.diffuse(wo, wi);
            float pdf = (1 - ps) * wi.z * kInvPi;
            if (!c.smooth()) {
                f += Vec3(c.specular(wo, wi));
                pdf += ps * c.specularPdf(wo, wi);
            }
            f = f * wi.z;
            float got;
            Vec3 fc = c.evalCos(wo, wi, got);
            INFO("alpha " << alpha << " sample " << k);
            REQUIRE(fc.x == f.x);
            REQUIRE(fc.y == f.y);
            REQUIRE(fc.z == f.z);
            REQUIRE(got == pdf);
        }
    }
}
