// Degenerate input and energy: no NaN or Inf reaches the film in any mode, nothing crashes, and
// a furnace at albedo 0.99 converges to its closed form without blowing up.
#include "stress/stress_scenes.h"

#include <limits>

namespace rayproc::test::stress {

namespace {

const char* const kAllModes[] = {"preview", "raytrace", "path", "gi"};

void checkClean(const RenderResult& r, const std::string& label) {
    INFO(label << ": invalid samples " << r.stats.totals.invalidSamples);
    CHECK(allFinite(r.image));
    CHECK(r.stats.totals.invalidSamples == 0);
    for (float v : r.image.pixels) {
        if (!(v >= 0)) {
            FAIL_CHECK(label << ": negative pixel " << v);
            break;
        }
    }
}

Shape& addSphere(SceneBuilder& b, Vec3 c, float r, int mat) {
    auto n = std::make_unique<Node>();
    n->kind = Node::Kind::Shape;
    n->shape.type = ShapeType::Sphere;
    n->shape.center = c;
    n->shape.radius = r;
    n->shape.material = mat;
    b.scene->root->children.push_back(std::move(n));
    return b.scene->root->children.back()->shape;
}

Shape& addDisk(SceneBuilder& b, Vec3 c, float r, Vec3 normal, int mat) {
    Shape& s = addSphere(b, c, r, mat);
    s.type = ShapeType::Disk;
    s.normal = normal;
    return s;
}

// Every degenerate case of the issue in one scene, in front of a lit back wall.
std::unique_ptr<Scene> degenerateScene(bool cameraInside) {
    SceneBuilder b;
    int white = b.material(MaterialType::Diffuse, Vec3(1.0f));
    int black = b.material(MaterialType::Diffuse, Vec3(0.0f));
    int grey = b.material(MaterialType::Diffuse, Vec3(0.5f));
    int glassIor1 = b.material(MaterialType::Dielectric, Vec3(1.0f), 1.0f);
    int glossy0 = b.material(MaterialType::Glossy, Vec3(0.9f), 1.5f, 0.0f);
    int glossy1 = b.material(MaterialType::Glossy, Vec3(0.9f), 1.5f, 1.0f);
    int mirror = b.material(MaterialType::Mirror, Vec3(1.0f));

    b.addFloor(-2, 2, -1, 2, grey);
    b.addBox({-2, -1, -2.2f}, {2, 2, -2}, white); // back wall
    // Zero-area triangles: coincident vertices, collinear vertices; a needle 1e-30 wide.
    b.addMesh({{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {-1, 0, 0}, {0, 0, 0}, {1, 0, 0},
               {-0.5f, 0.5f, 0}, {0.5f, 0.5f, 0}, {0, 0.5f + 1e-30f, 0}},
              {0, 1, 2, 3, 4, 5, 6, 7, 8}, grey);
    // Shading normals: zero-length, NaN, and opposite to the winding.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    b.addMesh({{-1.5f, -0.5f, -1}, {-0.5f, -0.5f, -1}, {-1, 0.5f, -1}},
              {0, 1, 2}, white, {{0, 0, 0}, {nan, nan, nan}, {0, 0, -1}});
    // Lights: a zero-area emissive triangle, a zero-radius sphere and disk, a zero-power
    // emitter, a point light of zero intensity, and one real light.
    b.addMesh({{0, 1.5f, 0}, {0, 1.5f, 0}, {0.1f, 1.5f, 0}}, {0, 1, 2}, black).emission = Vec3(5.0f);
    addSphere(b, {1, 1, -1}, 0.0f, black).emission = Vec3(5.0f);
    addDisk(b, {-1, 1, -1}, 0.0f, {0, -1, 0}, black).emission = Vec3(5.0f);
    b.addMesh({{-0.2f, 1.9f, -0.2f}, {0.2f, 1.9f, -0.2f}, {0, 1.9f, 0.2f}}, {0, 2, 1}, black).emission = Vec3(0.0f);
    b.addMesh({{-0.5f, 1.95f, -1}, {0.5f, 1.95f, -1}, {0, 1.95f, 0}}, {0, 2, 1}, black).emission = Vec3(8.0f);
    Light dark;
    dark.position = {0, 1, 1};
    dark.intensity = Vec3(0.0f);
    b.scene->lights.push_back(dark);
    // Materials at their limits.
    addSphere(b, {-1.2f, -0.5f, -0.5f}, 0.4f, glassIor1);
    addSphere(b, {-0.4f, -0.5f, -0.5f}, 0.3f, glossy0);
    addSphere(b, {0.4f, -0.5f, -0.5f}, 0.3f, glossy1);
    addSphere(b, {1.2f, -0.5f, -0.5f}, 0.3f, black);
    addSphere(b, {0.8f, 0.4f, -0.8f}, 0.3f, mirror);
    b.addBox({1.3f, 0.2f, -1.2f}, {1.8f, 0.6f, -0.8f}, white);

    Camera& c = b.scene->camera;
    c.position = cameraInside ? Vec3(1.55f, 0.4f, -1.0f) : Vec3(0, 0.3f, 3);
    c.lookAt = cameraInside ? Vec3(0, 0.4f, -1.0f) : Vec3(0, 0, 0);
    c.fovY = 50;
    c.width = c.height = 32;
    return b.take(Frame::make(1.0, {}, false));
}

} // namespace

TEST_CASE("Degenerate geometry, lights and materials put no NaN or Inf on the film",
          "[stress][degenerate]") {
    for (bool inside : {false, true}) {
        auto scene = degenerateScene(inside);
        EmbreeScene accel(*scene);
        for (const char* mode : kAllModes) {
            for (int width : {1, 16}) {
                RenderResult r = renderStress(*scene, accel, mode, 4, 7, 2, width);
                checkClean(r, std::string(mode) + (inside ? ", camera inside a box" : "") +
                                  ", packet width " + std::to_string(width));
            }
        }
        // Outside, the real light is seen: the scene is not trivially black. Inside the
        // closed box it is black, as it must be.
        RenderResult r = renderStress(*scene, accel, "path", 4, 7);
        CHECK((meanValue(r.image) > 0) != inside);
    }
}

TEST_CASE("A furnace at albedo 0.99 converges to Le / (1 - a) without blowing up",
          "[stress][energy]") {
    // The camera inside a closed box whose walls emit Le = 0.01 and reflect 0.99: with a
    // maximum depth D, the path estimate converges to Le (1 - a^(D+1)) / (1 - a).
    SceneBuilder b;
    int wall = b.material(MaterialType::Diffuse, Vec3(0.99f));
    b.addBox({-1, -1, -1}, {1, 1, 1}, wall).emission = Vec3(0.01f);
    b.scene->root->children.back()->shape.twoSided = true;
    b.scene->camera.position = {0, 0, 0};
    b.scene->camera.lookAt = {0, 0, -1};
    b.scene->camera.fovY = 60;
    b.scene->camera.width = b.scene->camera.height = 16;
    auto scene = b.take(Frame::make(1.0, {}, false));
    EmbreeScene accel(*scene);

    RenderOptions o;
    o.mode = "path";
    o.spp = 64;
    o.maxDepth = 255;
    RenderResult r = render(*scene, accel, o);
    checkClean(r, "path furnace");
    double expected = 0.01 * (1 - std::pow(0.99, 256)) / 0.01;
    PixelStats st = pixelStats(r.image, 0);
    INFO("mean " << st.mean << " expected " << expected << " standard error " << st.stdError
                 << " max pixel " << st.max);
    CHECK(std::abs(st.mean - expected) <= 0.03 * expected);
    CHECK(st.max <= 3 * expected);
    CHECK(st.stdError <= 0.01 * expected);
    CHECK(r.stats.totals.clampedSamples == 0);

    // gi and raytrace on the same furnace: finite, no invalid samples.
    for (const char* mode : kAllModes) checkClean(renderStress(*scene, accel, mode, 4, 3), mode);
}

} // namespace rayproc::test::stress
