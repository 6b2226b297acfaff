// White-furnace tests of the pbrt-v4 BSDF kinds: the directional albedo (mean sample weight, in
// energy units) of lossless settings. Single-scattering microfacet models lose the energy of
// light that would scatter more than once between microfacets, more at higher alpha and at
// grazing angles; the bounds below are the measured values less a margin (measured with 4e5
// samples; the figures are in the comments). Every albedo must also stay <= 1 (+ 4 sigma).
// The rough conductor's albedo is compared with an independent quadrature of
// int D_wo(m) F G2 / G1 dm, so a wrong weight fails even where the bound is loose.
#include "statistical/bsdf_test_util.h"

using namespace rayproc;
using namespace rayproc::test;
using namespace rayproc::kernels;

namespace {

constexpr int kAlbedoSamples = 400000;

void checkAtMostOne(const Albedo& a, const std::string& label) {
    for (int c = 0; c < 3; ++c) {
        INFO(label << ", channel " << c << ": albedo " << a.mean[c] << " +- " << a.stdError[c]);
        CHECK(a.mean[c] <= 1.0f + 4.0f * a.stdError[c] + 1e-4f);
    }
}

// The single-scattering albedo of a lossless rough conductor by quadrature over the microfacet
// normals: E(wo) = int D_wo(m) G(wo, wi) / G1(wo) [wi = reflect(wo, m) above] dm.
double conductorAlbedoQuadrature(const TrowbridgeReitz& mf, const Vec3& wo) {
    const int n = 1200, m = 600;
    double e = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {
            double c = (i + 0.5) / n, phi = 2 * kPi * (j + 0.5) / m;
            double s = std::sqrt(1 - c * c);
            Vec3 h(float(s * std::cos(phi)), float(s * std::sin(phi)), float(c));
            Vec3 wi = reflectAbout(wo, h);
            if (wi.z > 0) e += mf.dVisible(wo, h) * mf.g(wo, wi) / mf.g1(wo);
        }
    return e * (1.0 / n) * (2 * kPi / m);
}

} // namespace

TEST_CASE("Furnace: lossless rough conductor", "[bsdf][furnace]") {
    // eta = 1, k = 1000: F > 0.99999 at every angle. Measured at 0 / 45 / 80 degrees:
    // alpha 0.1: 0.988 / 0.982 / 0.896; 0.3: 0.878 / 0.846 / 0.849; 0.5: 0.689 / 0.684 / 0.806.
    // (At normal incidence and alpha 0.5 a third of the reflected directions are below the
    // horizon: that is the loss.)
    struct Bound {
        float alpha, theta, atLeast;
    };
    const Bound bounds[] = {{0.1f, 0.0f, 0.98f},  {0.1f, 45.0f, 0.97f}, {0.1f, 80.0f, 0.88f},
                            {0.3f, 0.0f, 0.86f},  {0.3f, 80.0f, 0.83f}, {0.5f, 0.0f, 0.67f},
                            {0.5f, 80.0f, 0.79f}};
    for (const Bound& bd : bounds) {
        BsdfParams b;
        b.kind = BsdfKind::Conductor;
        b.eta = Vec3(1.0f);
        b.k = Vec3(1000.0f);
        b.alphaX = b.alphaY = bd.alpha;
        Vec3 wo = direction(bd.theta);
        Albedo a = directionalAlbedo(b, wo, kAlbedoSamples, 17);
        double q = conductorAlbedoQuadrature({bd.alpha, bd.alpha}, wo);
        std::string label =
            "alpha " + std::to_string(bd.alpha) + ", theta_o " + std::to_string(bd.theta);
        INFO(label << ": albedo " << a.mean.x << " +- " << a.stdError.x << ", quadrature " << q);
        checkAtMostOne(a, label);
        CHECK(a.mean.x >= bd.atLeast);
        CHECK(std::abs(a.mean.x - q) <= 4.0 * a.stdError.x + 2e-3);
    }
    // Anisotropic alphas lose in between their isotropic neighbours.
    BsdfParams b;
    b.kind = BsdfKind::Conductor;
    b.eta = Vec3(1.0f);
    b.k = Vec3(1000.0f);
    b.alphaX = 0.1f;
    b.alphaY = 0.3f;
    Albedo a = directionalAlbedo(b, direction(45.0f), kAlbedoSamples, 18);
    checkAtMostOne(a, "anisotropic");
    CHECK(a.mean.x >= 0.85f);
}

TEST_CASE("Conductor: complex Fresnel at normal incidence", "[bsdf]") {
    // ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2), per channel, for gold-like and aluminium-like
    // indices; the smooth conductor's sample weight at normal incidence is that reflectance, and
    // a slightly rough one's albedo is within its (tiny) microfacet loss.
    const Vec3 etas[] = {Vec3(0.143f, 0.374f, 1.442f), Vec3(1.657f, 0.880f, 0.521f)};
    const Vec3 ks[] = {Vec3(3.983f, 2.385f, 1.603f), Vec3(9.224f, 6.270f, 4.837f)};
    for (int i = 0; i < 2; ++i) {
        BsdfParams b;
        b.kind = BsdfKind::Conductor;
        b.eta = etas[i];
        b.k = ks[i];
        BsdfSample s = sampleBsdf(b, kUp, kUp, kUp, {0.3f, 0.6f}, 0.5f);
        REQUIRE(s.valid);
        CHECK(s.delta);
        CHECK(length(s.wi - kUp) < 1e-6f);
        b.alphaX = b.alphaY = 0.01f;
        Albedo rough = directionalAlbedo(b, kUp, 20000, 3);
        for (int c = 0; c < 3; ++c) {
            float n = etas[i][c], k = ks[i][c];
            float expected = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
            INFO("set " << i << ", channel " << c << ": expected " << expected);
            CHECK(std::abs(fresnelComplex(1.0f, n, k) - expected) < 1e-5f);
            CHECK(std::abs(s.weight[c] - expected) < 1e-5f);
            CHECK(std::abs(rough.mean[c] - expected) < 2e-3f);
        }
    }
    // k = 0 is a dielectric: the complex formula must agree with the real one at every angle.
    for (float c : {1.0f, 0.7f, 0.3f, 0.05f})
        CHECK(std::abs(fresnelComplex(c, 1.5f, 0.0f) - fresnelDielectric(c, 1.5f)) < 1e-5f);
}

TEST_CASE("Furnace: rough dielectric reflection plus transmission", "[bsdf][furnace]") {
    // Energy: transmitted weights carry radiance's 1 / etap^2, undone here (times etap^2);
    // color 1. Measured (outside 0 / 45 / 80; inside 0 / 30 / 60 degrees):
    // alpha 0.1: 0.999 / 0.997 / 0.943; 0.989 / 0.985 / 0.963.
    // alpha 0.3: 0.988 / 0.972 / 0.901; 0.899 / 0.870 / 0.785.
    struct Bound {
        float alpha, theta, atLeast;
    };
    const Bound bounds[] = {{0.1f, 0.0f, 0.99f},   {0.1f, 45.0f, 0.99f},  {0.1f, 80.0f, 0.93f},
                            {0.1f, 180.0f, 0.98f}, {0.1f, 150.0f, 0.97f}, {0.1f, 120.0f, 0.95f},
                            {0.3f, 0.0f, 0.98f},   {0.3f, 80.0f, 0.89f},  {0.3f, 120.0f, 0.77f}};
    for (const Bound& bd : bounds) {
        BsdfParams b;
        b.kind = BsdfKind::Dielectric;
        b.ior = 1.5f;
        b.color = Vec3(1.0f);
        b.alphaX = b.alphaY = bd.alpha;
        Vec3 wo = direction(bd.theta);
        float etap = wo.z > 0 ? b.ior : 1.0f / b.ior;
        Albedo a = directionalAlbedo(b, wo, kAlbedoSamples, 19, [&](const BsdfSample& s) {
            return s.transmitted ? s.weight * (etap * etap) : s.weight;
        });
        std::string label =
            "alpha " + std::to_string(bd.alpha) + ", theta_o " + std::to_string(bd.theta);
        INFO(label << ": albedo " << a.mean.x << " +- " << a.stdError.x);
        checkAtMostOne(a, label);
        CHECK(a.mean.x >= bd.atLeast);
    }
}

TEST_CASE("Furnace: thin dielectric and its multiple-reflection probability", "[bsdf][furnace]") {
    BsdfParams b;
    b.kind = BsdfKind::ThinDielectric;
    b.ior = 1.5f;
    // R' = R + T^2 R / (1 - R^2) equals 2R / (1 + R) (the series in closed form).
    for (float c : {1.0f, 0.5f, 0.1f}) {
        float r = fresnelDielectric(c, 1.5f);
        CHECK(std::abs(thinDielectricReflectance(c, 1.5f) - 2 * r / (1 + r)) < 1e-6f);
    }
    for (float theta : {0.0f, 60.0f, 85.0f, 135.0f}) {
        Vec3 wo = direction(theta);
        float rSlab = thinDielectricReflectance(std::abs(wo.z), b.ior);
        float rSingle = fresnelDielectric(std::abs(wo.z), b.ior);
        TestRng rng(23);
        const int n = 200000;
        int reflected = 0, wrong = 0;
        for (int i = 0; i < n; ++i) {
            BsdfSample s = sampleBsdf(b, wo, kUp, kUp, rng.uniform2(), rng.uniform());
            if (!s.valid || !s.delta || length(s.weight - Vec3(1.0f)) != 0) ++wrong;
            if (s.transmitted) {
                if (length(s.wi + wo) > 1e-6f) ++wrong; // straight through
            } else {
                ++reflected;
                if (length(s.wi - reflect(wo, wo.z > 0 ? kUp : -kUp)) > 1e-5f) ++wrong;
            }
        }
        double sigma = std::sqrt(n * double(rSlab) * (1 - rSlab));
        INFO("theta_o " << theta << ": reflected " << reflected << ", expected " << n * rSlab
                        << " +- " << sigma << " (single interface: " << n * rSingle << ")");
        CHECK(wrong == 0); // every weight is 1: the furnace albedo is exactly 1
        CHECK(std::abs(reflected - n * rSlab) <= 4 * sigma);
        // The single-interface probability is rejected (the test can fail).
        CHECK(std::abs(reflected - n * rSingle) > 4 * sigma);
    }
}

TEST_CASE("Furnace: diffuse transmission with R + T = 1", "[bsdf][furnace]") {
    BsdfParams b;
    b.kind = BsdfKind::DiffuseTransmission;
    b.color = Vec3(0.2f, 0.5f, 0.3f);
    b.transmittance = Vec3(0.8f, 0.5f, 0.7f);
    for (float theta : {0.0f, 60.0f, 120.0f}) {
        Albedo a = directionalAlbedo(b, direction(theta), kAlbedoSamples, 29);
        for (int c = 0; c < 3; ++c) {
            INFO("theta_o " << theta << ", channel " << c << ": " << a.mean[c] << " +- "
                            << a.stdError[c]);
            CHECK(std::abs(a.mean[c] - 1.0f) <= 4.0f * a.stdError[c]);
        }
    }
    // R + T = 0.8 per channel gives 0.8, not 1 (the test can fail).
    b.transmittance = Vec3(0.6f, 0.3f, 0.5f);
    Albedo lossy = directionalAlbedo(b, direction(30.0f), kAlbedoSamples, 31);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(lossy.mean[c] - 0.8f) <= 4.0f * lossy.stdError[c]);
}

TEST_CASE("Furnace: coated diffuse with a white base", "[bsdf][furnace]") {
    // Lossless settings: a nearly vanishing slab (thickness 1e-4, no scattering) or a scattering
    // slab of albedo 1; maxDepth 100 so that the walk's truncation loses nothing measurable.
    // Measured (0 / 45 / 80 degrees): smooth coat 0.9991 / 0.9991 / 0.9994; scattering slab
    // (albedo 1, g 0.3, thickness 0.1) 1.0000; rough coat alpha 0.1: 0.925 / 0.923 / 0.890,
    // alpha 0.3: 0.703 / 0.693 / 0.668 (light meets the rough interface many times from
    // inside, losing its single-scattering deficit each time). The default maxDepth 10 loses
    // the walks still trapped by total internal reflection: smooth coat, thickness 1e-4: 0.928;
    // thickness 0.01 (the default): 0.866.
    struct Case {
        float alpha, thickness, albedo, g;
        int maxDepth;
        float atLeast;
    };
    const Case cases[] = {{0.0f, 1e-4f, 0.0f, 0.0f, 100, 0.995f},
                          {0.0f, 0.1f, 1.0f, 0.3f, 100, 0.995f},
                          {0.1f, 1e-4f, 0.0f, 0.0f, 100, 0.88f},
                          {0.3f, 1e-4f, 0.0f, 0.0f, 100, 0.66f},
                          {0.0f, 1e-4f, 0.0f, 0.0f, 10, 0.92f}};
    for (const Case& c : cases)
        for (float theta : {0.0f, 45.0f, 80.0f}) {
            BsdfParams b;
            b.kind = BsdfKind::CoatedDiffuse;
            b.color = Vec3(1.0f);
            b.alphaX = b.alphaY = c.alpha;
            b.thickness = c.thickness;
            b.albedo = Vec3(c.albedo);
            b.g = c.g;
            b.maxDepth = c.maxDepth;
            Albedo a = directionalAlbedo(b, direction(theta), kAlbedoSamples, 37);
            std::string label = "alpha " + std::to_string(c.alpha) + ", thickness " +
                                std::to_string(c.thickness) + ", albedo " +
                                std::to_string(c.albedo) + ", maxDepth " +
                                std::to_string(c.maxDepth) + ", theta_o " +
                                std::to_string(theta);
            INFO(label << ": albedo " << a.mean.x << " +- " << a.stdError.x);
            checkAtMostOne(a, label);
            CHECK(a.mean.x >= c.atLeast);
        }
    // A black base under a smooth coat reflects exactly the coat's Fresnel reflectance.
    BsdfParams b;
    b.kind = BsdfKind::CoatedDiffuse;
    b.color = Vec3(0.0f);
    for (float theta : {0.0f, 60.0f, 85.0f}) {
        Vec3 wo = direction(theta);
        Albedo a = directionalAlbedo(b, wo, kAlbedoSamples, 41);
        float f = fresnelDielectric(wo.z, b.ior);
        INFO("black base, theta_o " << theta << ": " << a.mean.x << " +- " << a.stdError.x
                                    << ", Fresnel " << f);
        CHECK(std::abs(a.mean.x - f) <= 4.0f * a.stdError.x + 1e-6f);
    }
}
