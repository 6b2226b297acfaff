// The scene loader on good input: the scene files in scenes/, the Cornell box figure by
// figure, transforms, instances and prototypes, shapes and defaults.
#include "scene_test_files.h"

#include "scene/metals.h"

#include <map>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// Shape leaves and triangles of the tree, counting each placement of an instance.
struct Counts {
    std::size_t shapes = 0, triangles = 0, emissive = 0;
};

void count(const Node& n, Counts& c) {
    switch (n.kind) {
    case Node::Kind::Shape:
        ++c.shapes;
        if (n.shape.mesh) c.triangles += n.shape.mesh->triangleCount();
        if (n.shape.isEmissive()) ++c.emissive;
        break;
    case Node::Kind::Group:
        for (const auto& child : n.children) count(*child, c);
        break;
    case Node::Kind::Instance:
        for (const auto& child : n.prototype->children) count(*child, c);
        break;
    }
}

Counts countScene(const Scene& s) {
    Counts c;
    count(*s.root, c);
    return c;
}

std::unique_ptr<Scene> loadText(const std::string& name, const std::string& text) {
    return loadScene(writeTestFile(name, text));
}

std::string withNodes(const std::string& nodes) {
    return std::string("{") + kOneMaterial + R"(, "nodes": )" + nodes + "}";
}

void checkVec(const Vec3& a, const Vec3& b, double margin = 1e-5) {
    CHECK(a.x == Approx(b.x).margin(margin));
    CHECK(a.y == Approx(b.y).margin(margin));
    CHECK(a.z == Approx(b.z).margin(margin));
}

} // namespace

TEST_CASE("Every scene in scenes/ loads", "[scene]") {
    std::size_t loaded = 0;
    for (const auto& entry : std::filesystem::directory_iterator(sourceScenes())) {
        if (entry.path().extension() != ".json") continue;
        INFO("scene: " << entry.path());
        auto scene = loadScene(entry.path().string());
        REQUIRE(scene->root);
        Bounds3 b = scene->worldBounds();
        CHECK(!b.empty());
        CHECK(isFinite(b.lo));
        CHECK(isFinite(b.hi));
        CHECK(countScene(*scene).shapes > 0);
        ++loaded;
    }
    CHECK(loaded >= 5);
}

TEST_CASE("The Cornell box has exactly its figures", "[scene]") {
    auto scene = loadScene((sourceScenes() / "cornell-box.json").string());
    Counts c = countScene(*scene);
    CHECK(c.shapes == 8);
    CHECK(c.triangles == 36);
    CHECK(c.emissive == 1);
    CHECK(scene->lights.empty());
    CHECK(scene->prototypes.empty());

    std::map<MaterialType, int> byType;
    for (const Material& m : scene->materials) ++byType[m.type];
    CHECK(scene->materials.size() == 8);
    CHECK(byType[MaterialType::Diffuse] == 8);
    CHECK(scene->findMaterial("LeftWall") >= 0);
    checkVec(scene->materials[scene->findMaterial("RightWall")].color, {0.14f, 0.45f, 0.091f}, 0);

    // The render block is left to the CLI.
    CHECK(scene->render.mode.empty());
    CHECK(scene->render.spp == 0);

    const Camera& cam = scene->camera;
    checkVec(cam.position, {0, 1, 6.8f}, 0);
    checkVec(cam.lookAt, {0, 1, 0}, 0);
    CHECK(cam.fovY == 19.5f);
    CHECK(cam.width == 512);
    CHECK(cam.height == 512);

    Bounds3 b = scene->worldBounds();
    checkVec(b.lo, {-1, 0, -1}, 1e-6);
    checkVec(b.hi, {1, 2, 1}, 1e-6);

    // The light faces down, into the box.
    const Shape* light = nullptr;
    for (const auto& n : scene->root->children)
        if (n->kind == Node::Kind::Shape && n->shape.isEmissive()) light = &n->shape;
    REQUIRE(light);
    CHECK(light->isQuad);
    CHECK_FALSE(light->twoSided);
    checkVec(light->emission, {17, 12, 4}, 0);
    const auto& p = light->mesh->positions;
    Vec3 n = normalize(cross(p[1] - p[0], p[2] - p[0]));
    checkVec(n, {0, -1, 0});
    CHECK(scene->materials[light->material].color == Vec3(0.0f));
}

TEST_CASE("The Cornell box with spheres has a mirror and a glass sphere", "[scene]") {
    auto scene = loadScene((sourceScenes() / "cornell-spheres.json").string());
    Counts c = countScene(*scene);
    CHECK(c.shapes == 8);
    CHECK(c.triangles == 12);
    int spheres = 0;
    for (const auto& n : scene->root->children) {
        if (n->kind != Node::Kind::Shape || n->shape.type != ShapeType::Sphere) continue;
        ++spheres;
        CHECK(n->shape.radius == 0.33f);
        MaterialType t = scene->materials[n->shape.material].type;
        CHECK((t == MaterialType::Mirror || t == MaterialType::Dielectric));
    }
    CHECK(spheres == 2);
}

TEST_CASE("Transforms are T * R * S, from an object or a matrix", "[scene]") {
    auto scene = loadText("xf.json", withNodes(R"([
        {"type": "group", "transform": {"translate": [1, 2, 3],
            "rotate": {"angle": 90, "axis": [0, 0, 1]}, "scale": [2, 1, 1]},
         "children": [{"type": "sphere", "material": "m", "radius": 1}]},
        {"type": "group", "transform": [0, -1, 0, 1,  2, 0, 0, 2,  0, 0, 1, 3,  0, 0, 0, 1],
         "children": [{"type": "sphere", "material": "m", "radius": 1}]},
        {"type": "group", "transform": [0, -1, 0, 1,  2, 0, 0, 2,  0, 0, 1, 3],
         "children": [{"type": "sphere", "material": "m", "radius": 1}]},
        {"type": "group", "transform": {"rotate": [{"angle": 90, "axis": [0, 0, 1]},
                                                   {"angle": 90, "axis": [1, 0, 0]}]},
         "children": [{"type": "sphere", "material": "m", "radius": 1}]},
        {"type": "group", "transform": {"scale": 3},
         "children": [{"type": "sphere", "material": "m", "radius": 1}]}])"));
    const auto& nodes = scene->root->children;
    // Scale first: (1,0,0) -> (2,0,0) -> rotated to (0,2,0) -> translated to (1,4,3).
    checkVec(nodes[0]->transform.point({1, 0, 0}), {1, 4, 3});
    checkVec(nodes[1]->transform.point({1, 0, 0}), {1, 4, 3});
    checkVec(nodes[2]->transform.point({1, 0, 0}), {1, 4, 3});
    // Rotations act in the order written: z first takes x to y, then x takes y to z.
    checkVec(nodes[3]->transform.point({1, 0, 0}), {0, 0, 1});
    checkVec(nodes[4]->transform.point({1, 1, 1}), {3, 3, 3});
    // Bounds follow: the unit sphere, stretched along x, turned onto y, spans x in [1-1, 1+1],
    // y in [2-2, 2+2], z in [3-1, 3+1].
    checkVec(nodes[0]->bounds.lo, {0, 0, 2});
    checkVec(nodes[0]->bounds.hi, {2, 4, 4});
}

TEST_CASE("A shape's own transform becomes a group around it", "[scene]") {
    auto scene = loadText("shapexf.json", withNodes(R"([{"type": "sphere", "name": "ball",
        "material": "m", "center": [1, 0, 0], "radius": 0.5,
        "transform": {"translate": [0, 5, 0]}}])"));
    const Node& g = *scene->root->children[0];
    REQUIRE(g.kind == Node::Kind::Group);
    REQUIRE(g.children.size() == 1);
    const Node& s = *g.children[0];
    CHECK(s.kind == Node::Kind::Shape);
    CHECK(s.shape.name == "ball");
    CHECK(s.transform.isIdentity());
    checkVec(s.shape.center, {1, 0, 0}); // still in the group's space
    checkVec(scene->worldBounds().lo, {0.5f, 4.5f, -0.5f});
}

TEST_CASE("Prototypes come after the prototypes they instance", "[scene]") {
    auto scene = loadText("protos.json", std::string("{") + kOneMaterial + R"(,
        "prototypes": {
          "field": {"children": [
            {"type": "instance", "prototype": "row", "transform": {"translate": [0, 0, 0]}},
            {"type": "instance", "prototype": "row", "transform": {"translate": [0, 0, 10]}}]},
          "row": {"transform": {"scale": 2}, "children": [
            {"type": "instance", "prototype": "tree"},
            {"type": "instance", "prototype": "tree", "transform": {"translate": [3, 0, 0]}}]},
          "unused": {"children": []},
          "tree": {"children": [
            {"type": "sphere", "material": "m", "center": [0, 1, 0], "radius": 1}]}
        },
        "nodes": [{"type": "instance", "name": "the field", "prototype": "field"}]})");
    std::vector<std::string> order;
    for (const auto& p : scene->prototypes) order.push_back(p->name);
    CHECK(order == std::vector<std::string>{"tree", "row", "field", "unused"});

    const Node& inst = *scene->root->children[0];
    CHECK(inst.kind == Node::Kind::Instance);
    CHECK(inst.name == "the field");
    CHECK(inst.prototype == scene->prototypes[2].get());
    // A row spans x in [-1, 4] before its scale of 2; the field places rows at z = 0 and 10.
    checkVec(scene->worldBounds().lo, {-2, 0, -2});
    checkVec(scene->worldBounds().hi, {8, 4, 12});
    CHECK(countScene(*scene).shapes == 4);
}

TEST_CASE("Quads, rectangles, disks and grids", "[scene]") {
    auto scene = loadText("shapes.json", withNodes(R"([
        {"type": "rectangle", "material": "m", "center": [0, 1, 0], "size": [4, 2]},
        {"type": "rectangle", "material": "m", "center": [0, 0, -1], "size": [4, 2],
         "normal": [0, 0, 2]},
        {"type": "rectangle", "material": "m", "size": [1, 1], "normal": [1, 0, 0],
         "up": [0, 0, 1]},
        {"type": "disk", "material": "m", "center": [0, 0, 0], "normal": [0, 3, 0], "radius": 2},
        {"type": "grid", "material": "m", "size": [4, 2], "segments": [4, 3]},
        {"type": "grid", "material": "m", "size": [4, 2], "segments": [2, 2],
         "displace": "waves", "amplitude": 0.5, "frequency": 0.25}])"));
    const auto& n = scene->root->children;
    for (int i = 0; i < 3; ++i) {
        const Shape& r = n[i]->shape;
        CHECK(r.isQuad);
        REQUIRE(r.mesh->positions.size() == 4);
        CHECK(r.mesh->indices == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3});
    }
    auto frontNormal = [](const Shape& s) {
        const auto& p = s.mesh->positions;
        return normalize(cross(p[1] - p[0], p[2] - p[0]));
    };
    checkVec(frontNormal(n[0]->shape), {0, 1, 0});
    checkVec(frontNormal(n[1]->shape), {0, 0, 1});
    checkVec(frontNormal(n[2]->shape), {1, 0, 0});
    // A floor's width runs along x; a wall's height runs along y.
    checkVec(n[0]->bounds.lo, {-2, 1, -1});
    checkVec(n[1]->bounds.lo, {-2, -1, -1});
    checkVec(n[1]->bounds.hi, {2, 1, -1});
    // "up" [0, 0, 1] turns the height of the x-facing rectangle towards z.
    CHECK(n[2]->bounds.diagonal().z == Approx(1));

    CHECK(n[3]->shape.type == ShapeType::Disk);
    checkVec(n[3]->shape.normal, {0, 1, 0});

    const TriangleMesh& grid = *n[4]->shape.mesh;
    CHECK(grid.triangleCount() == 24);
    CHECK(grid.positions.size() == 20);
    CHECK(grid.normals.empty());
    CHECK(grid.uvs.size() == 20);
    checkVec(n[4]->bounds.lo, {-2, 0, -1});
    checkVec(n[4]->bounds.hi, {2, 0, 1});
    const TriangleMesh& waves = *n[5]->shape.mesh;
    CHECK(waves.normals.size() == waves.positions.size());
    // Grid triangles face +y.
    Vec3 g0 = grid.positions[grid.indices[0]], g1 = grid.positions[grid.indices[1]],
         g2 = grid.positions[grid.indices[2]];
    CHECK(cross(g1 - g0, g2 - g0).y > 0);
}

TEST_CASE("Materials, defaults and emitters", "[scene]") {
    auto scene = loadText("mats.json", R"({
        "materials": {"d": {"type": "diffuse"}, "mi": {"type": "mirror"},
                      "g": {"type": "dielectric", "ior": 1.33}, "gl": {"type": "glossy"},
                      "gl2": {"type": "glossy", "roughness": 0.7, "color": [0.5, 0.4, 0.3]}},
        "nodes": [{"type": "sphere", "radius": 1, "emission": [1, 2, 3], "two_sided": true},
                  {"type": "sphere", "radius": 1, "emission": [4, 4, 4], "center": [3, 0, 0]},
                  {"type": "sphere", "radius": 1, "material": "gl2", "emission": [1, 1, 1]}]})");
    const auto& m = scene->materials;
    REQUIRE(m.size() == 6); // the five, then the shared emitter material
    CHECK(m[0].color == Vec3(0.5f));
    CHECK(m[1].type == MaterialType::Mirror);
    CHECK(m[1].color == Vec3(1.0f));
    CHECK(m[2].ior == 1.33f);
    CHECK(m[2].color == Vec3(1.0f));
    CHECK(m[3].roughness == 0.2f);
    CHECK(m[4].roughness == 0.7f);
    CHECK(m[5].name == "__emitter_black");
    CHECK(m[5].color == Vec3(0.0f));
    const auto& n = scene->root->children;
    CHECK(n[0]->shape.material == 5);
    CHECK(n[1]->shape.material == 5);
    CHECK(n[2]->shape.material == 4);
    CHECK(n[0]->shape.twoSided);
    CHECK_FALSE(n[1]->shape.twoSided);
    CHECK(countScene(*scene).emissive == 3);
}

TEST_CASE("Lights, camera and render settings", "[scene]") {
    auto scene = loadText("lights.json", std::string("{") + kOneMaterial + ", " + kOneSphere + R"(,
        "camera": {"position": [1, 2, 3], "look_at": [0, 0, 0], "up": [0, 2, 0], "fov": 30,
                   "resolution": [640, 480], "aperture": 0.1, "focus_distance": 4},
        "render": {"mode": "photon", "spp": 16, "max_depth": 8, "light_samples": 4, "seed": 42},
        "lights": [
          {"type": "point", "name": "bulb", "position": [0, 1.9, 0], "intensity": [5, 5, 5]},
          {"type": "spot", "position": [0, 2, 0], "direction": [0, -2, 0], "intensity": [1, 1, 1],
           "cone_angle": 20, "falloff_angle": 2},
          {"type": "directional", "direction": [0, 0, -3], "irradiance": [3, 3, 3]},
          {"type": "environment", "radiance": [0.2, 0.3, 0.5]}]})");
    const Camera& c = scene->camera;
    CHECK(c.width == 640);
    CHECK(c.height == 480);
    CHECK(c.apertureRadius == 0.1f);
    CHECK(c.focusDistance == 4.0f);
    CHECK(scene->render.mode == "photon");
    CHECK(scene->render.spp == 16);
    CHECK(scene->render.maxDepth == 8);
    CHECK(scene->render.lightSamples == 4);
    CHECK(scene->render.seed == 42);
    const auto& l = scene->lights;
    REQUIRE(l.size() == 4);
    CHECK(l[0].type == LightType::Point);
    CHECK(l[0].name == "bulb");
    CHECK(l[1].type == LightType::Spot);
    checkVec(l[1].direction, {0, -1, 0});
    CHECK(l[1].coneAngle == 20.0f);
    CHECK(l[1].falloffAngle == 2.0f);
    CHECK(l[2].type == LightType::Directional);
    checkVec(l[2].direction, {0, 0, -1});
    checkVec(l[2].intensity, {3, 3, 3});
    CHECK(l[3].type == LightType::Environment);
    checkVec(l[3].intensity, {0.2f, 0.3f, 0.5f});

    // Without a camera block the defaults of scene.h hold.
    auto plain = loadText("nocamera.json", withNodes(R"([{"type": "sphere", "material": "m",
        "radius": 1}])"));
    CHECK(plain->camera.fovY == Camera{}.fovY);
    CHECK(plain->camera.width == Camera{}.width);
}

TEST_CASE("pbrt-v4 materials in JSON: conductor, coateddiffuse, thindielectric, diffusetransmission, mix", "[scene]") {
    auto scene = loadText("pbrt-mats.json", R"({
        "materials": {
            "au": {"type": "conductor", "metal": "Au", "roughness": 0.01},
            "brushed": {"type": "conductor", "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1],
                        "u_roughness": 0.05, "v_roughness": 0.2, "remap_roughness": false},
            "paint": {"type": "conductor", "reflectance": [0.9, 0.5, 0.1]},
            "plastic": {"type": "coateddiffuse", "color": [0.8, 0.1, 0.1], "thickness": 0.02,
                        "samples": 3},
            "film": {"type": "thindielectric", "ior": 1.4},
            "paper": {"type": "diffusetransmission", "transmittance": [0.3, 0.3, 0.3]},
            "rough-glass": {"type": "dielectric", "roughness": 0.1},
            "worn": {"type": "mix", "materials": ["plastic", "au"], "amount": 0.3}},
        "nodes": [{"type": "sphere", "radius": 1, "material": "worn"}]})");
    const auto& m = scene->materials;
    REQUIRE(m.size() == 8);
    Vec3 eta, k;
    REQUIRE(namedMetal("Au", eta, k));
    CHECK(m[0].type == MaterialType::Conductor);
    CHECK(m[0].eta.value == eta);
    CHECK(m[0].k.value == k);
    CHECK(m[0].remapRoughness);
    CHECK(m[1].uRoughness.value == 0.05f);
    CHECK(m[1].vRoughness.value == 0.2f);
    CHECK_FALSE(m[1].remapRoughness);
    CHECK(m[2].useReflectance);
    CHECK(m[2].color == Vec3(0.9f, 0.5f, 0.1f));
    CHECK(m[3].type == MaterialType::CoatedDiffuse);
    CHECK(m[3].thickness.value == 0.02f);
    CHECK(m[3].nSamples == 3);
    CHECK(m[4].type == MaterialType::ThinDielectric);
    CHECK(m[5].color == Vec3(0.25f));
    CHECK(m[5].transmittance.value == Vec3(0.3f));
    CHECK(materialClass(m, 6) == MaterialClass::Glossy);
    CHECK(m[7].mix[0] == 3);
    CHECK(m[7].mix[1] == 0);
    CHECK(m[7].amount.value == 0.3f);
    CHECK(materialClass(m, 7) == MaterialClass::Diffuse);

    checkLoadError("mix-self.json", R"({"materials": {"a": {"type": "mix", "materials": ["a", "a"]}},
        "nodes": [{"type": "sphere", "radius": 1, "material": "a"}]})",
                   "/materials/a/materials", "contains itself");
    checkLoadError("mix-missing.json", R"({"materials": {"a": {"type": "mix", "materials": ["a", "b"]}},
        "nodes": [{"type": "sphere", "radius": 1, "material": "a"}]})",
                   "/materials/a/materials/1", "unknown material \"b\"");
    checkLoadError("metal.json", R"({"materials": {"a": {"type": "conductor", "metal": "Xx"}},
        "nodes": [{"type": "sphere", "radius": 1, "material": "a"}]})",
                   "/materials/a/metal", "unknown metal");
}
