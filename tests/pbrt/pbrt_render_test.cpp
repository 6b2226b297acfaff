// Rendered checks of the pbrt importer: images are not mirrored (pbrt's left-handed camera, with
// and without the exporters' "Scale -1 1 1"), scenes/cornell-box.pbrt renders the same image as
// scenes/cornell-box.json, and the command line prints warnings with file and line.
#include "pbrt_test_util.h"
#include "test_util.h"

#include "image/metrics.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

Image renderSmall(const Scene& scene) {
    EmbreeScene accel(scene);
    EngineSettings engine;
    engine.quiet = true;
    engine.threads = 2;
    engine.seed = 1;
    RaytraceSettings s;
    s.spp = 4;
    return renderRaytrace(scene, accel, s, engine).image;
}

// Red minus green summed over a rectangle of pixels.
double redness(const Image& img, int x0, int x1, int y0, int y1) {
    double sum = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) sum += img.at(x, y)[0] - img.at(x, y)[1];
    return sum;
}

// A red sphere one unit to the camera's right and a green one one unit above, in pbrt's camera
// conventions: camera space x is the image's right, y its up. `camera` sets up the view from
// `eye` towards the origin; `right` and `up` are the world directions pbrt's camera space x and
// y take under it. A point light sits at the eye.
void checkNotMirrored(const std::string& camera, const Vec3& eye, const Vec3& right,
                      const Vec3& up) {
    auto at = [](const Vec3& p) {
        return std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z);
    };
    std::string text = camera +
                       "\nCamera \"perspective\" \"float fov\" 50\n"
                       "Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32\n"
                       "WorldBegin\n"
                       "LightSource \"point\" \"point3 from\" [" +
                       at(eye) +
                       "] \"rgb I\" [30 30 30]\n"
                       "AttributeBegin\nTranslate " +
                       at(right) +
                       "\n"
                       "Material \"diffuse\" \"rgb reflectance\" [0.9 0 0]\n"
                       "Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
                       "AttributeBegin\nTranslate " +
                       at(up) +
                       "\n"
                       "Material \"diffuse\" \"rgb reflectance\" [0 0.9 0]\n"
                       "Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n";
    auto r = loadPbrt(text, "mirror.pbrt");
    Image img = renderSmall(*r.scene);
    double rightRed = redness(img, 16, 32, 0, 32), leftRed = redness(img, 0, 16, 0, 32);
    INFO("red on the right " << rightRed << ", on the left " << leftRed);
    CHECK(rightRed > 1.0);
    CHECK(rightRed > 20 * std::max(leftRed, 0.01));
    double topGreen = -redness(img, 0, 32, 0, 16), bottomGreen = -redness(img, 0, 32, 16, 32);
    INFO("green at the top " << topGreen << ", at the bottom " << bottomGreen);
    CHECK(topGreen > 1.0);
    CHECK(topGreen > 20 * std::max(bottomGreen, 0.01));
}

} // namespace

TEST_CASE("pbrt images are not mirrored: the exporters' Scale -1 1 1 + LookAt", "[pbrt]") {
    // With the x flip, pbrt's camera x is world +x when looking down -z.
    checkNotMirrored("Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0", {0, 0, 5}, {1, 0, 0}, {0, 1, 0});
}

TEST_CASE("pbrt images are not mirrored: a plain LookAt", "[pbrt]") {
    // pbrt's LookAt makes camera x = cross(up, view) = world -x when looking down -z.
    checkNotMirrored("LookAt 0 0 5  0 0 0  0 1 0", {0, 0, 5}, {-1, 0, 0}, {0, 1, 0});
    // And a camera given as a matrix (camera from world, column by column): at (5, 0, 0)
    // looking down -x, camera x (the image's right) is world +z.
    checkNotMirrored("Transform [0 0 -1 0  0 1 0 0  1 0 0 0  0 0 5 1]", {5, 0, 0}, {0, 0, 1},
                     {0, 1, 0});
}

TEST_CASE("scenes/cornell-box.pbrt renders the image of scenes/cornell-box.json", "[pbrt]") {
    auto pbrtScene = loadPbrtScene((sourceDir() / "scenes/cornell-box.pbrt").string());
    auto jsonScene = loadScene(scenePath("cornell-box"));
    for (Scene* s : {pbrtScene.get(), jsonScene.get()}) {
        s->camera.width = 64;
        s->camera.height = 64;
    }
    // The pbrt file has no PixelFilter, so it gets pbrt-v4's default gaussian; the JSON scene
    // rayproc's box. The filters are tested in tests/engine/pixel_filter_test.cpp.
    CHECK(pbrtScene->camera.filter.type == PixelFilter::Type::Gaussian);
    pbrtScene->camera.filter = jsonScene->camera.filter;
    Image a = renderSmall(*pbrtScene), b = renderSmall(*jsonScene);
    ImageMetrics m = compareImages(a, b);
    INFO("relMSE " << m.relmse << ", max |a - b| " << m.maxAbs);
    // Same geometry, vertex order, materials and camera: the images are bit-identical (measured
    // relMSE 0). Anything above noise level would mean the two loaders disagree.
    CHECK(m.relmse < 1e-6);
    CHECK(m.maxAbs == 0.0);
    CHECK(meanValue(a) > 0.05); // a lit box, not two black images
}

TEST_CASE("rayproc info reads .pbrt scenes and prints warnings with file and line", "[pbrt]") {
    TempDir dir;
    std::string scene = dir.file("warn.pbrt");
    writeText(scene, std::string(kPbrtHeader) + "Shape \"curve\"\nShape \"sphere\"\n");
    RunResult r = runRayproc({"info", scene}, dir);
    CHECK(r.status == 0);
    CHECK_THAT(r.err, Catch::Contains(scene + ":5: warning: Shape \"curve\" is not supported; "
                                              "skipped"));
    CHECK_THAT(r.out, Catch::Contains("spheres      1"));

    writeText(scene, std::string(kPbrtHeader) + "Shape \"sphere\" \"float radius\" [1\n");
    r = runRayproc({"info", scene}, dir);
    CHECK(r.status != 0);
    CHECK_THAT(r.err, Catch::Contains(scene + ":5:31: "));
}
