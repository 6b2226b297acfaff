// Chi-square tests of sampleBsdf against evalBsdf's pdf for the deterministic pbrt-v4 kinds:
// the rough conductor (isotropic at three alphas and three angles, anisotropic with two
// tangents, wo on the back side), the rough dielectric (reflection and transmission histograms,
// from outside and inside, beyond the critical angle, isotropic and anisotropic) and diffuse
// transmission; each sample's pdf and weight must equal evalBsdf's. A sanity case shows that
// the test rejects the conductor's pdf with the two alphas swapped. See statistical.h for the
// significance (Sidak over every chi-square test of the suite).
#include "bsdf_test_util.h"

#include <vector>

using namespace rayproc;
using namespace rayproc::test;
using namespace rayproc::kernels;

namespace {

BsdfParams conductor(float ax, float ay, Vec3 tangent = Vec3(0.0f)) {
    BsdfParams b;
    b.kind = BsdfKind::Conductor;
    b.eta = Vec3(0.2f, 0.92f, 1.1f); // copper-like
    b.k = Vec3(3.9f, 2.45f, 2.2f);
    b.alphaX = ax;
    b.alphaY = ay;
    b.tangent = tangent;
    return b;
}

BsdfParams roughDielectric(float ax, float ay) {
    BsdfParams b;
    b.kind = BsdfKind::Dielectric;
    b.ior = 1.5f;
    b.color = Vec3(0.9f, 0.8f, 0.7f);
    b.alphaX = ax;
    b.alphaY = ay;
    b.tangent = Vec3(1.0f, 1.0f, 0.0f);
    return b;
}

std::string angles(float a, float b) { return std::to_string(a) + ", " + std::to_string(b); }

} // namespace

TEST_CASE("Chi-square: rough conductor sampling follows its pdf", "[bsdf][statistical][heavy]") {
    // Isotropic: 9 tests, bins centred on the mirror direction as the glossy test.
    for (float alpha : {0.05f, 0.3f, 0.8f})
        for (float theta : {10.0f, 45.0f, 75.0f}) {
            BsdfParams b = conductor(alpha, alpha);
            Vec3 wo = direction(theta);
            ChiRun run = chiSquareRun(b, wo, reflect(wo, kUp), lobeCosMin(alpha),
                                      std::uint64_t(100 * alpha + theta));
            checkChiRun(run, "conductor alpha " + std::to_string(alpha) + ", theta_o " +
                                 std::to_string(theta));
        }
    // Anisotropic (4 tests): the tangent along x, and a tangent not perpendicular to the normal
    // (Gram-Schmidt must make it so) at 45 degrees in the plane.
    for (float theta : {30.0f, 70.0f}) {
        BsdfParams a = conductor(0.1f, 0.4f);
        BsdfParams c = conductor(0.5f, 0.08f, Vec3(1.0f, 1.0f, 0.7f));
        Vec3 wo = direction(theta, 70.0f);
        ChiRun ra = chiSquareRun(a, wo, reflect(wo, kUp), lobeCosMin(0.4f), 11 + int(theta));
        checkChiRun(ra, "conductor alphas 0.1, 0.4, theta_o " + std::to_string(theta));
        ChiRun rc = chiSquareRun(c, wo, reflect(wo, kUp), lobeCosMin(0.5f), 12 + int(theta));
        checkChiRun(rc, "conductor alphas 0.5, 0.08, oblique tangent, theta_o " +
                            std::to_string(theta));
    }
    // wo below the geometric normal: the back side mirrors the front (1 test).
    BsdfParams b = conductor(0.3f, 0.3f);
    Vec3 wo = direction(120.0f);
    ChiRun back = chiSquareRun(b, wo, reflect(wo, -kUp), lobeCosMin(0.3f), 120);
    checkChiRun(back, "conductor, wo below");
}

TEST_CASE("Chi-square: the test rejects the anisotropic conductor with swapped alphas",
          "[bsdf][statistical]") {
    BsdfParams b = conductor(0.1f, 0.4f), swapped = conductor(0.4f, 0.1f);
    Vec3 wo = direction(30.0f, 70.0f);
    ChiRun run = chiSquareRun(b, wo, reflect(wo, kUp), lobeCosMin(0.4f), 5, [&](const Vec3& wi) {
        float p;
        evalBsdf(swapped, wo, wi, kUp, kUp, p);
        return double(p);
    });
    INFO("samples of alphas (0.1, 0.4) vs pdf of (0.4, 0.1): chi2 " << run.chi.chi2 << ", p "
                                                                   << run.chi.pValue);
    CHECK(run.chi.pValue < 1e-12);
}

TEST_CASE("Chi-square: rough dielectric sampling follows its pdf", "[bsdf][statistical][heavy]") {
    // Each configuration is tested with two histograms, one around the mirror direction and one
    // around the macroscopic refraction (the other lobe falls in the outside bin), or with one
    // over the whole sphere for wide lobes and total internal reflection. wo at 20 and 70 degrees
    // from outside, 20 and 50 (past the critical 41.8) from inside. 14 tests.
    struct Case {
        float ax, ay, theta;
    };
    const Case cases[] = {{0.1f, 0.1f, 20.0f},  {0.1f, 0.1f, 70.0f}, {0.1f, 0.1f, 160.0f},
                          {0.1f, 0.1f, 130.0f}, {0.4f, 0.4f, 45.0f}, {0.4f, 0.4f, 150.0f},
                          {0.1f, 0.3f, 45.0f},  {0.1f, 0.3f, 150.0f}};
    for (const Case& c : cases) {
        BsdfParams b = roughDielectric(c.ax, c.ay);
        Vec3 wo = direction(c.theta);
        bool entering = wo.z > 0;
        Vec3 n = entering ? kUp : -kUp;
        float eta = entering ? b.ior : 1.0f / b.ior;
        float alpha = std::max(c.ax, c.ay);
        std::string label = "rough dielectric alphas " + angles(c.ax, c.ay) + ", theta_o " +
                            std::to_string(c.theta);
        Vec3 wt;
        bool refracts = refract(wo, n, eta, wt);
        std::uint64_t seed = std::uint64_t(1000 * c.ax + 100 * c.ay + c.theta);
        if (alpha >= 0.4f || !refracts) {
            ChiRun run = chiSquareRun(b, wo, n, -1.0f, seed);
            checkChiRun(run, label + ", whole sphere");
            CHECK(run.invalid < kSamples / 5); // below the horizon or TIR
            continue;
        }
        ChiRun refl = chiSquareRun(b, wo, reflect(wo, n), lobeCosMin(alpha), seed);
        checkChiRun(refl, label + ", around the mirror direction");
        // Refraction deviates the direction by only ~|1 - 1/eta| of the microfacet's tilt
        // (reflection: twice it), so the transmitted lobe is several times narrower: a cap of
        // 0.4 of the reflection's keeps its peak resolved by the histogram and the integrator.
        float cap = 0.4f * std::acos(lobeCosMin(alpha));
        ChiRun trans = chiSquareRun(b, wo, wt, std::cos(cap), seed + 7);
        checkChiRun(trans, label + ", around the refracted direction");
    }
}

TEST_CASE("Chi-square: diffuse transmission sampling follows its pdf", "[bsdf][statistical]") {
    BsdfParams b;
    b.kind = BsdfKind::DiffuseTransmission;
    b.color = Vec3(0.2f, 0.5f, 0.3f);
    b.transmittance = Vec3(0.7f, 0.4f, 0.6f);
    // 3 tests; the whole sphere, the reflected half on wo's side.
    for (float theta : {10.0f, 75.0f, 120.0f}) {
        ChiRun run = chiSquareRun(b, direction(theta), kUp, -1.0f, std::uint64_t(theta) + 3);
        checkChiRun(run, "diffuse transmission, theta_o " + std::to_string(theta));
        CHECK(run.invalid == 0);
    }
}

TEST_CASE("Transmissive kinds evaluate both sides, opaque kinds only wo's",
          "[bsdf]") {
    Vec3 wo = direction(30.0f), below = direction(150.0f, 200.0f), above = direction(40.0f, 200.0f);
    auto value = [&](const BsdfParams& b, const Vec3& wi) {
        float p;
        Vec3 f = evalBsdf(b, wo, wi, kUp, kUp, p);
        return maxComponent(f) > 0 && p > 0;
    };
    BsdfParams dt;
    dt.kind = BsdfKind::DiffuseTransmission;
    dt.color = Vec3(0.5f);
    dt.transmittance = Vec3(0.5f);
    BsdfParams coated;
    coated.kind = BsdfKind::CoatedDiffuse;
    coated.alphaX = coated.alphaY = 0.3f;
    BsdfParams rough = roughDielectric(0.3f, 0.3f);
    BsdfParams metal = conductor(0.3f, 0.3f);
    CHECK(value(rough, above));
    CHECK(value(rough, below));
    CHECK(value(dt, above));
    CHECK(value(dt, below));
    CHECK(value(metal, above));
    CHECK_FALSE(value(metal, below));
    CHECK(value(coated, above));
    CHECK_FALSE(value(coated, below));

    CHECK(hasTransmission(rough));
    CHECK(hasTransmission(dt));
    CHECK_FALSE(hasTransmission(metal));
    CHECK_FALSE(hasTransmission(coated));
    CHECK_FALSE(isDeltaBsdf(rough));
    CHECK_FALSE(isDeltaBsdf(metal));
    CHECK_FALSE(isDeltaBsdf(coated));
    BsdfParams smoothMetal = conductor(0.0f, 0.0f), thin;
    thin.kind = BsdfKind::ThinDielectric;
    CHECK(isDeltaBsdf(smoothMetal));
    CHECK(isDeltaBsdf(thin));
    CHECK(hasTransmission(thin));
    BsdfParams glass;
    glass.kind = BsdfKind::Dielectric;
    CHECK(isDeltaBsdf(glass));
}

TEST_CASE("Rough conductor and dielectric obey (generalised) reciprocity", "[bsdf]") {
    // Conductor: f(wo, wi) = f(wi, wo). Dielectric reflection likewise; transmission carries
    // radiance, so f(wi, wo) / eta_wi^2 = f(wo, wi) / eta_wo^2 (Veach 1997, 5.2): with wo
    // outside and wi inside, f(wi, wo) = eta^2 f(wo, wi). evalBsdf returns f |cos wi|.
    auto f = [](const BsdfParams& b, const Vec3& wo, const Vec3& wi) {
        float p;
        return evalBsdf(b, wo, wi, kUp, kUp, p) / std::abs(wi.z);
    };
    BsdfParams metal = conductor(0.2f, 0.45f, Vec3(1.0f, 0.3f, 0.0f));
    BsdfParams glass = roughDielectric(0.25f, 0.15f);
    glass.color = Vec3(1.0f);
    int checked = 0;
    for (float a : {15.0f, 50.0f, 80.0f})
        for (float b : {5.0f, 35.0f, 70.0f})
            for (float phi : {0.0f, 100.0f, 200.0f}) {
                Vec3 wo = direction(a, 10.0f), wi = direction(b, phi);
                INFO("theta_o " << a << ", theta_i " << b << ", phi_i " << phi);
                Vec3 m1 = f(metal, wo, wi), m2 = f(metal, wi, wo);
                CHECK(length(m1 - m2) <= 1e-4f * length(m1) + 1e-7f);
                float r1 = f(glass, wo, wi).x, r2 = f(glass, wi, wo).x;
                CHECK(std::abs(r1 - r2) <= 1e-4f * r1 + 1e-7f);
                Vec3 below = -wi;
                float t1 = f(glass, wo, below).x, t2 = f(glass, below, wo).x;
                CHECK(std::abs(t2 - 2.25f * t1) <= 1e-3f * t2 + 1e-7f);
                checked += t1 > 0;
            }
    CHECK(checked >= 6); // transmission needs wi roughly opposite wo in azimuth
}

TEST_CASE("Every kind with a tilted shading normal: finite values, the right side of ng",
          "[bsdf]") {
    // Shading normals up to ~35 degrees off the geometric one, wo anywhere: samples must be
    // finite and non-negative, reflections must leave on wo's side of ng and transmissions on
    // the other; evalBsdf finite with a non-negative pdf.
    std::vector<BsdfParams> kinds;
    for (BsdfKind k : {BsdfKind::Diffuse, BsdfKind::Mirror, BsdfKind::Dielectric,
                       BsdfKind::Glossy, BsdfKind::Conductor, BsdfKind::ThinDielectric,
                       BsdfKind::DiffuseTransmission, BsdfKind::CoatedDiffuse}) {
        BsdfParams b;
        b.kind = k;
        b.transmittance = Vec3(0.4f);
        b.eta = Vec3(0.2f, 0.9f, 1.1f);
        b.k = Vec3(3.9f, 2.4f, 2.2f);
        kinds.push_back(b);
        if (k == BsdfKind::Dielectric || k == BsdfKind::Conductor ||
            k == BsdfKind::CoatedDiffuse) {
            b.alphaX = 0.3f;
            b.alphaY = 0.05f;
            b.tangent = Vec3(0.3f, 0.8f, 0.1f);
            b.albedo = Vec3(0.5f);
            kinds.push_back(b);
        }
    }
    TestRng rng(77);
    const Vec3 ng = kUp;
    for (const BsdfParams& b0 : kinds) {
        BsdfParams b = b0;
        int bad = 0, wrongSide = 0, valid = 0;
        for (int i = 0; i < 20000; ++i) {
            Vec2 t = rng.uniform2();
            Vec3 ns = normalize(Vec3(0.7f * (t.x - 0.5f), 0.7f * (t.y - 0.5f), 1.0f));
            Vec2 d = rng.uniform2();
            float z = 2.0f * d.x - 1.0f, r = std::sqrt(std::max(0.0f, 1 - z * z));
            Vec3 wo(r * std::cos(2 * kPi * d.y), r * std::sin(2 * kPi * d.y), z);
            if (std::abs(wo.z) < 1e-3f) continue;
            b.key = std::uint64_t(i);
            BsdfSample s = sampleBsdf(b, wo, ng, ns, rng.uniform2(), rng.uniform());
            if (!s.valid) continue;
            ++valid;
            if (!isFinite(s.weight) || s.weight.x < 0 || s.weight.y < 0 || s.weight.z < 0 ||
                !(s.pdf >= 0) || !std::isfinite(s.pdf))
                ++bad;
            float side = dot(s.wi, ng) * dot(wo, ng);
            if (s.transmitted ? side >= 0 : side <= 0) ++wrongSide;
            float p;
            Vec3 f = evalBsdf(b, wo, s.wi, ng, ns, p);
            if (!isFinite(f) || !(p >= 0) || !std::isfinite(p)) ++bad;
        }
        INFO("kind " << int(b.kind) << ", alphas " << b.alphaX << ", " << b.alphaY << ": "
                     << valid << " valid samples");
        CHECK(valid > 5000);
        CHECK(bad == 0);
        CHECK(wrongSide == 0);
    }
}
