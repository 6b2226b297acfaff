// Bump and normal mapping (engine/material_bsdf.h, resolveShading) as pbrt-v4 defines them: the
// shading normal of a displaced surface p + d(u, v) n and of a tangent-space normal map, checked
// against their closed forms on a flat patch, and a render whose light follows the tilted normal.
#include "engine/material_bsdf.h"
#include "test_util.h"
#include "texture/texture_image.h"

#include <cmath>
#include <functional>
#include <memory>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A linear image texture of `width` x 1 texels whose value at texel centre x is
// f((x + 0.5) / width): bilinear lookups reproduce f exactly where f is linear in u.
int addImageTexture(Scene& scene, int width, const std::function<Vec3(float)>& f, bool isFloat) {
    auto img = std::make_shared<TextureImage>();
    img->levels.resize(1);
    img->levels[0].width = width;
    img->levels[0].height = 1;
    for (int x = 0; x < width; ++x) {
        Vec3 c = f((float(x) + 0.5f) / float(width));
        img->levels[0].rgb.insert(img->levels[0].rgb.end(), {c.x, c.y, c.z});
    }
    buildMipLevels(*img);
    Texture t;
    t.type = TextureType::Image;
    t.isFloat = isFloat;
    t.image = img;
    t.wrap = TextureWrap::Clamp;
    t.filter = TextureFilter::Bilinear;
    scene.textures.push_back(t);
    return int(scene.textures.size()) - 1;
}

// A hit at the centre of a flat L x L patch in the z = 0 plane, u along x, v along y.
SurfaceHit patchHit(float size) {
    SurfaceHit h;
    h.p = {0.5f * size, 0.5f * size, 0};
    h.ng = h.ns = {0, 0, 1};
    h.uv = {0.5f, 0.5f};
    h.dpdu = {size, 0, 0};
    h.dpdv = {0, size, 0};
    h.material = 0;
    return h;
}

bool near(const Vec3& a, const Vec3& b, float eps) { return length(a - b) < eps; }

} // namespace

TEST_CASE("Bump mapping: a displacement rising k over the patch tilts the normal by atan(k / L)",
          "[engine][bump]") {
    // d(u) = k u on an L x L patch: the displaced surface is the plane z = (k / L) x, whose
    // normal is (-k / L, 0, 1) normalised (pbrt-v4's BumpMap, with no dn/du on a flat patch).
    for (float k : {0.05f, 0.5f, 2.0f}) {
        const float size = 2.0f;
        Scene scene;
        Material m;
        m.displacement = addImageTexture(scene, 64, [k](float u) { return Vec3(k * u); }, true);
        scene.materials.push_back(m);
        SurfaceHit h = patchHit(size);
        resolveShading(scene, h, {0, 0, 1});
        Vec3 expected = normalize(Vec3(-k / size, 0, 1));
        INFO("k " << k << ": ns " << h.ns.x << " " << h.ns.y << " " << h.ns.z);
        CHECK(near(h.ns, expected, 2e-3f));
        CHECK(std::abs(dot(h.ns, normalize(h.dpdu))) < 1e-4f); // the new frame is the new normal's
        CHECK(std::abs(dot(h.ns, normalize(h.dpdv))) < 1e-4f);
        CHECK(h.ng.z == 1.0f); // the geometric normal stays
    }
}

TEST_CASE("Bump mapping: a constant displacement and a material without one leave the normal",
          "[engine][bump]") {
    Scene scene;
    Material bumped, plain;
    bumped.displacement = addImageTexture(scene, 8, [](float) { return Vec3(0.3f); }, true);
    scene.materials = {bumped, plain};
    for (int material : {0, 1}) {
        SurfaceHit h = patchHit(1.0f);
        h.material = material;
        resolveShading(scene, h, {0, 0, 1});
        CHECK(near(h.ns, {0, 0, 1}, 1e-6f));
    }
}

TEST_CASE("Normal mapping: the image's 2c - 1 in the frame (dp/du, n x dp/du, n)",
          "[engine][bump]") {
    // A flat map (0.5, 0.5, 1) keeps the normal; a tilted one turns it within the (dp/du, n)
    // plane or the (n x dp/du, n) plane; one pointing below the surface is turned to the
    // geometric normal's side (pbrt-v4's SetShadingGeometry).
    struct Case {
        Vec3 tangentNormal, expected;
    } cases[] = {
        {{0, 0, 1}, {0, 0, 1}},
        {{0.6f, 0, 0.8f}, {0.6f, 0, 0.8f}},
        {{0, -0.6f, 0.8f}, {0, -0.6f, 0.8f}},
        {{0.6f, 0, -0.8f}, {-0.6f, 0, 0.8f}},
    };
    for (const Case& c : cases) {
        Scene scene;
        Material m;
        Vec3 colour = (c.tangentNormal + Vec3(1.0f)) * 0.5f;
        m.normalMap = addImageTexture(scene, 4, [colour](float) { return colour; }, false);
        scene.materials.push_back(m);
        SurfaceHit h = patchHit(3.0f);
        resolveShading(scene, h, {0, 0, 1});
        INFO("map normal " << c.tangentNormal.x << " " << c.tangentNormal.y << " "
                           << c.tangentNormal.z << ": ns " << h.ns.x << " " << h.ns.y << " "
                           << h.ns.z);
        CHECK(near(h.ns, c.expected, 1e-4f));
        CHECK(length(h.dpdu) == Approx(3.0f).epsilon(1e-4)); // dp/du keeps its length
        CHECK(std::abs(dot(h.ns, h.dpdu)) < 1e-4f);
    }
}

TEST_CASE("Bump mapping in a render: a floor under an overhead light dims as the cosine of the "
          "bumped normal's tilt",
          "[engine][bump]") {
    // A Lambertian floor lit by a distant light straight down, seen from above: its radiance is
    // albedo / pi E cos(theta) with theta the shading normal's tilt, here atan(k / L) from a
    // displacement ramp. Path mode at depth 1 (no other surface).
    const float k = 1.0f, size = 2.0f;
    auto renderFloor = [&](bool bumped) {
        auto scene = sceneFromJson(R"({
            "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 10,
                       "resolution": [8, 8]},
            "materials": {"floor": {"type": "diffuse", "color": [0.5, 0.5, 0.5]}},
            "lights": [{"type": "directional", "direction": [0, 0, -1], "irradiance": [1, 1, 1]}],
            "nodes": [{"type": "mesh", "material": "floor",
                       "positions": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]],
                       "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]],
                       "indices": [[0, 1, 2], [0, 2, 3]]}]})");
        if (bumped)
            scene->materials[0].displacement =
                addImageTexture(*scene, 64, [k](float u) { return Vec3(k * u); }, true);
        EmbreeScene accel(*scene);
        RenderOptions o;
        o.mode = "path";
        o.spp = 4;
        return imageMean(render(*scene, accel, o).image);
    };
    Vec3 flat = renderFloor(false), bumped = renderFloor(true);
    const float cosTilt = 1.0f / std::sqrt(1.0f + (k / size) * (k / size));
    INFO("flat " << flat.x << ", bumped " << bumped.x << ", cos " << cosTilt);
    CHECK(flat.x > 0.05f);
    CHECK(bumped.x / flat.x == Approx(cosTilt).epsilon(0.01));
}

TEST_CASE("JSON materials name their displacement and normal-map textures", "[engine][bump]") {
    const std::string base = R"({
        "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "resolution": [4, 4]},
        "textures": {"bumps": {"type": "constant", "value": [0.2, 0.2, 0.2]},
                     "normals": {"type": "constant", "value": [0.5, 0.5, 1]}},
        "materials": {"floor": {"type": "conductor", MATERIAL}},
        "nodes": [{"type": "sphere", "material": "floor", "radius": 1}]})";
    auto withMaterial = [&](const std::string& keys) {
        std::string json = base;
        json.replace(json.find("MATERIAL"), 8, keys);
        return json;
    };
    auto scene = sceneFromJson(withMaterial(R"("displacement": "bumps", "normal_map": "normals")"));
    const Material& m = scene->materials[0];
    CHECK(m.displacement == 0);
    CHECK(m.normalMap == 1);
    try {
        sceneFromJson(withMaterial(R"("displacement": "no-such-texture")"));
        FAIL("an unknown texture name was accepted");
    } catch (const std::exception& e) {
        std::string what = e.what();
        CHECK(what.find("/materials/floor/displacement") != std::string::npos);
        CHECK(what.find("no-such-texture") != std::string::npos);
    }
}
