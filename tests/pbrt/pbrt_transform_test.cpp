// pbrt's transformation semantics: CTM = CTM * M for every directive, counter-clockwise Rotate,
// column-by-column Transform, attribute scopes, named coordinate systems, baked meshes with
// pbrt's front sides, and the camera conversion with and without pbrt's handedness flip.
#include "pbrt_test_util.h"

#include "scene/pbrt/pbrt_transform.h"

using namespace rayproc;
using namespace rayproc::pbrt;
using namespace rayproc::test;

namespace {

bool near(const Vec3& a, const Vec3& b, float eps = 1e-5f) {
    return length(a - b) < eps;
}

// The world-space centre and radius of the only sphere of a world snippet.
std::pair<Vec3, float> sphereOf(const std::string& world) {
    auto r = loadWorld(world);
    auto shapes = rootShapes(*r.scene);
    REQUIRE(shapes.size() == 1);
    const Shape& s = *shapes[0].shape;
    return {shapes[0].transform.point(s.center), s.radius};
}

} // namespace

TEST_CASE("Mat4: Rotate is counter-clockwise, LookAt maps the eye to the origin and the target "
          "to +z",
          "[pbrt]") {
    Vec3d p = Mat4::rotate(90, 0, 0, 1).point({1, 0, 0});
    CHECK(near(p.toFloat(), {0, 1, 0}));
    p = Mat4::rotate(90, 1, 0, 0).point({0, 1, 0});
    CHECK(near(p.toFloat(), {0, 0, 1}));

    Mat4 camFromWorld;
    REQUIRE(Mat4::lookAt({0, 1, 6.8}, {0, 1, 0}, {0, 1, 0}, camFromWorld));
    CHECK(near(camFromWorld.point({0, 1, 6.8}).toFloat(), {0, 0, 0}));
    CHECK(near(camFromWorld.point({0, 1, 0}).toFloat(), {0, 0, 6.8f}));
    // pbrt's camera x is cross(up, dir): looking down -z, world -x is the camera's +x.
    CHECK(near(camFromWorld.vector({-1, 0, 0}).toFloat(), {1, 0, 0}));
    CHECK(camFromWorld.det3() == Approx(1.0));
    CHECK_FALSE(Mat4::lookAt({0, 0, 0}, {0, 1, 0}, {0, 1, 0}, camFromWorld));

    Mat4 inv, m = Mat4::translate(1, 2, 3) * Mat4::rotate(30, 1, 1, 0) * Mat4::scale(2, 3, 4);
    REQUIRE(m.inverse(inv));
    Mat4 id = m * inv;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) CHECK(id.m[i][j] == Approx(i == j ? 1.0 : 0.0).margin(1e-12));
    const double cols[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 7, 8, 9, 1};
    CHECK(near(Mat4::fromPbrt(cols).point({0, 0, 0}).toFloat(), {7, 8, 9}));
}

TEST_CASE("Every transform directive post-multiplies the CTM", "[pbrt]") {
    CHECK(near(sphereOf("Translate 1 2 3\nShape \"sphere\"").first, {1, 2, 3}));
    // Rotate then Translate: the translation applies first (in the rotated frame).
    CHECK(near(sphereOf("Rotate 90 0 0 1\nTranslate 1 0 0\nShape \"sphere\"").first, {0, 1, 0}));
    CHECK(near(sphereOf("Translate 1 0 0\nRotate 90 0 0 1\nShape \"sphere\"").first, {1, 0, 0}));
    auto [c, r] = sphereOf("Scale 2 2 2\nTranslate 1 0 0\nShape \"sphere\" \"float radius\" 0.5");
    CHECK(near(c, {2, 0, 0}));
    CHECK(r == Approx(1.0f));
    // ConcatTransform multiplies on the right; Transform replaces; both list columns.
    CHECK(near(sphereOf("Translate 1 0 0\nConcatTransform [1 0 0 0 0 1 0 0 0 0 1 0 0 5 0 1]\n"
                        "Shape \"sphere\"")
                   .first,
               {1, 5, 0}));
    CHECK(near(sphereOf("Translate 1 0 0\nTransform [2 0 0 0 0 2 0 0 0 0 2 0 0 5 0 1]\n"
                        "Shape \"sphere\"")
                   .first,
               {0, 5, 0}));
    CHECK(near(sphereOf("Translate 1 0 0\nTransform 1 0 0 0 0 1 0 0 0 0 1 0 3 0 0 1\n"
                        "Shape \"sphere\"")
                   .first,
               {3, 0, 0}));
    CHECK(near(sphereOf("Translate 1 0 0\nIdentity\nShape \"sphere\"").first, {0, 0, 0}));
    CHECK(near(sphereOf("AttributeBegin\nTranslate 1 0 0\nAttributeEnd\nShape \"sphere\"").first,
               {0, 0, 0}));
    CHECK(near(sphereOf("Translate 4 0 0\nCoordinateSystem \"here\"\nIdentity\n"
                        "CoordSysTransform \"here\"\nShape \"sphere\"")
                   .first,
               {4, 0, 0}));
}

TEST_CASE("CoordSysTransform \"camera\" places shapes in the camera's space", "[pbrt]") {
    // The camera sits at z = 5 looking at the origin (kPbrtHeader); one unit in front of it is
    // z = 4.
    auto r = loadWorld("CoordSysTransform \"camera\"\nTranslate 0 0 1\nShape \"sphere\"\n");
    auto shapes = rootShapes(*r.scene);
    REQUIRE(shapes.size() == 1);
    CHECK(near(shapes[0].transform.point(shapes[0].shape->center), {0, 0, 4}));
}

TEST_CASE("A non-uniformly scaled sphere keeps its transform in a group, similar ones are baked",
          "[pbrt]") {
    auto r = loadWorld("Scale 1 2 1\nShape \"sphere\"\nShape \"disk\"\nIdentity\n"
                       "Rotate 30 0 1 0\nScale 3 3 3\nShape \"disk\" \"float height\" 1\n");
    const Node& root = *r.scene->root;
    REQUIRE(root.children.size() == 2);
    REQUIRE(root.children[0]->kind == Node::Kind::Group); // both shapes share one group
    CHECK(root.children[0]->children.size() == 2);
    CHECK(root.children[0]->transform.m[1][1] == 2.0f);
    const Shape& disk = root.children[1]->shape;
    CHECK(disk.radius == Approx(3.0f));
    float s = std::sin(30 * kPi / 180), c = std::cos(30 * kPi / 180);
    CHECK(near(disk.center, {3 * s, 0, 3 * c}));
    CHECK(near(disk.normal, {s, 0, c}));
}

TEST_CASE("Meshes are baked with pbrt's front sides", "[pbrt]") {
    const std::string tri = "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]";
    auto frontOf = [](const LoadedPbrt& r) {
        const TriangleMesh& m = *rootShapes(*r.scene)[0].shape->mesh;
        const auto& P = m.positions;
        const auto& i = m.indices;
        return normalize(cross(P[i[1]] - P[i[0]], P[i[2]] - P[i[0]]));
    };
    auto plain = loadWorld(tri + "\n");
    CHECK(near(frontOf(plain), {0, 0, 1}));
    auto moved = loadWorld("Translate 0 0 2\n" + tri + "\n");
    CHECK(rootShapes(*moved.scene)[0].shape->mesh->positions[0] == Vec3(0, 0, 2));
    // A mirroring transform keeps the front on the mirrored side, as pbrt's handedness flip.
    auto mirrored = loadWorld("Scale 1 1 -1\n" + tri + "\n");
    CHECK(near(frontOf(mirrored), {0, 0, -1}));
    auto reversed = loadWorld("ReverseOrientation\n" + tri + "\n");
    CHECK(near(frontOf(reversed), {0, 0, -1}));
    // With normals, the front is the side the normals face.
    auto withN = loadWorld(tri + " \"normal N\" [0 0 -1 0 0 -1 0 0 -1]\n");
    CHECK(near(frontOf(withN), {0, 0, -1}));
    const TriangleMesh& m = *rootShapes(*withN.scene)[0].shape->mesh;
    CHECK(m.normals.size() == 3);
    auto rotatedN = loadWorld("Rotate 90 1 0 0\n" + tri + " \"normal N\" [0 0 1 0 0 1 0 0 1]\n");
    CHECK(near(rootShapes(*rotatedN.scene)[0].shape->mesh->normals[0], {0, -1, 0}));
}

TEST_CASE("The camera: position, view direction, up and fov from LookAt", "[pbrt]") {
    auto r = loadPbrt("Scale -1 1 1\nLookAt 0 1 6.8  0 1 0  0 1 0\n"
                      "Camera \"perspective\" \"float fov\" 19.5\nWorldBegin\nShape \"sphere\"\n");
    const Camera& c = r.scene->camera;
    CHECK(c.position == Vec3(0, 1, 6.8f));
    CHECK(near(normalize(c.lookAt - c.position), {0, 0, -1}));
    CHECK(near(c.up, {0, 1, 0}));
    CHECK(c.fovY == 19.5f);
    CHECK(c.apertureRadius == 0.0f);
    // No mirror needed: the sphere stays where the file put it.
    CHECK(rootShapes(*r.scene)[0].shape->center == Vec3(0, 0, 0));

    auto lens = loadPbrt("LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\" \"float lensradius\" "
                         "0.1 \"float focaldistance\" 4\nWorldBegin\nShape \"sphere\"\n");
    CHECK(lens.scene->camera.apertureRadius == Approx(0.1f));
    CHECK(lens.scene->camera.focusDistance == Approx(4.0f));
}

TEST_CASE("A plain LookAt mirrors the world about the camera's vertical plane", "[pbrt]") {
    // pbrt's plain LookAt from +z shows world -x on the right; rayproc's camera shows +x there,
    // so the importer mirrors the world about the plane x = 0 (through the eye, holding the view
    // direction and up). The camera itself does not change.
    auto r = loadPbrt("LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
                      "Translate 1 2 0\nShape \"sphere\"\nLightSource \"point\" \"point3 from\" "
                      "[3 0 0]\nLightSource \"spot\" \"point3 from\" [0 0 0] \"point3 to\" "
                      "[1 0 0]\n");
    CHECK(rootShapes(*r.scene)[0].shape->center == Vec3(-1, 2, 0));
    REQUIRE(r.scene->lights.size() == 2);
    CHECK(near(r.scene->lights[0].position, {-4, 2, 0}));
    CHECK(near(r.scene->lights[1].direction, {-1, 0, 0}));
    CHECK(r.scene->camera.position == Vec3(0, 0, 5));

    // The same with pbrt's default camera (no Camera directive: at the origin, looking +z).
    auto d = loadPbrt("WorldBegin\nTranslate 1 0 3\nShape \"sphere\"\n");
    CHECK(d.scene->camera.position == Vec3(0, 0, 0));
    CHECK(near(normalize(d.scene->camera.lookAt - d.scene->camera.position), {0, 0, 1}));
    CHECK(d.scene->camera.fovY == Approx(90.0f)); // 1280x720: fov is vertical
    CHECK(rootShapes(*d.scene)[0].shape->center == Vec3(-1, 0, 3));
}
