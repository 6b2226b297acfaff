// Dispersion of a coat in the spectral mode (docs/spectral.md, "Dispersion"): a coateddiffuse's
// `eta` or a coatedconductor's `interface.eta` that varies over wavelength is taken at the
// path's hero wavelength and ends the path's other wavelengths, as pbrt-v4's coated materials
// do (GetBxDF: eta(lambda[0]), then TerminateSecondary), so
// - bsdfAt gives the coat n(lambda_hero) and the coat reflects ((n - 1) / (n + 1))^2 at normal
//   incidence, and the coat is dispersive (its rays carry the terminated number);
// - a black-based coat lit by a narrow band reflects, head-on, the band's Fresnel
//   reflectance at the glass's n(lambda): more in blue than in red;
// - a coat over a white base in a furnace stays invisible (the hero carries the estimate);
// - RGB mode renders a glass-named coat at its n_d, bit-identical to the index as a float.
#include "engine/material_bsdf.h"
#include "kernels/pbrt_bsdfs.h"
#include "lighting/light_set.h"
#include "furnace_scene.h"
#include "scene/ior_spectrum.h"
#include "spectral/spectra.h"
#include "spectral_checks.h"

#include <cmath>
#include <cstdio>

using namespace rayproc;
using namespace rayproc::test;

namespace {

double fresnelNormal(double n) { return (n - 1) * (n - 1) / ((n + 1) * (n + 1)); }

// A camera looking down -z at a coated square (the plane z = 0, x < 0: the image's one half)
// inside a closed black sphere that emits `band` (a pbrt-v4 spectrum) on its inside: the other
// half sees the emitter itself. The coat reflects the emitter back to the camera.
std::string coatScene(const std::string& material, const std::string& band, int width,
                      int height, double fov) {
    char text[2048];
    std::snprintf(text, sizeof text,
                  "Scale -1 1 1  LookAt 0 0 10  0 0 0  0 1 0\n"
                  "Camera \"perspective\" \"float fov\" %g\n"
                  "Film \"rgb\" \"integer xresolution\" %d \"integer yresolution\" %d\n"
                  "WorldBegin\n"
                  "AttributeBegin\n"
                  "Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n"
                  "AreaLightSource \"diffuse\" %s \"bool twosided\" true\n"
                  "Shape \"sphere\" \"float radius\" 50\n"
                  "AttributeEnd\n"
                  "AttributeBegin\n"
                  "Material %s\n"
                  "Shape \"trianglemesh\" \"point3 P\" [-30 -30 0  0 -30 0  0 30 0  -30 30 0]\n"
                  "  \"integer indices\" [0 1 2  0 2 3]\n"
                  "AttributeEnd\n",
                  fov, width, height, band.c_str(), material.c_str());
    return text;
}

// A linear functional of the film's linear sRGB over the columns [x0, x1).
double columnsMean(const Image& img, int x0, int x1, const double w[3]) {
    double sum = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = x0; x < x1; ++x) {
            const float* p = img.at(x, y);
            sum += w[0] * p[0] + w[1] * p[1] + w[2] * p[2];
        }
    return sum / (double(img.height) * (x1 - x0));
}

// What the coat's half reflects of the emitter's half, in the matching function `cmf` (whose
// row of the sRGB -> XYZ matrix is `w`): the darker half over the brighter, a few columns
// either side of the coat's edge left out.
double measuredReflectance(const Image& img, const double w[3]) {
    const int half = img.width / 2, margin = 4;
    double left = columnsMean(img, 0, half - margin, w);
    double right = columnsMean(img, half + margin, img.width, w);
    return std::min(left, right) / std::max(left, right);
}

// The Fresnel reflectance at normal incidence averaged over the box band [lo, hi] nm weighted
// by `cmf`: what the coat reflects of the band head-on.
double expectedReflectance(const IorSpectrum& glass, const spectral::DenseSpectrum& cmf,
                           double lo, double hi) {
    double sum = 0, weighted = 0;
    for (double nm = lo; nm <= hi; nm += 0.25) {
        const double w = cmf.at(float(nm));
        sum += w;
        weighted += w * fresnelNormal(glass.at(float(nm)));
    }
    return weighted / sum;
}

} // namespace

TEST_CASE("Spectral mode: a dispersive coat's index is n(lambda) at the hero wavelength, and "
          "it ends the secondaries",
          "[spectral-mode][dispersion]") {
    IorSpectrumRef sf11 = namedGlassDispersion("glass-F11");
    REQUIRE(sf11);
    for (const char* material :
         {"\"coateddiffuse\" \"rgb reflectance\" [0 0 0] \"spectrum eta\" \"glass-F11\"",
          "\"coatedconductor\" \"spectrum interface.eta\" \"glass-F11\""}) {
        auto r = loadPbrt(std::string(kPbrtHeader) + "Material " + material +
                              "\nShape \"sphere\"\n",
                          "coat.pbrt");
        REQUIRE(r.warnings.empty());
        const Scene& scene = *r.scene;
        EmbreeScene accel(scene);
        LightSet lights = LightSet::build(scene, accel);
        SpectralRender render(scene, lights);
        SurfaceHit hit;
        hit.p = Vec3(0, 0, 1);
        hit.ng = hit.ns = Vec3(0, 0, 1);
        hit.dpdu = Vec3(1, 0, 0);
        hit.dpdv = Vec3(0, 1, 0);
        hit.material = rootShapes(scene)[0].shape->material;
        INFO(material);
        // RGB mode: n_d.
        CHECK(bsdfAt(scene, hit.material, hit, 0).ior == 1.7847f);
        double shortest = 1e9, longest = 0, fShortest = 0, fLongest = 0;
        for (float u : {0.02f, 0.2f, 0.45f, 0.7f, 0.98f}) {
            const LaneSpectrum lane = render.lane(u);
            const SpectralShading shading{render, lane};
            const float hero = lane.w.lambda[0];
            const kernels::BsdfParams b = bsdfAt(scene, hit.material, hit, 0, &shading);
            INFO("u " << u << ", hero " << hero << " nm");
            CHECK(b.ior == sf11->at(hero));
            CHECK(dispersive(scene, hit.material, &shading));
            const float marked = laneNumber(u, scene, hit.material, &shading);
            CHECK(std::signbit(marked));
            const LaneSpectrum ended = render.lane(marked);
            CHECK(ended.w.pdf[1] == 0);
            CHECK(ended.w.pdf[2] == 0);
            CHECK(ended.w.lambda[0] == hero);
            if (b.kind != kernels::BsdfKind::CoatedDiffuse) continue;
            // The smooth coat's mirror reflection head-on: ((n - 1) / (n + 1))^2 at n(hero).
            kernels::BsdfSample s =
                kernels::sampleCoatReflection(b, hit.ns, hit.ng, hit.ns, {0.5f, 0.5f});
            REQUIRE(s.valid);
            CHECK(s.weight.x == Approx(fresnelNormal(sf11->at(hero))).epsilon(1e-5));
            if (hero < shortest) shortest = hero, fShortest = s.weight.x;
            if (hero > longest) longest = hero, fLongest = s.weight.x;
        }
        if (shortest < longest) {
            INFO("F0 " << fShortest << " at " << shortest << " nm, " << fLongest << " at "
                       << longest << " nm");
            CHECK(fShortest > fLongest * 1.05);
        }
        // RGB mode's lanes are not marked.
        CHECK_FALSE(dispersive(scene, hit.material, nullptr));
    }
}

TEST_CASE("Spectral mode: a black-based coat reflects a narrow band head-on by its glass's "
          "n(lambda)",
          "[spectral-mode][dispersion]") {
    // Head-on (within 2.3 degrees of the normal) the smooth coat over a black base reflects
    // F0 = ((n - 1) / (n + 1))^2 of the emitter, at each wavelength's own n. SF11's F0 is about
    // 0.085 at 435 nm and 0.078 at 655 nm (n_d's 0.079): the blue band is measured in Z
    // (z-bar), the red in X.
    IorSpectrumRef sf11 = namedGlassDispersion("glass-F11");
    REQUIRE(sf11);
    const double rowX[3] = {0.4124564, 0.3575761, 0.1804375};
    const double rowZ[3] = {0.0193339, 0.1191920, 0.9503041};
    const std::string coat = "\"coateddiffuse\" \"rgb reflectance\" [0 0 0] "
                             "\"spectrum eta\" \"glass-F11\"";
    const std::string blueBand = "\"spectrum L\" [419 0 420 1 450 1 451 0]";
    const std::string redBand = "\"spectrum L\" [639 0 640 1 670 1 671 0]";
    const double blueExpected = expectedReflectance(*sf11, spectral::cieZ(), 420, 450);
    const double redExpected = expectedReflectance(*sf11, spectral::cieX(), 640, 670);
    const double blue = measuredReflectance(
        renderPbrtPath(coatScene(coat, blueBand, 96, 48, 2), 256, true), rowZ);
    const double red = measuredReflectance(
        renderPbrtPath(coatScene(coat, redBand, 96, 48, 2), 256, true), rowX);
    INFO("blue: " << blue << " (Fresnel " << blueExpected << "), red " << red << " (Fresnel "
                  << redExpected << "), n_d's " << fresnelNormal(1.7847));
    CHECK(blueExpected > redExpected * 1.07); // the split the check must see
    CHECK(blue == Approx(blueExpected).epsilon(0.006));
    CHECK(red == Approx(redExpected).epsilon(0.006));
}

TEST_CASE("Spectral mode: a dispersive coat over a white base in a furnace is invisible "
          "(unbiased termination)",
          "[spectral-mode][dispersion][heavy]") {
    // The furnace of spectral_dispersion_test.cpp (every ray carries 5) around a sphere whose
    // smooth SF11 coat lies over a white base with no absorption between them (the analytic
    // coat: lossless): a path that meets the coat keeps its hero alone, which must carry the
    // whole estimate.
    checkSpectralPathFurnace("\"coateddiffuse\" \"rgb reflectance\" [1 1 1] "
                             "\"spectrum eta\" \"glass-F11\" \"float thickness\" 1e-7",
                             "the coated sphere");
}

TEST_CASE("RGB mode renders a glass-named coat at its n_d, to the bit",
          "[spectral-mode][dispersion]") {
    const std::string band = "\"rgb L\" [1 1 1]";
    for (const auto& [named, flat] :
         {std::pair<std::string, std::string>{
              "\"coateddiffuse\" \"rgb reflectance\" [0.3 0.5 0.7] \"float roughness\" 0.1 "
              "\"spectrum eta\" \"glass-F11\"",
              "\"coateddiffuse\" \"rgb reflectance\" [0.3 0.5 0.7] \"float roughness\" 0.1 "
              "\"float eta\" 1.7847"},
          {"\"coatedconductor\" \"float interface.roughness\" 0.1 "
           "\"spectrum interface.eta\" \"glass-F11\"",
           "\"coatedconductor\" \"float interface.roughness\" 0.1 \"float interface.eta\" "
           "1.7847"}}) {
        INFO(named);
        Image a = renderPbrtPath(coatScene(named, band, 32, 16, 40), 4, false);
        Image b = renderPbrtPath(coatScene(flat, band, 32, 16, 40), 4, false);
        CHECK(sameBits(a, b));
    }
}

TEST_CASE("Spectral gi: a visible point on a dispersive coat reads the irradiance cache",
          "[spectral-mode][dispersion][gi]") {
    // Behind dispersive glass a visible point depends on the path's one wavelength and skips
    // the cache (spectral_dispersion_test.cpp); on a dispersive coat that the camera's path
    // reached with all its wavelengths it does not, though the coat leaves the path its hero
    // alone: the cache's light there is the path's, as on a coat of a constant index.
    auto render = [](const std::string& eta) {
        auto r = loadPbrt(furnaceAround("\"coateddiffuse\" \"rgb reflectance\" [1 1 1] " + eta),
                          "coat-furnace.pbrt");
        REQUIRE(r.warnings.empty());
        EmbreeScene accel(*r.scene);
        GiSettings s = giSettings(*r.scene, ModeOverrides{16, 0, 0});
        s.photons = 400000;
        s.photonRounds = 1;
        return renderGi(*r.scene, accel, s, seedOneEngine(true));
    };
    RenderResult dispersive = render("\"spectrum eta\" \"glass-F11\"");
    RenderResult flat = render("\"float eta\" 1.7847");
    // Every camera path meets the sphere first: one lookup a sample, nearly all of them hits.
    const double lookups = extraStat(dispersive, "gi/cache_lookups");
    CHECK(lookups >= 32 * 32 * 16);
    CHECK(extraStat(dispersive, "gi/cache_hit_rate") > 0.9);
    const Vec3 a = imageMean(dispersive.image), b = imageMean(flat.image);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": glass-F11 " << a[c] << ", constant index " << b[c]);
        CHECK(std::abs(a[c] / b[c] - 1) < 0.015);
    }
}
