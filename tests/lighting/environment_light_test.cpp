// EnvironmentLight with images: radiance lookup of known pixels (in a rotated frame too),
// sampling against pdf (chi-square), the pdf integrating to one over the sphere, weights equal
// to radiance / pdf, mixtures of a constant sky and several images, and photon directions.
#include "image/image.h"
#include "lighting/environment.h"
#include "lighting/sphere_mapping.h"
#include "statistical/statistical.h"

#include <catch2/catch.hpp>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A w x h image with smoothly varying, strictly positive channels and one bright pixel.
std::shared_ptr<const Image> testImage(int w, int h, int sunX, int sunY, float sun) {
    auto img = std::make_shared<Image>(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* p = img->at(x, y);
            p[0] = 0.2f + 0.1f * float(x % 3);
            p[1] = 0.1f + 0.05f * float((x + y) % 5);
            p[2] = 0.3f + 0.02f * float(y);
        }
    float* s = img->at(sunX, sunY);
    s[0] = s[1] = s[2] = sun;
    return img;
}

Light imageLight(std::shared_ptr<const Image> img, EnvironmentMapping m, Vec3 scale,
                 Affine frame = {}) {
    Light l;
    l.type = LightType::Environment;
    l.image = std::move(img);
    l.mapping = m;
    l.intensity = scale;
    l.toWorld = frame;
    return l;
}

// Integral of pdf over the sphere by a fine (cos theta, phi) midpoint rule.
double pdfIntegral(const EnvironmentLight& env, bool compensated = false) {
    const int n = 1000;
    double sum = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < 2 * n; ++i) {
            double z = -1 + (j + 0.5) * 2.0 / n, phi = (i + 0.5) * kPi / n;
            double r = std::sqrt(1 - z * z);
            sum += env.pdf({float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)}, {},
                           compensated);
        }
    return sum * (2.0 / n) * (kPi / n);
}

void checkSampling(const EnvironmentLight& env, std::uint64_t seed, bool compensated = false) {
    const int samples = 1000000;
    DirectionHistogram h({0, 0, 1}, -1.0f, 10, 20);
    TestRng rng(seed);
    for (int i = 0; i < samples; ++i) {
        EnvironmentSample s = env.sample(rng.uniform2(), {0, 1, 0}, compensated);
        if (!s.valid) {
            h.addOutside();
            continue;
        }
        h.add(s.wi);
        // The sample's own pdf is pdf(), its weight radiance / pdf.
        if (i % 97 == 0) {
            REQUIRE(s.pdf == Approx(env.pdf(s.wi, {}, compensated)).epsilon(1e-3));
            Vec3 L = env.radiance(s.wi);
            for (int c = 0; c < 3; ++c) REQUIRE(s.weight[c] * s.pdf == Approx(L[c]).epsilon(1e-3));
        }
    }
    auto expected =
        h.expected([&](const Vec3& w) { return double(env.pdf(w, {}, compensated)); }, samples, 5);
    ChiSquareResult r = chiSquareTest(h.counts(), expected);
    INFO("chi2 " << r.chi2 << " dof " << r.dof << " p " << r.pValue);
    CHECK(r.pValue > testSignificance());
}

} // namespace

TEST_CASE("Image sky: radiance of a known pixel's direction, in a rotated frame", "[lights]") {
    auto img = testImage(16, 16, 5, 3, 40.0f);
    Affine frame = Affine::rotate(90.0f, {1, 0, 0}); // light +z -> world -y
    EnvironmentLight env;
    env.add(imageLight(img, EnvironmentMapping::EqualArea, {2, 2, 2}, frame));
    for (auto [x, y] : {std::pair{5, 3}, {0, 0}, {15, 7}, {8, 8}}) {
        Vec3 dLight = equalAreaSquareToSphere({(x + 0.5f) / 16, (y + 0.5f) / 16});
        Vec3 L = env.radiance(frame.vector(dLight));
        const float* p = img->at(x, y);
        CHECK(L.x == Approx(2 * p[0]));
        CHECK(L.y == Approx(2 * p[1]));
        CHECK(L.z == Approx(2 * p[2]));
    }
    // The image's centre (+z in light space) is world -y after the rotation.
    const float* c = img->at(8, 8);
    CHECK(env.radiance({0, -1, 0}).x == Approx(2 * c[0]));
    CHECK_FALSE(env.cosineSampled());
}

TEST_CASE("Image sky (equal-area): samples follow pdf, which integrates to 1", "[lights]") {
    EnvironmentLight env;
    env.add(imageLight(testImage(8, 8, 2, 5, 30.0f), EnvironmentMapping::EqualArea, {1, 1, 1},
                       Affine::rotate(30.0f, {1, 1, 0})));
    CHECK(pdfIntegral(env) == Approx(1.0).epsilon(2e-3));
    checkSampling(env, 11);
}

// MIS compensation (path mode's light samples of an image sky): the density of the excess over
// the mean, sampled as its pdf says; nothing below the mean; the plain density when no pixel is
// above it (a flat image).
TEST_CASE("Image sky, compensated: samples follow pdf, which is zero below the mean", "[lights]") {
    const int res = 8, samples = 1000000;
    auto img = testImage(res, res, 2, 5, 30.0f);
    EnvironmentLight env;
    env.add(imageLight(img, EnvironmentMapping::EqualArea, {1, 1, 1}));
    CHECK(pdfIntegral(env, true) == Approx(1.0).epsilon(2e-3));
    // The density is piecewise constant over the pixels, most of them zero: the chi-square
    // runs over the pixels, against each one's excess over the mean (equal-area: all pixels
    // cover the same solid angle).
    const float mean = (env.average().x + env.average().y + env.average().z) / 3;
    std::vector<double> observed(res * res, 0.0), expected(res * res, 0.0);
    double total = 0;
    int below = 0;
    for (int y = 0; y < res; ++y)
        for (int x = 0; x < res; ++x) {
            const float* p = img->at(x, y);
            const double e = std::max(0.0, (p[0] + p[1] + p[2]) / 3.0 - mean);
            expected[std::size_t(y * res + x)] = e;
            total += e;
            below += e == 0;
            Vec3 d = equalAreaSquareToSphere({(x + 0.5f) / res, (y + 0.5f) / res});
            if (e == 0) CHECK(env.pdf(d, {}, true) == 0.0f);
            else CHECK(env.pdf(d, {}, true) > 0.0f);
        }
    CHECK(below > 16);
    for (double& e : expected) e *= samples / total;
    TestRng rng(21);
    for (int i = 0; i < samples; ++i) {
        EnvironmentSample s = env.sample(rng.uniform2(), {0, 1, 0}, true);
        REQUIRE(s.valid);
        if (i % 97 == 0) {
            REQUIRE(s.pdf == Approx(env.pdf(s.wi, {}, true)).epsilon(1e-3));
            REQUIRE(s.weight.x * s.pdf == Approx(env.radiance(s.wi).x).epsilon(1e-3));
        }
        Vec2 uv = equalAreaSphereToSquare(s.wi);
        int x = std::min(res - 1, int(uv.x * res)), y = std::min(res - 1, int(uv.y * res));
        observed[std::size_t(y * res + x)] += 1;
    }
    ChiSquareResult r = chiSquareTest(observed, expected);
    INFO("chi2 " << r.chi2 << " dof " << r.dof << " p " << r.pValue);
    CHECK(r.pValue > testSignificance());
    // The sun pixel takes a larger share than without compensation.
    Vec3 sun = equalAreaSquareToSphere({2.5f / res, 5.5f / res});
    CHECK(env.pdf(sun, {}, true) > env.pdf(sun, {}));
    // A flat image has nothing above its mean: sampled as without compensation.
    auto flat = std::make_shared<Image>(8, 8);
    for (float& v : flat->pixels) v = 2.0f;
    EnvironmentLight even;
    even.add(imageLight(flat, EnvironmentMapping::EqualArea, {1, 1, 1}));
    CHECK(even.pdf({0, 0, 1}, {}, true) == Approx(1.0 / (4 * kPi)));
}

// The lat-long density has an integrable 1 / sin(theta) singularity at the poles, which the
// histogram's midpoint rules integrate poorly: the chi-square runs in the image's (u, v) space,
// where the density is piecewise constant (the expected count of a pixel is exact), and the
// conversion to solid angle is checked by pdf() integrating to 1 and by weight * pdf = L.
TEST_CASE("Image sky (lat-long): samples follow pdf, which integrates to 1", "[lights]") {
    const int w = 16, h = 8, samples = 1000000;
    auto img = testImage(w, h, 3, 2, 30.0f);
    EnvironmentLight env;
    env.add(imageLight(img, EnvironmentMapping::LatLong, {1, 1, 1}));
    CHECK(pdfIntegral(env) == Approx(1.0).epsilon(2e-3));
    std::vector<double> observed(w * h, 0.0), expected(w * h, 0.0);
    TestRng rng(12);
    for (int i = 0; i < samples; ++i) {
        EnvironmentSample s = env.sample(rng.uniform2(), {0, 1, 0});
        REQUIRE(s.valid);
        if (i % 97 == 0) {
            REQUIRE(s.pdf == Approx(env.pdf(s.wi, {})).epsilon(1e-3));
            REQUIRE(s.weight.x * s.pdf == Approx(env.radiance(s.wi).x).epsilon(1e-3));
        }
        Vec2 uv = sphereToLatLong(s.wi);
        int x = std::min(w - 1, int(uv.x * w)), y = std::min(h - 1, int(uv.y * h));
        observed[std::size_t(y * w + x)] += 1;
    }
    // Expected: the pixel's channel mean times its solid angle share (sin theta at the row).
    double total = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float* p = img->at(x, y);
            double v = (p[0] + p[1] + p[2]) / 3.0 * std::sin(kPi * (y + 0.5) / h);
            expected[std::size_t(y * w + x)] = v;
            total += v;
        }
    for (double& e : expected) e *= samples / total;
    ChiSquareResult r = chiSquareTest(observed, expected);
    INFO("chi2 " << r.chi2 << " dof " << r.dof << " p " << r.pValue);
    CHECK(r.pValue > testSignificance());
}

TEST_CASE("Constant sky plus two images: radiance adds, the mixture pdf is consistent",
          "[lights]") {
    EnvironmentLight env;
    Light constant;
    constant.type = LightType::Environment;
    constant.intensity = {0.5f, 0.5f, 0.5f};
    env.add(constant);
    env.add(imageLight(testImage(8, 8, 1, 1, 20.0f), EnvironmentMapping::EqualArea, {1, 1, 1}));
    env.add(imageLight(testImage(16, 8, 9, 4, 10.0f), EnvironmentMapping::LatLong, {3, 3, 3}));
    env.add(imageLight(testImage(4, 4, 2, 1, 50.0f), EnvironmentMapping::EqualArea, {1, 1, 1},
                       Affine::rotate(70.0f, {0, 1, 0})));
    Vec3 d = normalize(Vec3{0.3f, -0.4f, 0.8f});
    EnvironmentLight a, b;
    a.add(imageLight(testImage(8, 8, 1, 1, 20.0f), EnvironmentMapping::EqualArea, {1, 1, 1}));
    b.add(imageLight(testImage(16, 8, 9, 4, 10.0f), EnvironmentMapping::LatLong, {3, 3, 3}));
    EnvironmentLight c;
    c.add(imageLight(testImage(4, 4, 2, 1, 50.0f), EnvironmentMapping::EqualArea, {1, 1, 1},
                     Affine::rotate(70.0f, {0, 1, 0})));
    Vec3 sum = a.radiance(d) + b.radiance(d) + c.radiance(d) + Vec3(0.5f);
    CHECK(env.radiance(d).x == Approx(sum.x));
    CHECK(env.radiance(d).z == Approx(sum.z));
    CHECK(env.average().y == Approx(a.average().y + b.average().y + c.average().y + 0.5f));
    CHECK(pdfIntegral(env) == Approx(1.0).epsilon(2e-3));
    // Chi-square in direction space without the lat-long image (see the lat-long test).
    EnvironmentLight noLatLong;
    noLatLong.add(constant);
    noLatLong.add(imageLight(testImage(8, 8, 1, 1, 20.0f), EnvironmentMapping::EqualArea, {1, 1, 1}));
    noLatLong.add(imageLight(testImage(4, 4, 2, 1, 50.0f), EnvironmentMapping::EqualArea,
                             {1, 1, 1}, Affine::rotate(70.0f, {0, 1, 0})));
    checkSampling(noLatLong, 13);
    // With it: every sample's pdf and weight are the mixture's.
    TestRng rng(14);
    for (int i = 0; i < 20000; ++i) {
        EnvironmentSample s = env.sample(rng.uniform2(), {0, 0, 1});
        REQUIRE(s.valid);
        REQUIRE(s.pdf == Approx(env.pdf(s.wi, {})).epsilon(1e-3));
        REQUIRE(s.weight.y * s.pdf == Approx(env.radiance(s.wi).y).epsilon(1e-3));
    }
}

TEST_CASE("Image sky: average radiance, and sampleSphere for photons", "[lights]") {
    auto img = std::make_shared<Image>(4, 4);
    for (float& v : img->pixels) v = 1.0f;
    img->at(1, 2)[0] = 17.0f; // one of 16 equal-area pixels: mean red (15 + 17) / 16 = 2
    EnvironmentLight env;
    env.add(imageLight(img, EnvironmentMapping::EqualArea, {1, 1, 1}));
    CHECK(env.average().x == Approx(2.0f));
    CHECK(env.average().y == Approx(1.0f));
    // The Monte Carlo mean of weight over sampleSphere is the integral of radiance: 4 pi avg.
    TestRng rng(5);
    Vec3 sum{0, 0, 0};
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        EnvironmentSample s = env.sampleSphere(rng.uniform2());
        REQUIRE(s.valid);
        sum += s.weight;
    }
    CHECK(sum.x / n == Approx(4 * kPi * 2.0f).epsilon(0.01));
    CHECK(sum.y / n == Approx(4 * kPi * 1.0f).epsilon(0.01));
}

TEST_CASE("Constant sky keeps its cosine-weighted sampling", "[lights]") {
    EnvironmentLight env;
    Light constant;
    constant.type = LightType::Environment;
    constant.intensity = {1.0f, 2.0f, 3.0f};
    env.add(constant);
    CHECK(env.cosineSampled());
    EnvironmentSample s = env.sample({0.3f, 0.7f}, {0, 0, 1});
    REQUIRE(s.valid);
    CHECK(s.pdf == Approx(s.wi.z / kPi));
    CHECK(env.pdf(s.wi, {0, 0, 1}) == Approx(s.pdf));
}
