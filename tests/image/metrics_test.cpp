// Image metrics and the difference pictures of `rayproc diff`: known values of every metric, the
// crop, the errors thrown for bad input, and the heatmap's per-pixel errors, range, size,
// colours and labels.
#include "image/heatmap.h"
#include "image/metrics.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace rayproc;

namespace {

Image constantImage(int w, int h, float v) {
    Image img(w, h);
    for (float& p : img.pixels) p = v;
    return img;
}

// A gradient, so no two pixels are alike.
Image gradientImage(int w, int h) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y)[c] = 0.1f * float(x + 2 * y + c) + 0.05f;
    return img;
}

} // namespace

TEST_CASE("Identical images: every error is zero and PSNR is infinite", "[image]") {
    Image a = gradientImage(7, 5);
    ImageMetrics m = compareImages(a, a);
    CHECK(m.rmse == 0);
    CHECK(m.relmse == 0);
    CHECK(m.mae == 0);
    CHECK(m.maxAbs == 0);
    CHECK(m.pixels == 35);
    CHECK(std::isinf(m.psnr));
    CHECK(m.psnr > 0);
}

TEST_CASE("A NaN in the test image makes every error NaN, PSNR included (not inf)", "[image]") {
    Image b = gradientImage(7, 5);
    Image a = b;
    a.at(3, 2)[1] = std::numeric_limits<float>::quiet_NaN();
    ImageMetrics m = compareImages(a, b);
    CHECK(std::isnan(m.rmse));
    CHECK(std::isnan(m.relmse));
    CHECK(std::isnan(m.psnr)); // was +inf: NaN > 0 is false, so it read as "equal images"
    CHECK(std::isnan(m.maxAbs)); // was the largest finite difference, 0 here
    CHECK(std::isnan(m.meanRel));
    // In whichever channel the NaN is: a later channel's finite error must not replace it.
    for (int c = 0; c < 3; ++c) {
        Image one = b;
        one.at(1, 1)[c] = std::numeric_limits<float>::quiet_NaN();
        INFO("NaN in channel " << c);
        CHECK(std::isnan(compareImages(one, b).meanRel)); // red and green read 0 before
    }
    // A NaN in the reference is left out, as documented: the rest compares as equal.
    ImageMetrics r = compareImages(b, a);
    CHECK(r.rmse == 0);
    CHECK(r.referenceNonFinite == 1);
    CHECK(std::isinf(r.psnr));
}

TEST_CASE("A constant offset d on a constant image b gives the closed forms", "[image]") {
    const double b = 0.5, d = 0.125; // exact in float
    Image ref = constantImage(8, 6, float(b));
    Image test = constantImage(8, 6, float(b + d));
    ImageMetrics m = compareImages(test, ref);
    CHECK(m.rmse == Approx(d).epsilon(1e-12));
    CHECK(m.relmse == Approx(d * d / (b * b + 0.01)).epsilon(1e-12));
    CHECK(m.mae == Approx(d).epsilon(1e-12));
    CHECK(m.maxAbs == Approx(d).epsilon(1e-12));
    CHECK(m.psnr == Approx(10.0 * std::log10(1.0 / (d * d))).epsilon(1e-12));
    CHECK(m.pixels == 48);

    // A negative offset gives the same figures: the metrics are symmetric in the sign of a - b.
    ImageMetrics n = compareImages(constantImage(8, 6, float(b - d)), ref);
    CHECK(n.rmse == Approx(m.rmse));
    CHECK(n.relmse == Approx(m.relmse));
}

TEST_CASE("relMSE divides by the reference, not by the test image", "[image]") {
    Image ref = constantImage(2, 2, 0.0f);
    Image test = constantImage(2, 2, 0.1f);
    // (0.1)^2 / (0 + 0.01) = 1; swapped: (0.1)^2 / (0.01 + 0.01) = 0.5.
    CHECK(compareImages(test, ref).relmse == Approx(1.0).epsilon(1e-6));
    CHECK(compareImages(ref, test).relmse == Approx(0.5).epsilon(1e-6));
}

TEST_CASE("A relMSE denominator image replaces the reference in relMSE only", "[image]") {
    // Test 0.3 against a "converged" 0.2: (0.1)^2 / (b^2 + 0.01) with b from the denominator.
    Image test = constantImage(3, 2, 0.3f);
    Image converged = constantImage(3, 2, 0.2f);
    Image full = constantImage(3, 2, 0.4f);
    ImageMetrics plain = compareImages(test, converged);
    ImageMetrics m = compareImages(test, converged, std::nullopt, &full);
    CHECK(plain.relmse == Approx(0.01 / (0.04 + 0.01)).epsilon(1e-6));
    CHECK(m.relmse == Approx(0.01 / (0.16 + 0.01)).epsilon(1e-6));
    CHECK(m.rmse == plain.rmse);
    CHECK(m.mae == plain.mae);
    CHECK(m.meanRel == plain.meanRel);
    CHECK(m.blockRel == plain.blockRel);
    // Per pixel: a brighter denominator in one pixel lowers only that pixel's term.
    full.at(0, 0)[0] = 1.0f;
    ImageMetrics one = compareImages(test, converged, std::nullopt, &full);
    CHECK(one.relmse == Approx((17 * 0.01 / 0.17 + 0.01 / 1.01) / 18.0).epsilon(1e-6));
    Image square = constantImage(3, 3, 0.4f);
    CHECK_THROWS_WITH(compareImages(test, converged, std::nullopt, &square),
                      Catch::Contains("3x2") && Catch::Contains("3x3"));
}

TEST_CASE("A crop restricts the comparison to its pixels", "[image]") {
    Image ref = constantImage(10, 8, 0.25f);
    Image test = ref;
    // One bad pixel outside the crop [2, 6) x [1, 5), a smaller one inside.
    for (int c = 0; c < 3; ++c) {
        test.at(8, 7)[c] = 10.0f;
        test.at(3, 2)[c] = 0.5f;
    }
    ImageMetrics m = compareImages(test, ref, CropRect{2, 1, 6, 5});
    CHECK(m.pixels == 16);
    CHECK(m.maxAbs == Approx(0.25));
    CHECK(m.mae == Approx(0.25 / 16));
    CHECK(m.rmse == Approx(std::sqrt(0.25 * 0.25 / 16)));

    ImageMetrics whole = compareImages(test, ref);
    CHECK(whole.maxAbs == Approx(9.75));
    CHECK(whole.pixels == 80);

    // The crop may be the whole image.
    ImageMetrics full = compareImages(test, ref, CropRect{0, 0, 10, 8});
    CHECK(full.rmse == whole.rmse);
}

TEST_CASE("Different sizes and bad crops throw ImageIoError", "[image]") {
    Image a = constantImage(4, 4, 0.5f);
    CHECK_THROWS_AS(compareImages(a, constantImage(4, 5, 0.5f)), ImageIoError);
    CHECK_THROWS_AS(compareImages(a, constantImage(5, 4, 0.5f)), ImageIoError);
    CHECK_THROWS_WITH(compareImages(a, constantImage(3, 4, 0.5f)),
                      Catch::Contains("4x4") && Catch::Contains("3x4"));
    for (CropRect bad : {CropRect{0, 0, 5, 4}, CropRect{-1, 0, 2, 2}, CropRect{2, 2, 2, 3},
                         CropRect{3, 1, 1, 3}, CropRect{0, 0, 4, 0}}) {
        INFO("crop " << bad.x0 << " " << bad.y0 << " " << bad.x1 << " " << bad.y1);
        CHECK_THROWS_AS(compareImages(a, a, bad), ImageIoError);
    }
}

TEST_CASE("Heatmap per-pixel errors average to the printed metrics", "[image]") {
    Image ref = gradientImage(9, 4);
    Image test = ref;
    for (std::size_t i = 0; i < test.pixels.size(); ++i) test.pixels[i] += 0.01f * float(i % 7);
    ImageMetrics m = compareImages(test, ref);
    for (HeatmapMetric metric : {HeatmapMetric::RelMse, HeatmapMetric::Abs}) {
        std::vector<double> e = pixelErrors(test, ref, metric);
        REQUIRE(e.size() == 36);
        double mean = 0;
        for (double v : e) mean += v / double(e.size());
        CHECK(mean == Approx(metric == HeatmapMetric::RelMse ? m.relmse : m.mae).epsilon(1e-9));
    }
    // With a relMSE denominator image, the relmse heatmap follows it; abs does not change.
    Image den = constantImage(9, 4, 0.7f);
    ImageMetrics md = compareImages(test, ref, std::nullopt, &den);
    REQUIRE(md.relmse != Approx(m.relmse));
    std::vector<double> e = pixelErrors(test, ref, HeatmapMetric::RelMse, &den);
    double mean = 0;
    for (double v : e) mean += v / double(e.size());
    CHECK(mean == Approx(md.relmse).epsilon(1e-9));
    CHECK(pixelErrors(test, ref, HeatmapMetric::Abs, &den) ==
          pixelErrors(test, ref, HeatmapMetric::Abs));
}

TEST_CASE("Heatmap automatic ranges", "[image]") {
    HeatmapSettings log;
    // Errors 0.003 .. 0.4 widen to whole decades: [0.001, 1].
    std::vector<double> e{0.0, 0.003, 0.05, 0.4};
    HeatmapRange r = heatmapRange(e, 2, 2, log);
    CHECK(r.lo == Approx(0.001));
    CHECK(r.hi == Approx(1.0));
    // At most four decades below the largest error.
    HeatmapRange wide = heatmapRange({1e-12, 2.0, 0.0, 0.0}, 2, 2, log);
    CHECK(wide.hi == Approx(10.0));
    CHECK(wide.lo == Approx(1e-4));
    // A single error value: one decade ending at it.
    HeatmapRange one = heatmapRange({0.01, 0.01, 0.01, 0.01}, 2, 2, log);
    CHECK(one.hi == Approx(0.01));
    CHECK(one.lo == Approx(0.001));
    // No error at all: still a valid range.
    HeatmapRange none = heatmapRange({0, 0, 0, 0}, 2, 2, log);
    CHECK(none.lo > 0);
    CHECK(none.lo < none.hi);

    HeatmapSettings linear;
    linear.scale = HeatmapScale::Linear;
    HeatmapRange lin = heatmapRange(e, 2, 2, linear);
    CHECK(lin.lo == 0);
    CHECK(lin.hi == Approx(0.5));

    // Inside a crop only: the large error at pixel (1, 1) is outside [0, 1) x [0, 2).
    HeatmapSettings cropped;
    cropped.crop = CropRect{0, 0, 1, 2};
    HeatmapRange c = heatmapRange({0.02, 0.0, 0.003, 50.0}, 2, 2, cropped);
    CHECK(c.hi == Approx(0.1));

    // A fixed range is taken as given.
    HeatmapSettings fixed;
    fixed.lo = 0.002;
    fixed.hi = 0.3;
    HeatmapRange f = heatmapRange(e, 2, 2, fixed);
    CHECK(f.lo == 0.002);
    CHECK(f.hi == 0.3);
}

TEST_CASE("Heatmap picture: size, legend, colours, crop outline", "[image]") {
    Image ref = constantImage(40, 30, 0.5f);
    Image test = ref;
    test.at(5, 5)[0] = 2.0f;                                    // large error
    test.at(6, 5)[1] = std::numeric_limits<float>::quiet_NaN(); // non-finite: cyan
    HeatmapSettings s;
    s.lo = 1e-3; // error 2.88 at (5, 5) lies above: the top colour
    s.hi = 1.0;
    HeatmapSize size = heatmapSize(40, 30, s);
    CHECK(size.width > 40);
    CHECK(size.height == 96); // the legend's minimum height
    Image h = renderHeatmap(test, ref, s);
    CHECK(h.width == size.width);
    CHECK(h.height == size.height);
    // No error is black, the largest error is the top (pale yellow) colour.
    CHECK(h.at(0, 0)[0] < 0.001f);
    CHECK(h.at(5, 5)[0] > 0.9f);
    CHECK(h.at(5, 5)[1] > 0.9f);
    CHECK(h.at(6, 5)[0] == 0.0f);
    CHECK(h.at(6, 5)[1] == 1.0f);
    CHECK(h.at(6, 5)[2] == 1.0f);
    // The legend panel holds some light (labels, ticks, frame) pixels.
    int light = 0;
    for (int y = 0; y < h.height; ++y)
        for (int x = 40; x < h.width; ++x) light += h.at(x, y)[0] > 0.7f && h.at(x, y)[2] > 0.7f;
    CHECK(light > 50);

    s.legend = false;
    s.crop = CropRect{10, 10, 20, 20};
    Image bare = renderHeatmap(test, ref, s);
    CHECK(bare.width == 40);
    CHECK(bare.height == 30);
    CHECK(bare.at(9, 9)[1] == 1.0f); // the outline just outside the crop
    CHECK(bare.at(9, 9)[0] == 0.0f);
    CHECK(bare.at(10, 10)[1] < 0.001f);

    // Large images keep their own height; the legend only adds width.
    HeatmapSize big = heatmapSize(1000, 700, HeatmapSettings{});
    CHECK(big.height == 700);
    CHECK(big.width > 1000);

    CHECK_THROWS_AS(renderHeatmap(test, constantImage(4, 4, 0.5f), HeatmapSettings{}),
                    ImageIoError);
}

TEST_CASE("Difference image is |a - b| times the scale", "[image]") {
    Image ref = gradientImage(5, 3);
    Image test = ref;
    test.at(2, 1)[0] -= 0.25f;
    test.at(4, 2)[2] += 0.5f;
    Image d = differenceImage(test, ref, 2.0f);
    REQUIRE(d.width == 5);
    REQUIRE(d.height == 3);
    CHECK(d.at(2, 1)[0] == Approx(0.5));
    CHECK(d.at(4, 2)[2] == Approx(1.0));
    CHECK(d.at(0, 0)[0] == 0.0f);
    CHECK_THROWS_AS(differenceImage(test, constantImage(5, 4, 0.0f)), ImageIoError);
}

TEST_CASE("Difference image clamps values beyond float's range and counts them", "[image]") {
    Image ref = constantImage(3, 1, 0.0f);
    Image test = ref;
    test.at(0, 0)[0] = 4.0f;  // 4 * 3e38 overflows float
    test.at(1, 0)[1] = 0.5f;  // 1.5e38 fits
    std::size_t clamped = 99;
    Image d = differenceImage(test, ref, 3e38f, &clamped);
    CHECK(clamped == 1);
    CHECK(d.at(0, 0)[0] == std::numeric_limits<float>::max());
    CHECK(d.at(1, 0)[1] == Approx(1.5e38));
    for (float v : d.pixels) CHECK(std::isfinite(v)); // 0 * scale stays 0, never NaN
}

TEST_CASE("Heatmap tick labels use only the built-in glyphs", "[image]") {
    CHECK(heatmapTickLabel(0) == "0");
    CHECK(heatmapTickLabel(1) == "1");
    CHECK(heatmapTickLabel(0.01) == "0.01");
    CHECK(heatmapTickLabel(0.001) == "0.001");
    CHECK(heatmapTickLabel(1000) == "1000");
    CHECK(heatmapTickLabel(0.25) == "0.25");
    CHECK(heatmapTickLabel(1e-5) == "1e-5");
    CHECK(heatmapTickLabel(2.5e4) == "2.5e+4");
    CHECK(heatmapTickLabel(1e-12) == "1e-12");
    for (double v : {0.00123, 123.456, 7.5e-9, 3e7, 0.375, 1.25}) {
        std::string label = heatmapTickLabel(v);
        INFO(v << " -> " << label);
        CHECK(label.size() <= 7);
        CHECK(label.find_first_not_of("0123456789.e-+") == std::string::npos);
    }
}

// The public-scene suite's measures (docs/public-scenes.md), checked against values computed by
// hand.
namespace {

Image rgbImage(int w, int h, float r, float g, float b) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            img.at(x, y)[0] = r;
            img.at(x, y)[1] = g;
            img.at(x, y)[2] = b;
        }
    return img;
}

// Left columns [0, split) take value v, the rest w, on every channel.
Image splitImage(int w, int h, int split, float v, float wv) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y)[c] = x < split ? v : wv;
    return img;
}

} // namespace

TEST_CASE("Mean error is the worst channel's relative error of the image mean", "[image]") {
    Image ref = rgbImage(4, 4, 1.0f, 2.0f, 4.0f);
    // R exact, G +5%, B -5%: the worst channel is 0.05.
    ImageMetrics m = compareImages(rgbImage(4, 4, 1.0f, 2.1f, 3.8f), ref);
    CHECK(m.meanRel == Approx(0.05).epsilon(1e-5));
    // Per channel, signed: R 0, G +5%, B -5%.
    CHECK(m.meanRelRgb[0] == Approx(0.0).margin(1e-7));
    CHECK(m.meanRelRgb[1] == Approx(0.05).epsilon(1e-5));
    CHECK(m.meanRelRgb[2] == Approx(-0.05).epsilon(1e-5));
    // Per-pixel errors of opposite sign cancel in the mean: +10% and -10% halves give 0.
    Image test = splitImage(4, 4, 2, 1.1f, 0.9f);
    CHECK(compareImages(test, constantImage(4, 4, 1.0f)).meanRel == Approx(0.0).margin(1e-6));
}

TEST_CASE("Block error averages the blocks' relative errors, partial blocks included", "[image]") {
    // 64x32: two full blocks at +20% and -10%: (0.2 + 0.1) / 2; image mean +5%.
    ImageMetrics m = compareImages(splitImage(64, 32, 32, 1.2f, 0.9f), constantImage(64, 32, 1));
    CHECK(m.blocks == 2);
    CHECK(m.blocksSkipped == 0);
    CHECK(m.blockRel == Approx(0.15).epsilon(1e-5));
    CHECK(m.meanRel == Approx(0.05).epsilon(1e-4));
    // 40x32: a full block (+20%) and an 8-pixel-wide edge block (-10%) count the same;
    // the image mean is (32 * 1.2 + 8 * 0.9) / 40 = 1.14.
    m = compareImages(splitImage(40, 32, 32, 1.2f, 0.9f), constantImage(40, 32, 1));
    CHECK(m.blocks == 2);
    CHECK(m.blockRel == Approx(0.15).epsilon(1e-5));
    CHECK(m.meanRel == Approx(0.14).epsilon(1e-4));
}

TEST_CASE("Block error skips near-black reference blocks", "[image]") {
    // Reference mean (1 + 1e-4) / 2; the right block's 1e-4 is below 1e-3 of it: skipped, even
    // though the test is 100% off there.
    Image ref = splitImage(64, 32, 32, 1.0f, 1e-4f);
    Image test = splitImage(64, 32, 32, 1.1f, 2e-4f);
    ImageMetrics m = compareImages(test, ref);
    CHECK(m.blocks == 1);
    CHECK(m.blocksSkipped == 1);
    CHECK(m.blockRel == Approx(0.1).epsilon(1e-5));
}

TEST_CASE("Non-finite reference pixels are left out of every metric", "[image]") {
    Image ref = constantImage(4, 4, 1.0f);
    Image test = constantImage(4, 4, 1.5f);
    ref.at(1, 2)[1] = std::numeric_limits<float>::quiet_NaN();
    ref.at(3, 0)[0] = std::numeric_limits<float>::infinity();
    test.at(1, 2)[0] = 100.0f; // would dominate every metric if counted
    ImageMetrics m = compareImages(test, ref);
    CHECK(m.pixels == 14);
    CHECK(m.referenceNonFinite == 2);
    CHECK(m.rmse == Approx(0.5));
    CHECK(m.maxAbs == Approx(0.5));
    CHECK(m.relmse == Approx(0.25 / 1.01));
    CHECK(m.meanRel == Approx(0.5));
    CHECK(m.blockRel == Approx(0.5));
}

TEST_CASE("Box downsampling averages finite pixels - the factor must divide both sizes", "[image]") {
    Image img(4, 2);
    for (int x = 0; x < 4; ++x)
        for (int y = 0; y < 2; ++y)
            for (int c = 0; c < 3; ++c) img.at(x, y)[c] = float(x + 4 * y);
    img.at(3, 1)[2] = std::numeric_limits<float>::quiet_NaN();
    Image d = boxDownsample(img, 2);
    REQUIRE(d.width == 2);
    REQUIRE(d.height == 1);
    CHECK(d.at(0, 0)[0] == Approx((0 + 1 + 4 + 5) / 4.0));
    CHECK(d.at(1, 0)[0] == Approx((2 + 3 + 6) / 3.0)); // pixel (3, 1) left out on every channel
    CHECK(boxDownsample(gradientImage(4, 2), 1).pixels == gradientImage(4, 2).pixels);
    CHECK_THROWS_AS(boxDownsample(img, 3), ImageIoError);

    Image all = constantImage(2, 2, std::numeric_limits<float>::quiet_NaN());
    CHECK(std::isnan(boxDownsample(all, 2).at(0, 0)[0]));

    CHECK(downsampleFactor(Image(4, 3), Image(16, 12)) == 4);
    CHECK(downsampleFactor(Image(4, 3), Image(4, 3)) == 1);
    CHECK(downsampleFactor(Image(4, 3), Image(16, 9)) == 0); // different factors per axis
    CHECK(downsampleFactor(Image(4, 3), Image(10, 6)) == 0);
}

TEST_CASE("A reference's non-finite pixels are counted, and none finite is an error", "[image]") {
    Image img(4, 2);
    CHECK(nonFiniteReferencePixels(img, "x.pfm") == 0);
    img.pixels[3 * 3 + 2] = std::numeric_limits<float>::infinity();
    img.pixels[5 * 3] = std::nanf("");
    CHECK(nonFiniteReferencePixels(img, "x.pfm") == 2);
    for (float& v : img.pixels) v = std::nanf("");
    CHECK_THROWS_WITH(nonFiniteReferencePixels(img, "x.pfm"),
                      Catch::Contains("x.pfm") && Catch::Contains("no pixel"));
}
