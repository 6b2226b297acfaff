// Path mode's contributions by strategy (--stats "path/..."; ThreadStats::contributions): every
// contribution to the film is filed under exactly one category, so the categories' summed
// luminance is the image's; a light in view is "direct", and a light lit through a glossy
// surface shows up under its light samples and its BSDF-found emission.
#include "test_util.h"

#include <catch2/catch.hpp>

#include <string>

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("Path contributions by strategy add up to the image, one category each",
          "[modes][stats]") {
    auto scene = loadSceneAt("cornell-box", 32, 32);
    EmbreeScene accel(*scene);
    RenderOptions o;
    o.mode = "path";
    o.spp = 16;
    RenderResult r = render(*scene, accel, o);
    const auto& c = r.stats.totals.contributions;
    REQUIRE(c.size() >= 3); // direct, light 0's samples, light 0 found by BSDF rays
    double filed = 0;
    for (const ContributionMoments& m : c) filed += m.sum;
    double image = 0;
    for (std::size_t p = 0; p + 2 < r.image.pixels.size(); p += 3)
        image += double(luminance({r.image.pixels[p], r.image.pixels[p + 1], r.image.pixels[p + 2]}));
    INFO("filed " << filed / (32.0 * 32 * 16) << ", image mean " << image / (32.0 * 32));
    CHECK(filed / (32.0 * 32 * 16) == Approx(image / (32.0 * 32)).epsilon(1e-4));
    CHECK(c[0].count > 0);                            // the light in view
    CHECK(c[contributionOfLightSample(0)].count > 0); // next-event estimation
    CHECK(c[contributionOfBsdfHit(0)].count > 0);     // BSDF rays that found the light
    // The extras name them, and the image shares sum to one.
    double shares = 0;
    for (const auto& e : r.stats.extras)
        if (e.first.size() > 12 && e.first.compare(e.first.size() - 12, 12, "_image_share") == 0)
            shares += e.second;
    CHECK(shares == Approx(1.0).epsilon(1e-9));
}
