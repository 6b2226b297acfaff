// Statistical tests of the coated conductor (pbrt-v4's LayeredBxDF over a conductor). As for the
// coated diffuse surface (coated_diffuse_bsdf_test.cpp), pbrt-v4's pdf is an approximation of
// the walk's density mixed with the uniform sphere, so a chi-square of the sample histogram
// against it would reject a correct implementation; the weighted-histogram test checks the
// sampled weights against evalBsdf's stochastic f |cos| per direction bin instead, and the pdf is
// checked for what MIS needs (positive wherever f is, a sample's pdf equal to evalBsdf's).
#include "bsdf_test_util.h"

using namespace rayproc;
using namespace rayproc::test;
using namespace rayproc::kernels;

namespace {

BsdfParams coatedConductor(float coatAlpha, float baseAlpha, float thickness, Vec3 albedo,
                           float g) {
    BsdfParams b;
    b.kind = BsdfKind::CoatedConductor;
    b.ior = 1.5f;
    b.alphaX = b.alphaY = coatAlpha;
    b.baseAlphaX = b.baseAlphaY = baseAlpha;
    b.eta = Vec3(0.2f, 0.45f, 1.2f);
    b.k = Vec3(3.6f, 2.4f, 1.8f);
    b.thickness = thickness;
    b.albedo = albedo;
    b.g = g;
    b.tangent = Vec3(1.0f, 0.0f, 0.0f);
    return b;
}

// 40 x 40 evaluations per bin: through a mirror base pbrt-v4's f has no MIS at the exit, so its
// estimates are heavy-tailed and a bin's variance needs many of them (12 x 12 underestimated it:
// chi2 619 over 200 bins for the mirror base, 234 with 40 x 40; the totals agreed within 0.2%).
constexpr int kWeightedSamples = 600000, kPerBinSide = 40;

} // namespace

TEST_CASE("Coated conductor: sample weights agree with evalBsdf per direction bin",
          "[bsdf][statistical][coated-conductor]") {
    // A smooth coat over a rough conductor (the coat's delta reflection left out), a rough coat
    // over a smooth conductor (a delta base: the exit's MIS weight is 1), both rough with a
    // scattering slab at a grazing angle, and an anisotropic conductor seen from below.
    struct Case {
        BsdfParams b;
        float theta;
        int channel;
        std::string label;
    };
    BsdfParams aniso = coatedConductor(0.15f, 0.1f, 0.01f, Vec3(0.0f), 0.0f);
    aniso.baseAlphaY = 0.4f;
    BsdfParams mirrorBase = coatedConductor(0.3f, 0.0f, 0.02f, Vec3(0.0f), 0.0f);
    mirrorBase.maxDepth = 100;
    const Case cases[] = {
        {coatedConductor(0.0f, 0.3f, 0.05f, Vec3(0.0f), 0.0f), 30.0f, 0, "smooth coat, rough base"},
        {mirrorBase, 50.0f, 1, "rough coat, mirror base"},
        {coatedConductor(0.25f, 0.2f, 0.2f, Vec3(0.7f, 0.5f, 0.3f), 0.3f), 70.0f, 0,
         "both rough, scattering slab"},
        {aniso, 130.0f, 2, "anisotropic base (0.1, 0.4), wo below"},
    };
    std::uint64_t seed = 11;
    for (const Case& c : cases) {
        Vec3 wo = direction(c.theta);
        Vec3 side = wo.z > 0 ? kUp : -kUp;
        WeightedRun run = weightedHistogramRun(c.b, c.b, wo, side, 0.0f, kWeightedSamples,
                                               kPerBinSide, seed++, c.channel);
        INFO(c.label << ": chi2 " << run.chi2 << " over " << run.bins << " bins, p-value "
                     << run.pValue << ", significance " << testSignificance()
                     << "; sampled total " << run.sampledTotal << ", evaluated total "
                     << run.evaluatedTotal << ", delta fraction " << run.deltaFraction);
        CHECK(run.pValue > testSignificance());
        CHECK(run.evaluatedTotal > 0.05);
    }
}

TEST_CASE("Coated conductor: the weighted test rejects a 5% darker evaluation",
          "[bsdf][statistical][coated-conductor]") {
    BsdfParams b = coatedConductor(0.25f, 0.2f, 0.2f, Vec3(0.7f, 0.5f, 0.3f), 0.3f);
    BsdfParams darker = b;
    darker.albedo = b.albedo * 0.95f;
    darker.k = b.k * 0.9f;
    WeightedRun run = weightedHistogramRun(b, darker, direction(40.0f), kUp, 0.0f,
                                           kWeightedSamples, kPerBinSide, 99, 0);
    INFO("chi2 " << run.chi2 << " over " << run.bins << " bins, p " << run.pValue
                 << "; sampled " << run.sampledTotal << ", darker evaluated "
                 << run.evaluatedTotal);
    CHECK(run.pValue < 1e-6);
}

TEST_CASE("Coated conductor: pdf for MIS, delta cases and deterministic evaluation",
          "[bsdf][coated-conductor]") {
    BsdfParams b = coatedConductor(0.2f, 0.3f, 0.05f, Vec3(0.3f), 0.0f);
    Vec3 wo = direction(35.0f);
    int fWithoutPdf = 0, positive = 0;
    for (int i = 0; i < 60; ++i)
        for (int j = 0; j < 30; ++j) {
            double c = (i + 0.5) / 60, phi = 2 * kPi * (j + 0.5) / 30, s = std::sqrt(1 - c * c);
            Vec3 wi(float(s * std::cos(phi)), float(s * std::sin(phi)), float(c));
            b.key = std::uint64_t(i * 30 + j);
            float p;
            Vec3 f = evalBsdf(b, wo, wi, kUp, kUp, p);
            if (maxComponent(f) > 0 && !(p > 0)) ++fWithoutPdf;
            positive += maxComponent(f) > 0;
            // Opaque: nothing on the other side.
            Vec3 below(wi.x, wi.y, -wi.z);
            CHECK(maxComponent(evalBsdf(b, wo, below, kUp, kUp, p)) == 0);
        }
    CHECK(fWithoutPdf == 0);
    CHECK(positive > 1700);

    // A non-delta sample reports evalBsdf's pdf for its direction; same key, same estimate.
    int mismatches = 0, valid = 0;
    samplePdfConsistency(b, wo, valid, mismatches);
    CHECK(valid > 1000);
    CHECK(mismatches == 0);

    // A smooth coat over a smooth conductor without scattering is all delta: evalBsdf is zero,
    // every sample is a mirror reflection about the normal.
    BsdfParams mirror = coatedConductor(0.0f, 0.0f, 0.05f, Vec3(0.0f), 0.0f);
    CHECK(isDeltaBsdf(mirror));
    CHECK(!isDeltaBsdf(b));
    float p;
    CHECK(maxComponent(evalBsdf(mirror, wo, Vec3(-wo.x, -wo.y, wo.z), kUp, kUp, p)) == 0);
    int deltas = 0;
    TestRng rng(5);
    for (int i = 0; i < 500; ++i) {
        BsdfSample s = sampleBsdf(mirror, wo, kUp, kUp, rng.uniform2(), rng.uniform());
        if (!s.valid) continue;
        deltas += s.delta;
        CHECK(length(s.wi - Vec3(-wo.x, -wo.y, wo.z)) < 1e-4f);
    }
    CHECK(deltas > 400);
}
