// The pbrt reader's syntax: tokens, parameter lists, directives, Include / Import, the options
// block, and malformed input as InputErrors "file:line:column: problem".
#include "pbrt_test_util.h"

#include "modes/modes.h"
#include "scene/pbrt/pbrt_params.h"
#include "scene/pbrt/pbrt_tokenizer.h"

using namespace rayproc;
using namespace rayproc::pbrt;
using namespace rayproc::test;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

TEST_CASE("Tokens: words, strings with escapes, brackets, comments, lines and columns", "[pbrt]") {
    std::string file = "t.pbrt";
    Tokenizer tok("# a comment\n  Shape \"tri\\\"angle\" [ 1 -2.5e1 ] # more\n\"x\"", &file);
    Token t = tok.next();
    CHECK(t.is(Token::Kind::Word));
    CHECK(t.text == "Shape");
    CHECK(t.loc.line == 2);
    CHECK(t.loc.column == 3);
    t = tok.next();
    CHECK(t.is(Token::Kind::String));
    CHECK(Tokenizer::unescape(t) == "tri\"angle");
    CHECK(t.loc.column == 9);
    CHECK(tok.next().is(Token::Kind::LBracket));
    CHECK(tok.peek().text == "1");
    CHECK(tok.next().text == "1");
    CHECK(tok.next().text == "-2.5e1");
    CHECK(tok.next().is(Token::Kind::RBracket));
    t = tok.next();
    CHECK(t.loc.str() == "t.pbrt:3:1");
    CHECK(tok.next().is(Token::Kind::End));

    double v = 0;
    CHECK(parseNumber("+.5", v));
    CHECK(v == 0.5);
    CHECK_FALSE(parseNumber("1.5x", v));
    CHECK_FALSE(parseNumber("nan", v));
    CHECK_FALSE(parseNumber("1e39", v)); // not a float
}

TEST_CASE("Parameter lists: types, aliases, single values and bracketed lists", "[pbrt]") {
    std::string file = "p.pbrt";
    Tokenizer tok("\"float fov\" 45 \"point from\" [1 2 3] \"bool twosided\" true "
                  "\"string filename\" \"a b.ply\" \"color L\" [1 1 1] \"integer n\" [ 1 2 ] "
                  "\"spectrum eta\" \"glass-BK7\" Next",
                  &file);
    ParamList p;
    p.parse(tok);
    CHECK(tok.next().text == "Next");
    CHECK(p.getFloat("fov", 0) == 45.0);
    CHECK(p.getPoint3("from", {}) == Vec3(1, 2, 3));
    CHECK(p.getBool("twosided", false));
    CHECK(p.getString("filename", "") == "a b.ply");
    CHECK(p.find("L")->type == "rgb"); // pbrt-v3's "color"
    CHECK(p.find("n")->numbers.size() == 2);
    CHECK(p.find("eta")->strings[0] == "glass-BK7");
    CHECK(p.getFloat("absent", 7.0) == 7.0);
    CHECK(p.unused().size() == 3); // find() is not a use: "L", "n" and "eta" are unused
}

TEST_CASE("A minimal pbrt-v4 scene loads, and pbrt-v3's WorldEnd and TransformBegin are accepted",
          "[pbrt]") {
    auto v4 = loadWorld("Shape \"sphere\"\n");
    REQUIRE(rootShapes(*v4.scene).size() == 1);
    CHECK(v4.warnings.empty());
    CHECK(v4.scene->path == (pbrtTestDir() / "scene.pbrt").string());

    auto v3 = loadWorld("TransformBegin\n Translate 1 0 0\n Shape \"sphere\"\nTransformEnd\n"
                        "Shape \"sphere\"\nWorldEnd\n");
    auto shapes = rootShapes(*v3.scene);
    REQUIRE(shapes.size() == 2);
    CHECK(shapes[0].shape->center == Vec3(1, 0, 0));
    CHECK(shapes[1].shape->center == Vec3(0, 0, 0));
}

TEST_CASE("Include and Import read files relative to the including file", "[pbrt]") {
    writePbrtFile("inc/geometry/ball.pbrt", "Shape \"sphere\" \"float radius\" 2\n");
    writePbrtFile("inc/geometry/all.pbrt", "Include \"ball.pbrt\"\nTranslate 5 0 0\n"
                                           "Import \"ball.pbrt\"\n");
    auto r = loadWorld("Include \"geometry/all.pbrt\"\n", "inc/main.pbrt");
    auto shapes = rootShapes(*r.scene);
    REQUIRE(shapes.size() == 2);
    CHECK(shapes[0].shape->radius == 2.0f);
    CHECK(shapes[1].shape->center == Vec3(5, 0, 0)); // the CTM carries across files

    // An error inside an included file names that file.
    writePbrtFile("inc/broken.pbrt", "\n  Shape \"sphere\" \"float radius\" \"big\"\n");
    std::string e =
        pbrtErrorOf(std::string(kPbrtHeader) + "Include \"broken.pbrt\"\n", "inc/main2.pbrt");
    CHECK_THAT(e, StartsWith((pbrtTestDir() / "inc/broken.pbrt").string() + ":2:33: "));
}

TEST_CASE("Film, Sampler and Integrator set the resolution, spp, seed and depth", "[pbrt]") {
    auto r = loadPbrt("Sampler \"zsobol\" \"integer pixelsamples\" 64 \"integer seed\" 7\n"
                      "Integrator \"volpath\" \"integer maxdepth\" [ 12 ]\n"
                      "Film \"rgb\" \"integer xresolution\" 200 \"integer yresolution\" 100\n"
                      "Camera \"perspective\"\nWorldBegin\nShape \"sphere\"\n");
    CHECK(r.scene->camera.width == 200);
    CHECK(r.scene->camera.height == 100);
    CHECK(r.scene->render.spp == 64);
    CHECK(r.scene->render.seed == 7);
    // pbrt's 12 scattering events are rayproc's 11 bounces before the last light sample.
    CHECK(r.scene->render.maxDepth == 11);
    CHECK(r.scene->render.mode.empty());

    auto defaults = loadPbrt("Integrator \"path\"\nWorldBegin\nShape \"sphere\"\n");
    CHECK(defaults.scene->camera.width == 1280); // pbrt's default film
    CHECK(defaults.scene->camera.height == 720);
    CHECK(defaults.scene->render.spp == 0); // no Sampler: the mode decides
    CHECK(defaults.scene->render.maxDepth == 4); // pbrt's default maxdepth 5
}

TEST_CASE("Integrator sppm: its depth, radius and photons per iteration reach gi", "[pbrt]") {
    auto r = loadPbrt("Integrator \"sppm\" \"integer maxdepth\" [ 9 ] \"float radius\" [ 0.01 ]\n"
                      "  \"integer photonsperiteration\" [ 123456 ]\n"
                      "Film \"rgb\" \"integer xresolution\" 256 \"integer yresolution\" 256\n"
                      "Camera \"perspective\"\nWorldBegin\nShape \"sphere\"\n");
    // Camera chains of at most 8 specular bounces before the visible point, photons of at
    // most 9 intersections: SPPM's paths for maxdepth 9.
    CHECK(r.scene->render.maxDepth == 8);
    CHECK(r.scene->render.maxPhotonDepth == 9);
    CHECK(r.scene->render.photonRadius == 0.01f);
    CHECK(r.scene->render.photonsPerPass == 123456);
    GiSettings gi = giSettings(*r.scene, ModeOverrides{});
    CHECK(gi.maxDepth == 8);
    CHECK(gi.maxPhotonDepth == 9);
    CHECK(gi.causticRadius == 0.01f);
    CHECK(gi.causticPhotons == 123456);

    // pbrt's defaults (one photon per pixel, radius 1): gi's own photon count; a path
    // integrator's file leaves gi's photon settings alone.
    auto defaults = loadPbrt("Integrator \"sppm\"\nWorldBegin\nShape \"sphere\"\n");
    CHECK(defaults.scene->render.photonsPerPass == 0);
    CHECK(defaults.scene->render.photonRadius == 1.0f);
    CHECK(defaults.scene->render.maxPhotonDepth == 5);
    auto path = loadPbrt("Integrator \"path\" \"integer maxdepth\" 9\nWorldBegin\nShape \"sphere\"\n");
    CHECK(path.scene->render.maxPhotonDepth == 0);
    CHECK(giSettings(*path.scene, ModeOverrides{}).maxPhotonDepth == GiSettings{}.maxPhotonDepth);
}

TEST_CASE("pbrt's fov spans the shorter image axis, rayproc's fovY is vertical", "[pbrt]") {
    auto fovY = [](int w, int h, const std::string& extra) {
        auto r = loadPbrt("Camera \"perspective\" \"float fov\" 60 " + extra +
                          "\nFilm \"rgb\" \"integer xresolution\" " + std::to_string(w) +
                          " \"integer yresolution\" " + std::to_string(h) +
                          "\nWorldBegin\nShape \"sphere\"\n");
        return double(r.scene->camera.fovY);
    };
    auto deg = [](double tanHalf) { return 2 * std::atan(tanHalf) * 180 / 3.14159265358979; };
    double t = std::tan(30 * 3.14159265358979 / 180);
    CHECK(fovY(200, 100, "") == Approx(60.0).epsilon(1e-5));       // landscape: fov is fovY
    CHECK(fovY(100, 200, "") == Approx(deg(2 * t)).epsilon(1e-5)); // portrait: fov is fovX
    CHECK(fovY(100, 100, "") == Approx(60.0).epsilon(1e-5));
    CHECK(fovY(100, 100, "\"float screenwindow\" [-0.5 0.5 -0.5 0.5]") ==
          Approx(deg(0.5 * t)).epsilon(1e-5));
    CHECK(fovY(200, 100, "\"float frameaspectratio\" 2") == Approx(60.0).epsilon(1e-5));
}

TEST_CASE("Malformed pbrt input is an InputError at file:line:column", "[pbrt]") {
    std::string dir = pbrtTestDir().string() + "/";
    auto check = [&](const std::string& text, const std::string& where, const std::string& what) {
        std::string e = pbrtErrorOf(text);
        CHECK_THAT(e, StartsWith(dir + "bad.pbrt:" + where + ": ") && Contains(what));
    };
    std::string h = kPbrtHeader; // 4 lines
    check(h + "Shape \"sphere\n", "5:7", "unterminated string");
    check(h + "  Shap \"sphere\"\n", "5:3", "unknown directive \"Shap\"");
    check(h + "Shape \"sphere\" \"float radius\" \"one\"\n", "5:31", "expects numbers");
    check(h + "Shape \"sphere\" \"string radius\" \"one\"\n", "5:16",
          "parameter \"radius\" must be of type \"float\", not \"string\"");
    check(h + "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" "
              "[0 1 3]\n",
          "5:53", "index 3 out of range: the mesh has 3 vertices");
    check(h + "Shape \"trianglemesh\" \"integer indices\" [0 1 2.5]", "5:45", "expects integers");
    check(h + "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0]", "5:22", "multiple of 3");
    check(h + "Shape \"plymesh\" \"string filename\" \"missing.ply\"\n", "5:17",
          "PLY file not found: " + dir + "missing.ply");
    check(h + "AttributeBegin\nAttributeEnd\nAttributeEnd\n", "7:1", "unbalanced AttributeEnd");
    check(h + "AttributeBegin\nTransformEnd\n", "6:1", "does not match the AttributeBegin at");
    check(h + "AttributeBegin\nShape \"sphere\"\n", "5:1",
          "AttributeBegin has no matching AttributeEnd");
    check(h + "Shape \"sphere\" \"float radius\" [1\n", "5:31", "never closed");
    check(h + "NamedMaterial \"nope\"\nShape \"sphere\"\n", "5:1",
          "NamedMaterial \"nope\" was never defined");
    check(h + "ObjectInstance \"nope\"\n", "5:1", "\"nope\", which was never defined");
    check(h + "Camera \"perspective\"\n", "5:1", "not allowed after WorldBegin");
    check("Shape \"sphere\"\n", "1:1", "only allowed after WorldBegin");
    check(h + "Rotate 90 0 0 0\n", "5:1", "axis is zero");
    check("LookAt 0 0 0 0 0 0 0 1 0\n", "1:1", "LookAt");
    check(h + "Translate 1 2\nShape \"sphere\"", "6:1", "Translate expects a number");
    check(h + "Include \"nowhere.pbrt\"\n", "5:1", "cannot open the included file");
    check(h + "Shape \"sphere\" \"radius\" 1\n", "5:16", "expected a parameter declaration");
    check(h + "Shape \"sphere\" \"real radius\" 1\n", "5:16", "unknown parameter type \"real\"");
    check(h + "MakeNamedMaterial \"m\" \"string type\" \"diffuse\"\n"
              "MakeNamedMaterial \"m\" \"string type\" \"diffuse\"\n",
          "6:1", "defined twice");
    check(h + "Material \"diffuse\" \"rgb reflectance\" [1.5 0 0]\n", "5:20", "must not exceed 1");

    // Whole-file problems name the file.
    std::string noWorld = pbrtErrorOf("Camera \"perspective\"\n", "noworld.pbrt");
    CHECK_THAT(noWorld, StartsWith(dir + "noworld.pbrt: ") && Contains("no WorldBegin"));
    std::string empty = pbrtErrorOf(h + "Shape \"curve\"\n", "empty.pbrt");
    CHECK_THAT(empty, StartsWith(dir + "empty.pbrt: ") && Contains("no geometry"));
    std::string missing = pbrtErrorOf("", "x.pbrt"); // exists but empty
    CHECK_THAT(missing, Contains("no WorldBegin"));
    CHECK_THROWS_AS(loadPbrtScene(dir + "does-not-exist.pbrt"), InputError);
}
