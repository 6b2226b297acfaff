// OBJ files: merging, compact indices, attributes kept only when complete, and the OBJ node.
#include "scene/obj_loader.h"
#include "scene_test_files.h"

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("An OBJ quad becomes two triangles over four positions", "[scene][obj]") {
    std::string path = writeTestFile("meshes/quad.obj", "# a unit quad\n"
                                                        "mtllib missing.mtl\n"
                                                        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                                        "v 9 9 9\n" // unused
                                                        "usemtl nothing\n"
                                                        "f 1 2 3 4\n");
    TriangleMesh m = loadObjMesh(path);
    CHECK(m.triangleCount() == 2);
    CHECK(m.positions.size() == 4); // the unused vertex is dropped
    CHECK(m.normals.empty());
    CHECK(m.uvs.empty());
    Bounds3 b = m.bounds();
    CHECK(b.hi.x == 1.0f);
    CHECK(b.hi.z == 0.0f);
}

TEST_CASE("OBJ shapes merge - negative indices resolve", "[scene][obj]") {
    std::string path = writeTestFile("meshes/two.obj", "o first\n"
                                                       "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                                       "f -3 -2 -1\n"
                                                       "o second\n"
                                                       "v 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
                                                       "f 4 5 7 6\n"
                                                       "g shared\n"
                                                       "f 1 2 4\n");
    TriangleMesh m = loadObjMesh(path);
    CHECK(m.triangleCount() == 4);
    CHECK(m.positions.size() == 7);
    for (std::uint32_t i : m.indices) CHECK(i < m.positions.size());
}

TEST_CASE("OBJ normals and uvs survive only when every corner has them", "[scene][obj]") {
    // Two triangles sharing an edge; vertex 1 has a different uv on each: it splits.
    std::string full = writeTestFile("meshes/full.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                                        "vt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n"
                                                        "vn 0 0 2\n"
                                                        "f 1/1/1 2/2/1 3/3/1\n"
                                                        "f 2/2/1 4/4/1 1/4/1\n");
    TriangleMesh m = loadObjMesh(full);
    CHECK(m.triangleCount() == 2);
    CHECK(m.positions.size() == 5);
    REQUIRE(m.normals.size() == 5);
    REQUIRE(m.uvs.size() == 5);
    CHECK(m.normals[0].z == 1.0f); // normalised
    CHECK(m.uvs[1].x == 1.0f);

    std::string partial = writeTestFile("meshes/partial.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                                              "vn 0 0 1\n"
                                                              "f 1//1 2//1 3//1\n"
                                                              "f 2 4 3\n");
    TriangleMesh p = loadObjMesh(partial);
    CHECK(p.triangleCount() == 2);
    CHECK(p.positions.size() == 4);
    CHECK(p.normals.empty());
}

TEST_CASE("Broken OBJ files are input errors", "[scene][obj]") {
    std::string missing = (sceneTestDir() / "meshes" / "nope.obj").string();
    CHECK_THROWS_AS(loadObjMesh(missing), InputError);
    std::string empty = writeTestFile("meshes/empty.obj", "");
    CHECK_THROWS_WITH(loadObjMesh(empty), Catch::Matchers::Contains("no faces"));
    std::string outOfRange =
        writeTestFile("meshes/range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                          "f 1 2 3 40\nf -9 1 2\n");
    CHECK_THROWS_AS(loadObjMesh(outOfRange), InputError);
}

TEST_CASE("OBJ nodes resolve against the scene folder and share their mesh", "[scene][obj]") {
    writeTestFile("meshes/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    std::string path = writeTestFile("sub/objscene.json", R"({
        "materials": {"m": {"type": "diffuse"}},
        "nodes": [{"type": "obj", "material": "m", "file": "../meshes/tri.obj"},
                  {"type": "obj", "material": "m", "file": "../meshes/../meshes/tri.obj",
                   "transform": {"translate": [0, 0, 1]}}]})");
    auto scene = loadScene(path);
    const auto& n = scene->root->children;
    REQUIRE(n.size() == 2);
    const Shape& a = n[0]->shape;
    const Shape& b = n[1]->children.at(0)->shape;
    CHECK(a.mesh->triangleCount() == 1);
    CHECK(a.mesh == b.mesh);
    CHECK_FALSE(a.isQuad);
}

TEST_CASE("The torus of materials.json keeps normals and uvs", "[scene][obj]") {
    TriangleMesh m = loadObjMesh((sourceScenes() / "meshes" / "torus.obj").string());
    CHECK(m.triangleCount() == 24 * 12 * 2);
    CHECK(m.normals.size() == m.positions.size());
    CHECK(m.uvs.size() == m.positions.size());
    CHECK(m.positions.size() == 25 * 13); // the seams split
}

TEST_CASE("OBJ statements are read strictly: bad numbers, missing values and wild indices",
          "[scene][obj]") {
    struct Case {
        const char* body;
        const char* message; // part of the error, with the line number
    };
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    const Case cases[] = {
        {"v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", ":1: 'nan' is not a finite"},
        {"v 0 0 0\nv abc 0 0\nv 0 1 0\nf 1 2 3\n", ":2: 'abc' is not a number"},
        {"v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", ":2: a vertex (v) needs 3 coordinates"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 1e39\nf 1 2 3\n", ":3: '1e39' is not a finite"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0x\nf 1 2 3\n", ":3: '0x' is not a number"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0\nf 1 2 3\n", ":4: a normal (vn) needs 3"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt inf 0\nf 1 2 3\n", ":4: 'inf' is not a finite"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4294967299\n", ":4: vertex index 4294967299 is out"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n", ":4: vertex index"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", ":4: vertex index 0 is out of range"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3.5\n", ":4: '3.5' is not an integer vertex"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", ":4: vertex index -4 reaches before"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", ":4: a face (f) needs at least 3 corners"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n", ":4: 'x' is not an integer texture"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1/ 2 3\n", ":4: the face corner '1//1/'"},
    };
    int n = 0;
    for (const Case& c : cases) {
        INFO(c.body);
        std::string path = writeTestFile("meshes/strict" + std::to_string(n++) + ".obj", c.body);
        CHECK_THROWS_WITH(loadObjMesh(path), Catch::Matchers::Contains(path) &&
                                                 Catch::Matchers::Contains(c.message));
    }
    // What the strict reading still accepts: w, vertex colours, 1- and 3-value uvs, tabs, CRLF,
    // comments, relative and forward indices, tiny numbers that underflow.
    std::string fine = writeTestFile("meshes/lenient.obj",
                                     "# comment\r\nv 0 0 0 1\r\nv\t1 0 0 0.5 0.5 0.5\r\n"
                                     "v 0 1 1e-50\r\nvt 0.5\nvt 0 1 0\nf 1/1 2/2 -1/1\n"
                                     "f 1 2 4\nv 1 1 0\n");
    TriangleMesh m = loadObjMesh(fine);
    CHECK(m.triangleCount() == 2);
    CHECK(m.positions.size() == 4);
    CHECK(m.positions[2].z == 0.0f);
}
