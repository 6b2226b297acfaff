// Image textures: OpenImageIO decoding (float files linear, 8-bit files from sRGB), pbrt-v4's
// texel addressing and t flip, bilinear filtering, wrap modes, MIP levels, the scale, mix and
// checkerboard combinations, and the pbrt importer's texture classes and missing files.
#include "pbrt/pbrt_test_util.h"
#include "test_util.h"

#include "accel/embree_scene.h"
#include "engine/intersect.h"
#include "engine/ray_batch.h"
#include "engine/stats.h"
#include "image/image.h"
#include "scene/scene_loader.h"
#include "core/error.h"
#include "texture/texture_eval.h"
#include "texture/noise.h"
#include "texture/texture_image.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A 2x2 linear image: top row red, green; bottom row blue, white (as PFM: stored linear).
std::string writeQuadImage(const std::string& name) {
    Image img(2, 2);
    const float px[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c) img.at(i % 2, i / 2)[c] = px[i][c];
    std::filesystem::path p = pbrtTestDir() / name;
    std::filesystem::create_directories(p.parent_path());
    std::string path = p.string();
    writeImage(path, img);
    return path;
}

Scene sceneWith(std::vector<Texture> textures) {
    Scene s;
    s.textures = std::move(textures);
    return s;
}

Vec3 at(const Scene& s, float u, float v, int index = 0) {
    TextureContext ctx;
    ctx.uv = {u, v};
    return evalTexture(s, index, ctx);
}

bool near(const Vec3& a, const Vec3& b, float eps = 1e-5f) { return length(a - b) < eps; }

} // namespace

TEST_CASE("Image textures: texel centres, the t flip, bilinear filtering and wraps", "[texture]") {
    Texture t;
    t.type = TextureType::Image;
    t.image = loadTextureImage(writeQuadImage("quad.pfm"), TextureEncoding{});
    REQUIRE(t.image->width() == 2);
    Scene s = sceneWith({t});
    // Row 0 of the file is t = 1 (pbrt-v4 flips t): its texel centres are at t = 0.75.
    CHECK(near(at(s, 0.25f, 0.75f), {1, 0, 0}));
    CHECK(near(at(s, 0.75f, 0.75f), {0, 1, 0}));
    CHECK(near(at(s, 0.25f, 0.25f), {0, 0, 1}));
    CHECK(near(at(s, 0.75f, 0.25f), {1, 1, 1}));
    CHECK(near(at(s, 0.5f, 0.5f), {0.5f, 0.5f, 0.5f})); // the four texels' mean
    CHECK(near(at(s, 0.5f, 0.75f), {0.5f, 0.5f, 0.0f}));
    CHECK(near(at(s, 1.25f, -0.25f), {1, 0, 0})); // repeat: (0.25, 0.75)
    s.textures[0].wrap = TextureWrap::Black;
    CHECK(near(at(s, -0.5f, 0.25f), {0, 0, 0}));
    s.textures[0].wrap = TextureWrap::Clamp;
    CHECK(near(at(s, -3.0f, 0.75f), {1, 0, 0}));
    s.textures[0].wrap = TextureWrap::Repeat;
    s.textures[0].filter = TextureFilter::Point;
    CHECK(near(at(s, 0.6f, 0.9f), {0, 1, 0}));
    // Octahedral: left of the top-left texel is the square's other side, mirrored: bottom-left.
    s.textures[0].wrap = TextureWrap::Octahedral;
    CHECK(near(at(s, -0.25f, 0.75f), {0, 0, 1}));
    s.textures[0].wrap = TextureWrap::Repeat;
    // uv mapping, scale and invert.
    s.textures[0].filter = TextureFilter::Bilinear;
    s.textures[0].su = 0.5f; // s = u / 2
    CHECK(near(at(s, 0.5f, 0.75f), {1, 0, 0}));
    s.textures[0].scale = 2;
    s.textures[0].invert = true;
    CHECK(near(at(s, 0.5f, 0.75f), {-1, 1, 1}));
}

TEST_CASE("8-bit files decode from sRGB, float files are linear - MIP levels average", "[texture]") {
    Image img(4, 2);
    for (float& p : img.pixels) p = 0.5f;
    std::string png = (pbrtTestDir() / "half.png").string();
    writeImage(png, img); // 8-bit sRGB: 0.5 linear is stored as 188
    auto decoded = loadTextureImage(png, TextureEncoding{});
    CHECK(decoded->levels[0].at(1, 1)[0] == Approx(0.5f).margin(0.003f));
    auto raw = loadTextureImage(png, TextureEncoding{TextureEncoding::Kind::Linear});
    CHECK(raw->levels[0].at(1, 1)[0] == Approx(188.0f / 255.0f).margin(1e-4f));
    auto quad = loadTextureImage(writeQuadImage("quad-mip.pfm"), TextureEncoding{});
    REQUIRE(quad->levels.size() == 2);
    const float* top = quad->levels[1].at(0, 0);
    CHECK(top[0] == Approx(0.5f));
    CHECK(top[1] == Approx(0.5f));
    CHECK(top[2] == Approx(0.5f));
    CHECK_THROWS_AS(loadTextureImage((pbrtTestDir() / "nope.tga").string(), TextureEncoding{}),
                    ImageIoError);
}

TEST_CASE("Scale, mix and checkerboard textures", "[texture]") {
    Texture a, b, scale, mix, check;
    a.value = {0.2f, 0.4f, 0.6f};
    b.value = {1.0f, 0.0f, 0.5f};
    scale.type = TextureType::Scale;
    scale.a = 0;
    scale.bValue = Vec3(0.5f);
    mix.type = TextureType::Mix;
    mix.a = 0;
    mix.b = 1;
    mix.amount = 0.25f;
    check.type = TextureType::Checkerboard;
    check.a = 0;
    check.b = 1;
    check.su = check.sv = 4; // 4 x 4 squares over the unit square
    Scene s = sceneWith({a, b, scale, mix, check});
    CHECK(near(at(s, 0, 0, 2), {0.1f, 0.2f, 0.3f}));
    CHECK(near(at(s, 0, 0, 3), {0.4f, 0.3f, 0.575f}));
    CHECK(near(at(s, 0.1f, 0.1f, 4), a.value)); // square (0, 0): even
    CHECK(near(at(s, 0.3f, 0.1f, 4), b.value)); // square (1, 0): odd
    CHECK(near(at(s, 0.3f, 0.3f, 4), a.value)); // square (1, 1): even
    CHECK(evalFloatTexture(s, 0, TextureContext{}) == Approx(0.4f)); // a colour's mean
}

namespace {

// At world point p with geometric normal n (and uv 0).
Vec3 atPoint(const Scene& s, int index, const Vec3& p, const Vec3& n = {0, 0, 1}) {
    TextureContext ctx;
    ctx.p = p;
    ctx.n = n;
    return evalTexture(s, index, ctx);
}

// A bilerp whose value is (s, t, 0): it shows a mapping's (s, t).
Texture stProbe(TextureMapping mapping) {
    Texture t;
    t.type = TextureType::Bilerp;
    t.mapping = mapping;
    t.corners = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
    return t;
}

} // namespace

TEST_CASE("Bilerp, direction mix, 3D checkerboard and the spherical, cylindrical and planar "
          "mappings",
          "[texture]") {
    // pbrt-v4's definitions: bilerp (1-s)(1-t) v00 + s(1-t) v10 + (1-s)t v01 + st v11, not
    // wrapped; direction mix |n . dir| tex1 + (1 - |n . dir|) tex2; a 3D checkerboard on the
    // lattice of the point in texture space; spherical (theta / pi, phi / 2 pi), cylindrical
    // ((pi + atan2(y, x)) / 2 pi, z), planar (du + p . v1, dv + p . v2).
    Texture a, b;
    a.value = {1, 0, 0};
    b.value = {0, 0, 1};
    Texture bilerp;
    bilerp.type = TextureType::Bilerp;
    bilerp.corners = {Vec3(0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 1)};
    Texture mix;
    mix.type = TextureType::DirectionMix;
    mix.a = 0;
    mix.b = 1;
    mix.direction = {0, 1, 0};
    Texture check;
    check.type = TextureType::Checkerboard;
    check.mapping = TextureMapping::Point;
    check.a = 0;
    check.b = 1;
    check.textureFromWorld = Affine::translate({-1, 0, 0});
    Texture planar = stProbe(TextureMapping::Planar);
    planar.planarT = {0, 0, 1};
    planar.du = 0.5f;
    Scene s = sceneWith({a, b, bilerp, mix, check, stProbe(TextureMapping::Spherical),
                         stProbe(TextureMapping::Cylindrical), planar});
    CHECK(near(at(s, 0.25f, 0.5f, 2), {0.25f, 0.5f, 0.125f}));
    CHECK(near(at(s, 2.0f, -1.0f, 2), {2.0f, -1.0f, -2.0f})); // beyond the square: extrapolated
    CHECK(near(atPoint(s, 3, {}, {0, -1, 0}), a.value));
    CHECK(near(atPoint(s, 3, {}, {1, 0, 0}), b.value));
    CHECK(near(atPoint(s, 3, {}, {0, 0.5f, std::sqrt(0.75f)}), {0.5f, 0, 0.5f}));
    CHECK(near(atPoint(s, 4, {1.5f, 0.5f, 0.5f}), a.value)); // (0.5, 0.5, 0.5) in its space
    CHECK(near(atPoint(s, 4, {2.5f, 0.5f, 0.5f}), b.value));
    CHECK(near(atPoint(s, 4, {2.5f, -0.5f, 0.5f}), a.value));
    CHECK(near(atPoint(s, 5, {0, 0, 2}), {0, 0, 0}));
    CHECK(near(atPoint(s, 5, {1, 1, 0}), {0.5f, 0.125f, 0}));
    CHECK(near(atPoint(s, 5, {0, -3, 0}), {0.5f, 0.75f, 0}));
    CHECK(near(atPoint(s, 6, {-1, 0, 3}), {1, 3, 0}));
    CHECK(near(atPoint(s, 6, {0, 2, 0.5f}), {0.75f, 0.5f, 0}));
    CHECK(near(atPoint(s, 7, {2, 7, 3}), {2.5f, 3, 0}));
}

TEST_CASE("pbrt textures: bilerp, directionmix, 3D checkerboards and the mappings in the "
          "directive's space",
          "[texture][pbrt]") {
    auto r = loadWorld(
        "AttributeBegin\nTranslate 10 0 0\n"
        "Texture \"c3\" \"spectrum\" \"checkerboard\" \"integer dimension\" 3 "
        "\"rgb tex1\" [1 0 0] \"rgb tex2\" [0 0 1]\n"
        "Texture \"sph\" \"float\" \"bilerp\" \"string mapping\" \"spherical\" "
        "\"float v00\" 0 \"float v10\" 1 \"float v01\" 0 \"float v11\" 1\n"
        "Texture \"pl\" \"spectrum\" \"bilerp\" \"string mapping\" \"planar\" "
        "\"vector3 v1\" [0 0 1] \"vector3 v2\" [0 1 0] \"float udelta\" 0.5 \"rgb v10\" [1 1 1]\n"
        "Rotate 90 0 0 1\n"
        "Texture \"dm\" \"spectrum\" \"directionmix\" \"rgb tex1\" [1 1 1] "
        "\"texture tex2\" \"c3\"\n"
        "AttributeEnd\n"
        "Material \"diffuse\" \"texture reflectance\" \"dm\"\nShape \"sphere\"\n");
    CHECK(r.warnings.empty());
    const Scene& s = *r.scene;
    REQUIRE(s.textures.size() == 4);
    CHECK(s.textures[0].mapping == TextureMapping::Point);
    CHECK(near(atPoint(s, 0, {10.5f, 0.5f, 0.5f}), {1, 0, 0}));
    CHECK(near(atPoint(s, 0, {11.5f, 0.5f, 0.5f}), {0, 0, 1}));
    CHECK(s.textures[1].isFloat);
    // The sphere around (10, 0, 0): theta / pi at its equator is 0.5 (v10 = v11 = 1: s itself).
    CHECK(evalFloatTexture(s, 1, TextureContext{{}, {10, 2, 0}}) == Approx(0.5f));
    CHECK(s.textures[2].mapping == TextureMapping::Planar);
    // (s, t) = (0.5 + 0.3, 0.5) at texture-space (0.25, 0.5, 0.3); v10 = v01 = v11 = 1:
    // s + t - s t.
    CHECK(near(atPoint(s, 2, {10.25f, 0.5f, 0.3f}), Vec3(0.9f)));
    // "dir" (0, 1, 0) turned by the rotation: the world's x axis (either sign).
    CHECK(std::abs(s.textures[3].direction.x) == Approx(1.0f));
    CHECK(s.textures[3].b == 0);
    std::string e = pbrtErrorOf(std::string(kPbrtHeader) +
                                "Texture \"c\" \"float\" \"checkerboard\" \"integer dimension\" 4\n");
    CHECK_THAT(e, Catch::Contains("must be 2 or 3"));
    auto odd = loadWorld("Texture \"x\" \"float\" \"checkerboard\" \"string mapping\" \"cubic\"\n"
                         "Shape \"sphere\"\n");
    CHECK(odd.warned("texture mapping \"cubic\" is not one of pbrt-v4's"));
}

TEST_CASE("pbrt textures: imagemap, scale, mix and checkerboard classes, missing files", "[texture][pbrt]") {
    writeQuadImage("tex/quad.pfm");
    auto r = loadWorld("Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"tex/quad.pfm\" "
                       "\"float uscale\" 2 \"string wrap\" \"clamp\" \"string filter\" \"trilinear\"\n"
                       "Texture \"half\" \"spectrum\" \"scale\" \"texture tex\" \"img\" \"float scale\" 0.5\n"
                       "Texture \"m\" \"float\" \"mix\" \"float tex1\" 0.2 \"float tex2\" 0.8\n"
                       "Texture \"c\" \"spectrum\" \"checkerboard\" \"texture tex1\" \"half\" \"rgb tex2\" [0 1 0]\n"
                       "Material \"conductor\" \"texture roughness\" \"m\" \"texture reflectance\" \"c\"\n"
                       "Shape \"sphere\"\n");
    CHECK(r.warnings.empty());
    const Scene& s = *r.scene;
    REQUIRE(s.textures.size() == 4);
    CHECK(s.textures[0].type == TextureType::Image);
    CHECK(s.textures[0].su == 2.0f);
    CHECK(s.textures[0].wrap == TextureWrap::Clamp);
    CHECK(s.textures[0].filter == TextureFilter::Trilinear);
    CHECK(s.textures[1].type == TextureType::Scale);
    CHECK(s.textures[1].a == 0);
    CHECK(s.textures[1].bValue.x == 0.5f);
    CHECK(s.textures[2].type == TextureType::Mix);
    CHECK(s.textures[2].isFloat);
    CHECK(s.textures[3].type == TextureType::Checkerboard);
    CHECK(s.textures[3].a == 1);
    CHECK(s.textures[3].bValue == Vec3(0, 1, 0));
    const Material& m = s.materials[std::size_t(rootShapes(s)[0].shape->material)];
    CHECK(m.colorTexture == 3);
    CHECK(m.uRoughness.texture == 2);

    auto missing = loadWorld("Texture \"w\" \"spectrum\" \"imagemap\" \"string filename\" \"none.tga\"\n"
                             "Material \"diffuse\" \"texture reflectance\" \"w\"\nShape \"sphere\"\n");
    CHECK(missing.warned("scene.pbrt:5: ")); // file and line
    CHECK(missing.warned("cannot read the texture"));
    CHECK(missing.scene->textures.empty());
    const Material& d = missing.scene->materials[std::size_t(rootShapes(*missing.scene)[0].shape->material)];
    CHECK(d.colorTexture == -1);
    CHECK(d.color == Vec3(0.5f));
    std::string e = pbrtErrorOf(std::string(kPbrtHeader) +
                                "Texture \"w\" \"spectrum\" \"imagemap\" \"string filename\" \"x.png\" "
                                "\"string wrap\" \"mirror\"\n");
    CHECK_THAT(e, Catch::Contains("unknown texture wrap mode \"mirror\""));
}

TEST_CASE("A textured diffuse material shades with the texture in path mode", "[texture]") {
    // A quad whose texture is red on its left half and blue on its right, seen head-on.
    Image img(2, 1);
    img.at(0, 0)[0] = 1.0f;
    img.at(1, 0)[2] = 1.0f;
    std::string path = (pbrtTestDir() / "rb.pfm").string();
    writeImage(path, img);
    auto r = loadWorld("Texture \"rb\" \"spectrum\" \"imagemap\" \"string filename\" \"rb.pfm\" "
                       "\"string filter\" \"point\"\n"
                       "Material \"diffuse\" \"texture reflectance\" \"rb\"\n"
                       "Shape \"trianglemesh\" \"point3 P\" [-1 -1 0 1 -1 0 1 1 0 -1 1 0] "
                       "\"point2 uv\" [0 0 1 0 1 1 0 1] \"integer indices\" [0 1 2 0 2 3]\n"
                       "LightSource \"infinite\" \"rgb L\" [1 1 1]\n",
                       "textured.pbrt");
    EmbreeScene accel(*r.scene);
    RenderOptions o;
    o.mode = "path";
    o.spp = 4;
    Image out = render(*r.scene, accel, o).image;
    const float* left = out.at(12, 16);
    const float* right = out.at(20, 16);
    CHECK(left[0] > 10 * left[2]);
    CHECK(right[2] > 10 * right[0]);
}

TEST_CASE("JSON textures: image, checkerboard, scale, mix, and colours that name them", "[texture][scene]") {
    writeQuadImage("json/quad.pfm");
    std::string dir = (pbrtTestDir() / "json").string();
    std::string path = dir + "/textured.json";
    writeText(path, R"({
        "textures": {
            "img": {"type": "image", "file": "quad.pfm", "uscale": 2, "wrap": "clamp", "filter": "point"},
            "half": {"type": "scale", "tex": "img", "scale": 0.5},
            "check": {"type": "checkerboard", "tex1": "half", "tex2": [0, 1, 0], "uscale": 8, "vscale": 8},
            "blend": {"type": "mix", "tex1": 0.2, "tex2": "check", "amount": 0.25}},
        "materials": {"m": {"type": "diffuse", "color": "blend"},
                      "p": {"type": "diffusetransmission", "transmittance": "img"}},
        "nodes": [{"type": "sphere", "radius": 1, "material": "m"}]})");
    auto scene = loadScene(path);
    REQUIRE(scene->textures.size() == 4);
    CHECK(scene->textures[0].image);
    CHECK(scene->textures[0].su == 2.0f);
    CHECK(scene->textures[0].wrap == TextureWrap::Clamp);
    CHECK(scene->textures[1].a == 0);
    CHECK(scene->textures[2].a == 1);
    CHECK(scene->textures[2].bValue == Vec3(0, 1, 0));
    CHECK(scene->textures[3].aValue == Vec3(0.2f));
    CHECK(scene->textures[3].amount == 0.25f);
    CHECK(scene->materials[0].colorTexture == 3);
    CHECK(scene->materials[1].transmittance.texture == 0);

    writeText(dir + "/bad.json", R"({"materials": {"m": {"type": "diffuse", "color": "nope"}},
        "nodes": [{"type": "sphere", "radius": 1, "material": "m"}]})");
    try {
        loadScene(dir + "/bad.json");
        FAIL("expected an InputError");
    } catch (const InputError& e) {
        CHECK_THAT(std::string(e.what()), Catch::Contains("/materials/m/color: unknown texture \"nope\""));
    }
    writeText(dir + "/missing.json", R"({"textures": {"t": {"type": "image", "file": "none.png"}},
        "nodes": [{"type": "sphere", "radius": 1}]})");
    CHECK_THROWS_WITH(loadScene(dir + "/missing.json"), Catch::Contains("/textures/t/file"));
}

TEST_CASE("Alpha cut-outs: alpha 0 hides a mesh from camera and shadow rays at every packet width, 0.5 hides half", "[texture][alpha]") {
    // A white occluder quad at z = 1 in front of a red quad at z = 0, lit by a sky; the camera
    // looks down -z.
    auto sceneWithAlpha = [](const std::string& alpha) {
        return loadWorld("AttributeBegin\nMaterial \"diffuse\" \"rgb reflectance\" [1 1 1]\n"
                         "Shape \"trianglemesh\" \"point3 P\" [-5 -5 1 5 -5 1 5 5 1 -5 5 1] "
                         "\"integer indices\" [0 1 2 0 2 3] " + alpha + "\nAttributeEnd\n"
                         "Material \"diffuse\" \"rgb reflectance\" [1 0 0]\n"
                         "Shape \"trianglemesh\" \"point3 P\" [-5 -5 0 5 -5 0 5 5 0 -5 5 0] "
                         "\"integer indices\" [0 1 2 0 2 3]\n"
                         "LightSource \"infinite\" \"rgb L\" [1 1 1]\n",
                         "alpha.pbrt");
    };
    auto hidden = sceneWithAlpha("\"float alpha\" 0");
    CHECK(hidden.warnings.empty());
    auto opaque = sceneWithAlpha("");
    auto half = sceneWithAlpha("\"float alpha\" 0.5");
    for (int width : {1, 4, 8, 16}) {
        INFO("packet width " << width);
        RenderOptions o;
        o.mode = "path";
        o.spp = 16;
        o.packetWidth = width;
        EmbreeScene ha(*hidden.scene), oa(*opaque.scene), hb(*half.scene);
        Image h = render(*hidden.scene, ha, o).image;
        Image op = render(*opaque.scene, oa, o).image;
        Image hf = render(*half.scene, hb, o).image;
        // Hidden: the red quad lit by the whole upper sky (the occluder casts no shadow):
        // L = albedo * L_sky = (1, 0, 0). Opaque: white. Half: about the mean of the two.
        const float* ph = h.at(16, 16);
        const float* po = op.at(16, 16);
        CHECK(ph[0] == Approx(1.0f).margin(0.05f));
        CHECK(ph[1] == Approx(0.0f).margin(1e-6f));
        CHECK(po[1] == Approx(1.0f).margin(0.05f));
        double g = 0;
        for (int y = 8; y < 24; ++y)
            for (int x = 8; x < 24; ++x) g += hf.at(x, y)[1];
        g /= 256;
        CHECK(g > 0.3);
        CHECK(g < 0.7);
    }
}

namespace {

// Which of `rays` (origin, direction pairs) an occlusion query finds blocked.
std::vector<bool> blockedRays(const Scene& scene, const std::vector<std::pair<Vec3, Vec3>>& rays) {
    EmbreeScene accel(scene);
    ShadowBatch b;
    b.kind = RayKind::Shadow;
    for (const auto& [o, d] : rays) b.push(o.x, o.y, o.z, d.x, d.y, d.z, 0.0f, kInfinity);
    ThreadStats stats;
    Intersector(accel.root(), 16).trace(b, stats);
    std::vector<bool> blocked;
    for (int i = 0; i < b.count; ++i) blocked.push_back(b.occluded(i));
    return blocked;
}

} // namespace

TEST_CASE("Alpha cut-outs: a texture of the point or the normal reads the world-space hit, instanced or not", "[texture][alpha]") {
    // alpha: a checkerboard of unit squares planar-mapped in world space (s = x, t = y), 1 where
    // floor(x) + floor(y) is even; or a direction mix, 1 where the quad faces z, 0 facing x.
    const std::string textures =
        "Texture \"check\" \"float\" \"checkerboard\" \"string mapping\" \"planar\" "
        "\"vector3 v1\" [1 0 0] \"vector3 v2\" [0 1 0] \"float tex1\" 1 \"float tex2\" 0\n"
        "Texture \"facing\" \"float\" \"directionmix\" \"vector3 dir\" [0 0 1] "
        "\"float tex1\" 1 \"float tex2\" 0\n";
    auto quad = [](const std::string& alpha) {
        return "Shape \"trianglemesh\" \"point3 P\" [-4 -4 0 4 -4 0 4 4 0 -4 4 0] "
               "\"integer indices\" [0 1 2 0 2 3] \"texture alpha\" \"" + alpha + "\"\n";
    };
    // Rays straight down -z through points off the squares' edges.
    std::vector<std::pair<Vec3, Vec3>> down;
    std::vector<bool> expected;
    for (int i = 0; i < 11; ++i)
        for (int j = 0; j < 11; ++j) {
            float x = -2.75f + 0.5f * float(i), y = -2.75f + 0.5f * float(j);
            down.push_back({{x, y, 5}, {0, 0, -1}});
            expected.push_back(int(std::floor(x) + std::floor(y)) % 2 == 0);
        }
    // The quad moved by (0.25, 0.5, 1): at the root (its points made world-space at import),
    // and as two placements of an object (an Embree instance; the filter sees object space).
    auto root = loadWorld(textures + "AttributeBegin\nTranslate 0.25 0.5 1\n" + quad("check") +
                          "AttributeEnd\n");
    auto placed = loadWorld(textures + "ObjectBegin \"q\"\n" + quad("check") + "ObjectEnd\n" +
                            "AttributeBegin\nTranslate 0.25 0.5 1\nObjectInstance \"q\"\n"
                            "AttributeEnd\nAttributeBegin\nTranslate 100 0 0\n"
                            "ObjectInstance \"q\"\nAttributeEnd\n");
    REQUIRE(EmbreeScene(*placed.scene).stats().instances == 2);
    for (const LoadedPbrt* loaded : {&root, &placed}) {
        INFO((loaded == &root ? "at the root" : "instanced"));
        CHECK(loaded->warnings.empty());
        std::vector<bool> blocked = blockedRays(*loaded->scene, down);
        int wrong = 0;
        for (std::size_t k = 0; k < down.size(); ++k) wrong += blocked[k] != expected[k];
        CHECK(wrong == 0);
    }
    // The direction mix: one placement facing z, one rotated to face x; rays along each normal.
    auto facing = loadWorld(textures + "ObjectBegin \"q\"\n" + quad("facing") + "ObjectEnd\n" +
                            "ObjectInstance \"q\"\nAttributeBegin\nTranslate 20 0 0\n"
                            "Rotate 90 0 1 0\nObjectInstance \"q\"\nAttributeEnd\n");
    std::vector<bool> blocked =
        blockedRays(*facing.scene, {{{0.5f, 0.5f, 5}, {0, 0, -1}}, {{25, 0.5f, 0.5f}, {-1, 0, 0}}});
    CHECK(blocked[0]);  // faces z: alpha 1
    CHECK(!blocked[1]); // faces x: alpha 0
}

TEST_CASE("Solid noise: zero on the lattice, within [-1, 1], smooth, and pbrt-v4's values",
          "[texture][noise]") {
    for (Vec3 p : {Vec3(0, 0, 0), Vec3(3, -5, 7), Vec3(-200, 41, 1000), Vec3(255, 256, -257)})
        CHECK(solidNoise(p) == 0.0f);
    std::uint64_t h = 7;
    double sum = 0, sum2 = 0, largestStep = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        Vec3 p;
        for (float* c : {&p.x, &p.y, &p.z}) {
            h = h * 6364136223846793005ull + 1442695040888963407ull;
            *c = float(h >> 40) * 0x1p-24f * 200.0f - 100.0f;
        }
        const float v = solidNoise(p);
        CHECK(std::abs(v) <= 1.0f);
        sum += v;
        sum2 += double(v) * v;
        largestStep = std::max(largestStep, double(std::abs(solidNoise(p + Vec3(1e-3f)) - v)));
    }
    CHECK(std::abs(sum / n) < 0.02);
    CHECK(std::sqrt(sum2 / n) > 0.15);
    CHECK(largestStep < 0.01); // continuous: a 1.7e-3 step moves it less than 0.01
    // Values from an independent double-precision reading of pbrt-v4's definitions (Perlin's
    // permutation, pbrt's gradients, 1.99 lacunarity; a Python script), at float's precision.
    const float eps = 2e-5f;
    CHECK(solidNoise(0.3f, 1.7f, 2.2f) == Approx(-0.2725179399).margin(eps));
    CHECK(solidNoise(-3.25f, 7.5f, 0.125f) == Approx(0.4425694272).margin(eps));
    CHECK(solidNoise(100.6f, -20.2f, 5.9f) == Approx(-0.5259283876).margin(eps));
    const Vec3 p(0.37f, -1.21f, 2.63f);
    CHECK(fbmNoise(p, 0.5f, 8) == Approx(-0.2994776023).margin(eps));
    CHECK(turbulenceNoise(p, 0.5f, 8) == Approx(0.4101191135).margin(eps));
    CHECK(fbmNoise(p, 0.7f, 6) == Approx(-0.3044278459).margin(eps));
    CHECK(windyNoise(Vec3(3.1f, 0.4f, -2.2f)) == Approx(-0.0231272920).margin(eps));
    const Vec3 m = marbleColour(Vec3(0.7f, 1.3f, -0.4f), 1, 0.2f, 0.5f, 8);
    CHECK(m.x == Approx(0.7595169972).margin(eps));
    CHECK(m.y == Approx(0.7595169972).margin(eps));
    CHECK(m.z == Approx(0.8214989191).margin(eps));
    const Vec3 m2 = marbleColour(Vec3(2.0f, -0.8f, 1.1f), 2, 0.5f, 0.6f, 5);
    CHECK(m2.x == Approx(0.8699255197).margin(eps));
    CHECK(m2.z == Approx(0.8999068997).margin(eps));
    // The dots on a quarter-unit grid over [-2, 2]^2: 53 of its points, the first ones these.
    int inside = 0;
    for (int s = -8; s <= 8; ++s)
        for (int t = -8; t <= 8; ++t) inside += insidePolkaDot(float(s) / 4, float(t) / 4);
    CHECK(inside == 53);
    CHECK(insidePolkaDot(-2.0f, -1.75f));
    CHECK(insidePolkaDot(-1.25f, 1.75f));
    CHECK_FALSE(insidePolkaDot(-1.5f, -2.0f));
}

TEST_CASE("pbrt noise textures: fbm, wrinkled, windy, marble and dots as pbrt-v4 defines them",
          "[pbrt][texture][noise]") {
    // Defined under Translate 1 2 3: the 3D ones read the point in the directive's space.
    auto r = loadWorld(
        "AttributeBegin\nTranslate 1 2 3\n"
        "Texture \"f\" \"float\" \"fbm\" \"integer octaves\" 5 \"float roughness\" 0.7\n"
        "Texture \"w\" \"float\" \"wrinkled\"\nTexture \"y\" \"float\" \"windy\"\n"
        "Texture \"m\" \"spectrum\" \"marble\" \"float scale\" 2 \"float variation\" 0.5\n"
        "AttributeEnd\n"
        "Texture \"d\" \"spectrum\" \"dots\" \"rgb inside\" [1 0 0] \"rgb outside\" [0 0 1]\n"
        "Material \"diffuse\" \"texture reflectance\" \"m\"\nShape \"sphere\"\n"
        "Material \"diffuse\" \"texture reflectance\" \"d\"\nShape \"sphere\"\n"
        "Material \"conductor\" \"texture roughness\" \"f\"\nShape \"sphere\"\n"
        "Material \"conductor\" \"texture roughness\" \"w\"\nShape \"sphere\"\n"
        "Material \"conductor\" \"texture roughness\" \"y\"\nShape \"sphere\"\n");
    CHECK(r.warnings.empty());
    const Scene& scene = *r.scene;
    REQUIRE(scene.textures.size() == 5);
    const rayproc::Texture& f = scene.textures[0];
    CHECK(f.type == TextureType::Fbm);
    CHECK(f.octaves == 5);
    CHECK(f.omega == 0.7f);
    CHECK(scene.textures[1].octaves == 8); // pbrt-v4's defaults
    CHECK(scene.textures[1].omega == 0.5f);
    CHECK(scene.textures[3].noiseScale == 2.0f);
    CHECK(scene.textures[3].variation == 0.5f);
    TextureContext tc;
    tc.p = {1.5f, 1.25f, 4.75f};
    const Vec3 local = tc.p - Vec3(1, 2, 3);
    CHECK(evalFloatTexture(scene, 0, tc) == fbmNoise(local, 0.7f, 5));
    CHECK(evalFloatTexture(scene, 1, tc) == turbulenceNoise(local, 0.5f, 8));
    CHECK(evalFloatTexture(scene, 2, tc) == windyNoise(local));
    CHECK(evalTexture(scene, 3, tc) == marbleColour(local, 2, 0.5f, 0.5f, 8));
    // dots: uv mapping; inside the dot of the cell at (-2, -2) (see the noise test), not at
    // (-1.5, -2).
    tc.uv = {-2.0f, -1.75f};
    CHECK(evalTexture(scene, 4, tc) == Vec3(1, 0, 0));
    tc.uv = {-1.5f, -2.0f};
    CHECK(evalTexture(scene, 4, tc) == Vec3(0, 0, 1));
    CHECK_THAT(pbrtErrorOf(std::string(kPbrtHeader) +
                           "Texture \"f\" \"float\" \"fbm\" \"integer octaves\" -1\n"),
               Catch::Contains("\"octaves\" must be from 0 to 64"));
    // ptex is still not read: it warns and the parameter keeps its default.
    auto ptex = loadWorld("Texture \"p\" \"spectrum\" \"ptex\" \"string filename\" \"x.ptx\"\n"
                          "Material \"diffuse\" \"texture reflectance\" \"p\"\nShape \"sphere\"\n");
    CHECK(ptex.warned("Texture class \"ptex\" is not supported"));
}
