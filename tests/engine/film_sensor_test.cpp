// engine/film_sensor.h: pbrt-v4's "rgb" film with the "cie1931" sensor. The imaging ratio
// exposure x iso / 100 scales the image, white balance adapts the daylight white of its
// temperature to the colour space's white; the film's images in RGB and spectral mode, through
// the render job (the result, the progressive and watched images and the noise layers alike),
// and the pbrt importer's Film and Camera parameters.
#include "../analytic/analytic.h"
#include "engine/film_sensor.h"
#include "engine/noise_breakdown.h"
#include "pbrt/pbrt_test_util.h"
#include "scene/pbrt/pbrt_spectrum.h"
#include "spectral/color_space.h"
#include "spectral/spectra.h"
#include "spectral/white_balance.h"

#include <map>

using namespace rayproc;
using namespace rayproc::test;

namespace {

const spectral::ColorSpace& srgb() { return spectral::colorSpace(spectral::ColorSpaceId::Srgb); }

Vec3 applied(const SensorMatrix& s, const Vec3& rgb) {
    Image img(1, 1);
    for (int c = 0; c < 3; ++c) img.pixels[std::size_t(c)] = rgb[c];
    applySensor(s, img);
    return {img.pixels[0], img.pixels[1], img.pixels[2]};
}

// The linear sRGB of a grey reflectance 0.5 lit by `light` (at luminance 1), as the film holds it.
Vec3 greyUnder(const spectral::DenseSpectrum& light) {
    spectral::Xyz c = spectral::toXyz(light);
    const double k = 0.5 / c.y;
    spectral::ColorSpace::Rgb rgb = srgb().fromXyz({k * c.x, k * c.y, k * c.z});
    return {float(rgb.r), float(rgb.g), float(rgb.b)};
}

// The daylight of a white balance temperature as pbrt-v4 defines it (Spectra::D): the CIE
// D-series illuminant at the daylight locus's chromaticity for the corrected temperature (CIE
// 15:2004, eq. 3.3 and 3.2), a blackbody below 4000 K.
spectral::DenseSpectrum daylightAt(double kelvin) {
    const double t = kelvin * 1.4388 / 1.4380;
    if (t < 4000)
        return spectral::DenseSpectrum::sample(
            [t](double nm) { return kernels::spectral::planck(nm, t); });
    const double x = t <= 7000 ? -4.6070e9 / (t * t * t) + 2.9678e6 / (t * t) + 99.11 / t + 0.244063
                               : -2.0064e9 / (t * t * t) + 1.9018e6 / (t * t) + 247.48 / t + 0.237040;
    return spectral::daylightIlluminant(x, -3.0 * x * x + 2.87 * x - 0.275);
}

double spread(const Vec3& c) { return (maxComponent(c) - std::min({c.x, c.y, c.z})) / c.y; }

Image renderPbrt(const std::string& text, bool spectral) {
    LoadedPbrt r = loadPbrt(text);
    REQUIRE(r.warnings.empty());
    EmbreeScene accel(*r.scene);
    return renderPath(*r.scene, accel, pathSettings(r.scene->render, ModeOverrides{32, 0, 0}),
                      quietTwoThreads(spectral))
        .image;
}

// A grey square lit head-on by a distant light, seen by a camera whose Film line is `film`.
std::string greyScene(const std::string& film, const std::string& light, const std::string& camera = "") {
    return "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 20 " + camera +
           "\nFilm \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16 " + film +
           "\nWorldBegin\nLightSource \"distant\" " + light +
           " \"point3 from\" [0 0 1] \"point3 to\" [0 0 0]\n"
           "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n"
           "Shape \"bilinearmesh\" \"point3 P\" [-5 -5 0 5 -5 0 -5 5 0 5 5 0]\n";
}

// Every image one render hands out besides its result: the progressive images (one per pass
// but the last), the watcher's image at the end, the noise layers by name.
struct Outputs {
    RenderResult result;
    std::vector<Image> progressive;
    Image watched;
    std::map<std::string, std::vector<float>> layers;
};

Outputs renderOutputs(const std::string& text) {
    LoadedPbrt r = loadPbrt(text);
    REQUIRE(r.warnings.empty());
    EmbreeScene accel(*r.scene);
    Outputs out;
    EngineSettings engine = quietTwoThreads();
    RenderControl control;
    control.noiseBreakdown = true;
    control.progressiveSeconds = 0; // after every pass
    control.onProgress = [&](const Image& img) { out.progressive.push_back(img); };
    std::function<Image()> soFar;
    RenderControl::Watcher watcher;
    watcher.begin = [&](std::function<Image()> image, std::function<double()>,
                        std::function<std::uint64_t()>) { soFar = std::move(image); };
    watcher.end = [&] { out.watched = soFar(); };
    control.watcher = &watcher;
    out.result = renderPath(*r.scene, accel, pathSettings(r.scene->render, ModeOverrides{4, 0, 0}),
                            engine, control);
    for (const ImageLayer& l : out.result.layers) out.layers[l.name] = l.values;
    return out;
}

} // namespace

TEST_CASE("Film sensor: the imaging ratio is exposure x iso / 100", "[engine][spectral]") {
    CHECK(sensorMatrix(FilmSensor{}, srgb()).identity);
    FilmSensor iso200;
    iso200.iso = 200;
    Vec3 twice = applied(sensorMatrix(iso200, srgb()), Vec3(0.3f, 1.7f, 0.0f));
    CHECK(twice.x == 0.6f);
    CHECK(twice.y == 3.4f);
    CHECK(twice.z == 0.0f);
    FilmSensor shutter;
    shutter.iso = 400;
    shutter.exposureTime = 0.125;
    Vec3 half = applied(sensorMatrix(shutter, srgb()), Vec3(0.3f, 1.7f, 0.25f));
    CHECK(half.x == 0.15f);
    CHECK(half.z == 0.125f);
}

TEST_CASE("Film sensor: white balance at the colour space's own white is about the identity",
          "[engine][spectral]") {
    FilmSensor d65;
    d65.whiteBalance = 6504;
    SensorMatrix s = sensorMatrix(d65, srgb());
    double largest = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            largest = std::max(largest, std::abs(double(s.m[i][j]) - (i == j ? 1.0 : 0.0)));
    INFO("largest departure from the identity " << largest);
    CHECK(largest < 1e-3);
    FilmSensor warm;
    warm.whiteBalance = 3000;
    CHECK(std::abs(sensorMatrix(warm, srgb()).m[2][2] - 1) > 0.5); // blue lifted a lot
}

TEST_CASE("Film sensor: white balance at T takes a grey lit by daylight at T to neutral",
          "[engine][spectral]") {
    for (double kelvin : {2700.0, 3500.0, 5000.0, 8000.0, 12000.0}) {
        const Vec3 lit = greyUnder(daylightAt(kelvin));
        FilmSensor wb;
        wb.whiteBalance = kelvin;
        const Vec3 balanced = applied(sensorMatrix(wb, srgb()), lit);
        INFO(kelvin << " K: film " << lit.x << " " << lit.y << " " << lit.z << ", balanced "
                    << balanced.x << " " << balanced.y << " " << balanced.z);
        CHECK(spread(lit) > 0.05); // the light's colour shows without white balance
        CHECK(spread(balanced) < 1e-5);
        // The Bradford transform keeps Y of the white: the grey stays 0.5 x the light's Y.
        CHECK(balanced.y == Approx(0.5).epsilon(1e-4));
    }
}

TEST_CASE("pbrt Film iso, whitebalance and sensor, and the camera's shutter", "[pbrt][spectral]") {
    LoadedPbrt r = loadPbrt(greyScene("\"float iso\" 400 \"float whitebalance\" 5000",
                                      "\"rgb L\" [1 1 1]",
                                      "\"float shutteropen\" 0.25 \"float shutterclose\" 0.75"));
    CHECK(r.warnings.empty());
    CHECK(r.scene->sensor.iso == 400);
    CHECK(r.scene->sensor.whiteBalance == 5000);
    CHECK(r.scene->sensor.exposureTime == 0.5);
    LoadedPbrt plain = loadPbrt(greyScene("", "\"rgb L\" [1 1 1]"));
    CHECK(plain.scene->sensor.passthrough());
    // Another sensor: no curves here; rendered as cie1931, white balanced at pbrt-v4's 6500 K.
    LoadedPbrt canon = loadPbrt(greyScene("\"string sensor\" \"canon_eos_100d\"", "\"rgb L\" [1 1 1]"));
    CHECK(canon.warned("film sensor \"canon_eos_100d\""));
    CHECK(canon.scene->sensor.whiteBalance == 6500);
    // Errors name the file and line.
    CHECK_THAT(pbrtErrorOf(greyScene("", "\"rgb L\" [1 1 1]", "\"float shutterclose\" 0")),
               Catch::Contains("bad.pbrt:2") && Catch::Contains("shutter does not open"));
    CHECK_THAT(pbrtErrorOf(greyScene("\"float iso\" -5", "\"rgb L\" [1 1 1]")),
               Catch::Contains("bad.pbrt:3") && Catch::Contains("iso"));
}

TEST_CASE("Film sensor in renders: iso 200 doubles the image, RGB and spectral",
          "[engine][spectral]") {
    for (bool spectral : {false, true}) {
        Image base = renderPbrt(greyScene("", "\"blackbody L\" 3000"), spectral);
        Image iso = renderPbrt(greyScene("\"float iso\" 200", "\"blackbody L\" 3000"), spectral);
        REQUIRE(base.pixels.size() == iso.pixels.size());
        bool doubled = true;
        for (std::size_t i = 0; i < base.pixels.size(); ++i)
            doubled = doubled && iso.pixels[i] == 2 * base.pixels[i];
        INFO((spectral ? "spectral" : "RGB"));
        CHECK(meanValue(base) > 0.05);
        CHECK(doubled);
    }
}

TEST_CASE("Film sensor in renders: white balance at the light's temperature gives neutral grey",
          "[engine][spectral]") {
    // Below 4000 K pbrt-v4's daylight is a blackbody at T x 1.4388 / 1.4380: a grey lit by that
    // blackbody renders neutral with "whitebalance" T, in RGB mode (the light's colour) and
    // spectrally (Planck's law itself, through the matching functions).
    const double kelvin = 3000, light = kelvin * 1.4388 / 1.4380;
    const std::string bb = "\"blackbody L\" " + std::to_string(light);
    for (bool spectral : {false, true}) {
        Image raw = renderPbrt(greyScene("", bb), spectral);
        Image wb = renderPbrt(greyScene("\"float whitebalance\" 3000", bb), spectral);
        PixelStats a[3], b[3];
        for (int c = 0; c < 3; ++c) {
            a[c] = pixelStats(raw, c);
            b[c] = pixelStats(wb, c);
        }
        INFO((spectral ? "spectral" : "RGB") << ": without " << a[0].mean << " " << a[1].mean
                                             << " " << a[2].mean << ", balanced " << b[0].mean
                                             << " +- " << b[0].stdError << ", " << b[1].mean
                                             << " +- " << b[1].stdError << ", " << b[2].mean
                                             << " +- " << b[2].stdError);
        CHECK(a[0].mean > 2 * a[1].mean); // orange without white balance
        CHECK(a[1].mean > 2 * a[2].mean);
        // Neutral: every channel the grey's Y, 0.5 / pi (Bradford keeps the white's Y), within
        // 4 standard errors and 1e-3 (RGB mode's luminance weights against the matrix's Y row).
        for (int c = 0; c < 3; ++c)
            CHECK(std::abs(b[c].mean - 0.5 / kPi) <= 4 * b[c].stdError + 1e-3 * 0.5 / kPi);
    }
}

TEST_CASE("Film sensor: iso 200 doubles every image a render hands out, noise layers included",
          "[engine][spectral]") {
    const std::string light = "\"blackbody L\" 3000";
    Outputs base = renderOutputs(greyScene("", light));
    Outputs iso = renderOutputs(greyScene("\"float iso\" 200", light));
    REQUIRE(meanValue(base.result.image) > 0.05);
    // The progressive images (passes of 1 spp with the noise breakdown: three before the last)
    // and the watcher's: the film's RGB times 2, exactly, as the result.
    REQUIRE(base.progressive.size() == 3);
    REQUIRE(iso.progressive.size() == base.progressive.size());
    auto doubled = [](const Image& a, const Image& b) {
        bool same = a.pixels.size() == b.pixels.size();
        for (std::size_t i = 0; same && i < a.pixels.size(); ++i) same = b.pixels[i] == 2 * a.pixels[i];
        return same;
    };
    CHECK(doubled(base.result.image, iso.result.image));
    for (std::size_t k = 0; k < base.progressive.size(); ++k) {
        INFO("progressive image " << k);
        CHECK(doubled(base.progressive[k], iso.progressive[k]));
    }
    CHECK(sameBits(base.watched, base.result.image)); // after the last pass: the result
    CHECK(sameBits(iso.watched, iso.result.image));
    // The noise layers: each group's mean luminance doubles; its noise, a variance over
    // (F^2 + 0.01), F the pixel's mean luminance, becomes 4 var / (4 F^2 + 0.01).
    REQUIRE(base.layers.size() == 2 * NoiseBreakdown::kGroups + 1);
    double worstMean = 0, worstNoise = 0, largestMean = 0;
    for (int g = 0; g <= NoiseBreakdown::kGroups; ++g) {
        const std::string name = NoiseBreakdown::name(NoiseBreakdown::Group(g));
        const std::vector<float>& noiseA = base.layers.at("noise." + name);
        const std::vector<float>& noiseB = iso.layers.at("noise." + name);
        for (std::size_t p = 0; p < noiseA.size(); ++p) {
            const float* px = &base.result.image.pixels[3 * p];
            const double f = luminance(Vec3(px[0], px[1], px[2]));
            const double variance = noiseA[p] * (f * f + 0.01);
            const double expected = 4 * variance / (4 * f * f + 0.01);
            worstNoise = std::max(worstNoise, std::abs(noiseB[p] - expected) / (expected + 1e-6));
            if (g == NoiseBreakdown::kGroups) continue; // no mean.total
            const float a = base.layers.at("mean." + name)[p], b = iso.layers.at("mean." + name)[p];
            largestMean = std::max(largestMean, double(a));
            worstMean = std::max(worstMean, std::abs(double(b) - 2.0 * a) / (2.0 * a + 1e-6));
        }
    }
    INFO("largest mean " << largestMean << ", worst mean " << worstMean << ", worst noise "
                         << worstNoise);
    CHECK(largestMean > 0.05);
    CHECK(worstMean < 1e-5);
    CHECK(worstNoise < 1e-3);
}

TEST_CASE("Film sensor: the noise layers' means add up to the luminance of the image handed out",
          "[engine][spectral]") {
    // White balance mixes the channels: the layers weigh each contribution's colour through
    // the sensor's matrix, so the groups' means still add up to the written pixel's luminance.
    Outputs out = renderOutputs(
        greyScene("\"float iso\" 300 \"float whitebalance\" 2500", "\"blackbody L\" 6500"));
    double worst = 0, largest = 0;
    const std::size_t pixels = out.result.image.pixels.size() / 3;
    for (std::size_t p = 0; p < pixels; ++p) {
        double sum = 0;
        for (int g = 0; g < NoiseBreakdown::kGroups; ++g)
            sum += out.layers.at(std::string("mean.") + NoiseBreakdown::name(NoiseBreakdown::Group(g)))[p];
        const float* px = &out.result.image.pixels[3 * p];
        const double lum = luminance(Vec3(px[0], px[1], px[2]));
        largest = std::max(largest, lum);
        worst = std::max(worst, std::abs(sum - lum) / (lum + 1e-3));
    }
    INFO("largest luminance " << largest << ", worst relative difference " << worst);
    CHECK(largest > 0.1);
    CHECK(worst < 1e-4);
}
