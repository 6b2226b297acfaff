// Chi-square tests of kernels::sampleBsdf against kernels::evalBsdf's pdf, for every non-delta
// BSDF (diffuse; glossy at three roughnesses and three incident angles), the consistency of
// each sample's weight and pdf with evalBsdf, and for the delta BSDFs: the dielectric chooses
// reflection with the Fresnel probability (binomial, 3 sigma) and refracts by Snell's law; the
// mirror reflects. See docs/testing.md.
#include "statistical/bsdf_test_util.h"

#include "kernels/bsdf_sampling.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace rayproc;
using namespace rayproc::test;
using namespace rayproc::kernels;

// The chi-square run and its checks are shared with the pbrt-v4 kinds' tests
// (statistical/bsdf_test_util.h): kUp is the normal, direction() an incident direction.

TEST_CASE("Chi-square: diffuse sampling follows its cosine pdf", "[statistical]") {
    BsdfParams b;
    b.kind = BsdfKind::Diffuse;
    b.color = Vec3(0.8f, 0.5f, 0.2f);
    // Cosine-weighted about the normal on wo's side; the back side (wo below) mirrors it.
    for (float theta : {10.0f, 75.0f}) {
        ChiRun run = chiSquareRun(b, direction(theta), kUp, 0.0f, std::uint64_t(theta));
        checkChiRun(run, "diffuse, theta_o " + std::to_string(theta));
        CHECK(run.invalid == 0);
    }
    ChiRun back = chiSquareRun(b, direction(120.0f), -kUp, 0.0f, 120);
    checkChiRun(back, "diffuse, wo below the surface");
    CHECK(back.invalid == 0);
}

TEST_CASE("Chi-square: glossy (GGX) sampling follows its pdf", "[statistical]") {
    // Roughness 0.2 (the default; GGX alpha 0.04), 0.5 (0.25), 0.8 (0.64); incident angles 10,
    // 45 and 75 degrees. Bins are centred on the mirror direction, out to 4 atan(3 alpha) (90%
    // of the half vectors), so that narrow lobes spread over many bins; the rest, including
    // samples below the horizon (failed), is the outside bin.
    for (float roughness : {0.2f, 0.5f, 0.8f})
        for (float theta : {10.0f, 45.0f, 75.0f}) {
            BsdfParams b;
            b.kind = BsdfKind::Glossy;
            b.color = Vec3(0.9f, 0.6f, 0.3f);
            b.alpha = ggxAlpha(roughness);
            Vec3 wo = direction(theta);
            Vec3 mirror = reflect(wo, kUp);
            float angle = std::min(kPi, 4.0f * std::atan(3.0f * b.alpha));
            ChiRun run = chiSquareRun(b, wo, mirror, std::cos(angle),
                                  std::uint64_t(1000 * roughness + theta));
            checkChiRun(run, "glossy, roughness " + std::to_string(roughness) + ", theta_o " +
                              std::to_string(theta));
        }
}

TEST_CASE("Chi-square: the test rejects a wrong pdf", "[statistical]") {
    // Cosine-distributed samples against the uniform hemisphere pdf 1 / (2 pi).
    BsdfParams diffuse;
    diffuse.kind = BsdfKind::Diffuse;
    ChiRun uniform =
        chiSquareRun(diffuse, direction(10.0f), kUp, 0.0f, 1, [](const Vec3& w) {
            return w.z > 0 ? 1.0 / (2.0 * kPi) : 0.0;
        });
    INFO("cosine samples vs uniform pdf: chi2 " << uniform.chi.chi2 << ", dof " << uniform.chi.dof
                                                << ", p-value " << uniform.chi.pValue);
    CHECK(uniform.chi.pValue < 1e-12);

    // A subtler error: GGX samples of roughness 0.5 against the pdf of 5% more alpha.
    BsdfParams glossy;
    glossy.kind = BsdfKind::Glossy;
    glossy.alpha = ggxAlpha(0.5f);
    Vec3 wo = direction(45.0f);
    ChiRun wider = chiSquareRun(glossy, wo, reflect(wo, kUp), -1.0f, 2, [&](const Vec3& wi) {
        return double(glossyPdf(wo, wi, kUp, glossy.alpha * 1.05f));
    });
    INFO("GGX alpha 0.25 samples vs pdf of alpha 0.2625: chi2 " << wider.chi.chi2 << ", dof "
                                                                << wider.chi.dof << ", p-value "
                                                                << wider.chi.pValue);
    CHECK(wider.chi.pValue < testSignificance());
}

TEST_CASE("Dielectric: reflection is chosen with the Fresnel probability", "[statistical]") {
    BsdfParams b;
    b.kind = BsdfKind::Dielectric;
    b.ior = 1.5f;
    b.color = Vec3(0.9f, 0.8f, 0.7f);
    const int count = 100000;
    // Entering from outside (ng = +z, wo above) and leaving from inside (wo below): beyond the
    // critical angle asin(1/1.5) = 41.8 degrees every sample must reflect.
    for (float theta : {0.0f, 30.0f, 60.0f, 85.0f, 180.0f, 160.0f, 140.0f, 120.0f}) {
        Vec3 wo = direction(theta);
        bool entering = wo.z > 0;
        float cosI = std::abs(wo.z);
        float eta = entering ? b.ior : 1.0f / b.ior;
        float f = fresnelDielectric(cosI, eta);
        Vec3 side = entering ? kUp : -kUp;
        TestRng rng(42);
        int reflected = 0, wrongDirection = 0, wrongWeight = 0, invalid = 0, notDelta = 0;
        for (int i = 0; i < count; ++i) {
            BsdfSample s = sampleBsdf(b, wo, kUp, kUp, rng.uniform2(), rng.uniform());
            if (!s.valid) {
                ++invalid;
                continue;
            }
            if (!s.delta || s.pdf != 0) ++notDelta;
            if (!s.transmitted) {
                ++reflected;
                Vec3 r = reflect(wo, side);
                if (length(s.wi - r) > 1e-5f) ++wrongDirection;
                if (s.weight.x != 1 || s.weight.y != 1 || s.weight.z != 1) ++wrongWeight;
            } else {
                // Snell: n_i sin(theta_i) = n_t sin(theta_t), on the other side, in the plane of
                // incidence (the tangential components are antiparallel to wo's).
                float sinI = std::sqrt(std::max(0.0f, 1 - cosI * cosI));
                float sinT = std::sqrt(std::max(0.0f, 1 - s.wi.z * s.wi.z));
                Vec3 tangentO(wo.x, wo.y, 0), tangentT(s.wi.x, s.wi.y, 0);
                bool ok = dot(s.wi, side) < 0 && std::abs(sinI - eta * sinT) < 1e-5f &&
                          (sinI < 1e-6f || dot(tangentO, tangentT) < 0);
                if (!ok) ++wrongDirection;
                Vec3 expectW = entering ? b.color : Vec3(1.0f);
                if (length(s.weight - expectW) > 1e-6f) ++wrongWeight;
            }
        }
        double mean = count * double(f), sigma = std::sqrt(count * double(f) * (1.0 - f));
        INFO("theta_o " << theta << " (" << (entering ? "entering" : "leaving") << "), F " << f
                        << ": reflected " << reflected << " of " << count << ", expected " << mean
                        << " +- " << sigma << " (" << (reflected - mean) / std::max(sigma, 1e-9)
                        << " sigma)");
        CHECK(invalid == 0);
        CHECK(notDelta == 0);
        CHECK(wrongDirection == 0);
        CHECK(wrongWeight == 0);
        CHECK(std::abs(reflected - mean) <= 3.0 * sigma + 1e-9);
        // evalBsdf has no density for a delta BSDF.
        float pdf = 1;
        Vec3 fv = evalBsdf(b, wo, reflect(wo, side), kUp, kUp, pdf);
        CHECK(pdf == 0);
        CHECK(isBlack(fv));
    }
}

TEST_CASE("Mirror: perfect reflection with the mirror's colour", "[statistical]") {
    BsdfParams b;
    b.kind = BsdfKind::Mirror;
    b.color = Vec3(0.9f, 0.5f, 0.25f);
    TestRng rng(7);
    for (float theta : {0.0f, 40.0f, 89.0f, 130.0f}) {
        Vec3 wo = direction(theta);
        BsdfSample s = sampleBsdf(b, wo, kUp, kUp, rng.uniform2(), rng.uniform());
        INFO("theta_o " << theta);
        REQUIRE(s.valid);
        CHECK(s.delta);
        CHECK(length(s.wi - reflect(wo, wo.z > 0 ? kUp : -kUp)) < 1e-6f);
        CHECK(length(s.weight - b.color) == 0);
    }
}
