// Cache refinement (GiSettings::icRefineRays): the records keep gathering before every render
// pass, so the noise of their prepass gather leaves the image as passes accumulate. Checked on
// the Cornell box with deliberately noisy records (4 prepass rays each) against the same render
// with 256-ray records (same photon map: same seed and photons): with refinement the image's
// error against it falls to a fraction; the rays added are exactly records x rays x passes; the
// image does not depend on the thread count. (Correction rays, which take the map's own bias
// out of the records: tests/gi/map_correction_test.cpp.)
#include "gi/cache_refinement.h"
#include "kernels/random.h"
#include "test_util.h"

#include <cmath>

using namespace rayproc;
using namespace rayproc::test;

namespace {

RenderResult render(const Scene& scene, const EmbreeScene& accel, int gatherRays, int refineRays,
                    int threads, bool halves = false) {
    EngineSettings engine;
    // An error target below reach: half buffers and their estimate, all 32 passes.
    RenderControl control;
    if (halves) control.targetRelMse = 1e-12;
    engine.threads = threads;
    engine.seed = 5;
    engine.quiet = true;
    GiSettings s = giSettings(scene, ModeOverrides{32, 0, 0});
    s.photons = 20000;
    s.gatherRays = gatherRays;
    s.filmGatherRays = 64; // cache misses: the same gathers in every render
    s.icRefineRays = refineRays;
    s.icCorrectionRays = 0; // refinement alone: the same map's exact gather is the target
    return renderGi(scene, accel, s, engine, control);
}

} // namespace

TEST_CASE("Cache refinement: records gather on during the render and their noise leaves the image",
          "[gi][cache]") {
    auto scene = loadSceneAt("cornell-box", 32, 32);
    EmbreeScene accel(*scene);
    RenderResult reference = render(*scene, accel, 256, 0, 2);
    RenderResult frozen = render(*scene, accel, 4, 0, 2);
    RenderResult refined = render(*scene, accel, 4, 8, 2);

    const double records = extraStat(refined, "gi/cache_records");
    const double rays = extraStat(refined, "gi/refine_rays");
    INFO(records << " records, " << rays << " refinement rays");
    CHECK(records > 20);
    CHECK(extraStat(frozen, "gi/refine_rays") == 0);
    // 8 rays per record before each of the 31 passes after the first (below-surface strata
    // count as dark rays, as in a gather).
    CHECK(rays == records * 8 * 31);

    const double errFrozen = relMse(frozen.image, reference.image);
    const double errRefined = relMse(refined.image, reference.image);
    INFO("relMSE against 256-ray records: frozen 4-ray records " << errFrozen << ", refined "
                                                                 << errRefined);
    CHECK(errRefined < 0.25 * errFrozen); // measured: 0.00042 against 0.0066

    RenderResult one = render(*scene, accel, 4, 8, 1);
    CHECK(one.image.pixels == refined.image.pixels);
}

TEST_CASE("Record corrections' weight: one James-Stein weight from the means and their noise",
          "[gi][cache]") {
    // Exact cases: 1 - sum(v) / sum(b^2).
    CHECK(shrinkageWeight({3.0, 4.0}, {5.0, 0.0}) == Approx(0.8));
    CHECK(shrinkageWeight({0.0, 0.0}, {1.0, 1.0}) == 0.0); // nothing to apply
    CHECK(shrinkageWeight({}, {}) == 0.0);
    CHECK(shrinkageWeight({1.0}, {2.0}) == 0.0);          // clamped at 0
    CHECK(shrinkageWeight({-2.0, 2.0}, {0.0, 0.0}) == 1.0); // noiseless: all of it

    // Simulated: 4000 means b_i = beta_i + noise of variance v. Pure noise (beta = 0) gets a
    // weight near 0; a bias as large as the noise about half (the optimum beta^2 / (beta^2 +
    // v) = 0.5); a bias 10 times the noise's deviation about 0.99.
    auto weightFor = [](double beta, double v) {
        std::vector<double> means, variances;
        for (std::uint64_t i = 0; i < 4000; ++i) {
            // A standard normal from two uniforms (Box-Muller).
            double u1 = std::max(double(kernels::uniform(i, 0)), 1e-12);
            double u2 = kernels::uniform(i, 1);
            double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
            means.push_back(beta + std::sqrt(v) * z);
            variances.push_back(v);
        }
        return shrinkageWeight(means, variances);
    };
    CHECK(weightFor(0.0, 1.0) < 0.1);
    CHECK(weightFor(1.0, 1.0) == Approx(0.5).margin(0.05));
    CHECK(weightFor(10.0, 1.0) == Approx(0.99).margin(0.005));
}

TEST_CASE("Cache refinement: the two half buffers read records refined by their own passes",
          "[gi][cache]") {
    // Even and odd passes go to the film's two half buffers, whose difference estimates the
    // image's noise (--target-relmse). Each half's passes read records refined by rays of that
    // half's passes only, so the records' noise differs between the halves and the estimate
    // sees it; records shared by both halves would hide it. Records of 4 prepass rays and one
    // more each pass against records of 256: the first's noise should show in the estimate.
    auto scene = loadSceneAt("cornell-box", 32, 32);
    EmbreeScene accel(*scene);
    RenderResult clean = render(*scene, accel, 256, 1, 2, true);
    RenderResult noisy = render(*scene, accel, 4, 1, 2, true);
    REQUIRE(noisy.samplesDone == 32);
    INFO("relMSE estimate with 4-ray records " << noisy.relMseEstimate << ", with 256-ray "
                                              << clean.relMseEstimate);
    // Measured: 0.00175 against 0.00118; with records shared by the halves 0.00125 against
    // 0.00118 (the pixels' noise alone).
    CHECK(noisy.relMseEstimate > 1.25 * clean.relMseEstimate);
}
