// Every kind of scene-file mistake must be an InputError "<file>: <location>: <problem>" that
// names the JSON pointer (or line and column) and the cause. None may crash.
#include "scene_test_files.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A scene of one material "m" and the given node list.
std::string withNodes(const std::string& nodes) {
    return std::string("{") + kOneMaterial + R"(, "nodes": )" + nodes + "}";
}

// A scene of one material "m", one sphere, and the given extra top-level members.
std::string withSphere(const std::string& extra) {
    return std::string("{") + kOneMaterial + ", " + kOneSphere + ", " + extra + "}";
}

} // namespace

TEST_CASE("Syntax errors give line and column", "[scene]") {
    // Missing comma: the parser stops at the string after "sphere".
    checkLoadError("syntax1.json",
                   "{\n  \"nodes\": [\n    {\"type\": \"sphere\" \"radius\": 1}\n]}",
                   "line 3, column 30", "syntax error");
    checkLoadError("syntax2.json", "{\"nodes\": [1, 2,]}", "line 1, column 17", "syntax error");
    checkLoadError("syntax3.json", "{\n\"nodes\": [\n", "line 3, column 1", "end of input");
    checkLoadError("syntax4.json", "", "line 1, column 1", "end of input");
    checkLoadError("syntax5.json", "{\"nodes\": [nan]}", "line 1, column 13", "syntax error");
}

TEST_CASE("Missing and unreadable scene files are input errors", "[scene]") {
    std::string path = (sceneTestDir() / "does-not-exist.json").string();
    std::string message = loadErrorOf(path);
    CHECK_THAT(message, Catch::Matchers::StartsWith(path + ": ") &&
                            Catch::Matchers::Contains("cannot open"));
    CHECK_THAT(loadErrorOf(sceneTestDir().string()), Catch::Matchers::Contains("directory"));
}

TEST_CASE("Unknown keys list the allowed ones", "[scene]") {
    checkLoadError("unknown1.json", withSphere(R"("node": [])"), "/node",
                   "unknown key \"node\" in the scene; allowed keys: camera, render, textures, materials, "
                   "lights, prototypes, nodes");
    checkLoadError("unknown2.json", withNodes(R"([{"type": "group", "children": [{"type": "sphere",
                       "material": "m", "radius": 1, "radiuss": 2}]}])"),
                   "/nodes/0/children/0/radiuss", "allowed keys: type, name, transform, material");
    // Keys are allowed per material type: "ior" belongs to dielectrics only.
    checkLoadError("unknown3.json",
                   R"({"materials": {"m": {"type": "diffuse", "ior": 1.5}}, )" +
                       std::string(kOneSphere) + "}",
                   "/materials/m/ior", "allowed keys: type, color");
    checkLoadError("unknown4.json", withSphere(R"("camera": {"fov": 40, "zoom": 2})"),
                   "/camera/zoom", "unknown key");
    checkLoadError("unknown5.json", withSphere(R"("render": {"samples": 4})"), "/render/samples",
                   "allowed keys: mode, spp");
    checkLoadError("unknown6.json",
                   withSphere(R"("lights": [{"type": "point", "position": [0, 1, 0],
                       "intensity": [1, 1, 1], "direction": [0, -1, 0]}])"),
                   "/lights/0/direction", "unknown key");
    checkLoadError("unknown7.json", withNodes(R"([{"type": "sphere", "material": "m", "radius": 1,
                       "transform": {"translate": [0, 0, 0], "shear": 1}}])"),
                   "/nodes/0/transform/shear", "allowed keys: translate, rotate, scale");
}

TEST_CASE("Wrong types say what was expected", "[scene]") {
    checkLoadError("type1.json",
                   withNodes(R"([{"type": "sphere", "material": "m", "radius": "1"}])"),
                   "/nodes/0/radius", "expected a number");
    checkLoadError(
        "type2.json",
        withNodes(R"([{"type": "sphere", "material": "m", "radius": 1, "center": [0, 1]}])"),
        "/nodes/0/center", "expected an array of 3 numbers");
    checkLoadError("type3.json", withSphere(R"("camera": {"position": [0, "one", 2]})"),
                   "/camera/position/1", "expected a number");
    checkLoadError("type4.json", withSphere(R"("render": {"spp": 2.5})"), "/render/spp",
                   "expected an integer");
    checkLoadError(
        "type5.json",
        withNodes(R"([{"type": "sphere", "material": "m", "radius": 1, "two_sided": 1}])"),
        "/nodes/0/two_sided", "expected true or false");
    checkLoadError("type6.json", withNodes(R"({"type": "sphere"})"), "/nodes",
                   "expected an array of nodes");
    checkLoadError("type7.json", R"({"materials": [], )" + std::string(kOneSphere) + "}",
                   "/materials", "expected an object");
    checkLoadError("type8.json", "[1, 2]", "/", "expected an object");
    checkLoadError("type9.json", withNodes(R"([{"type": "sphere", "material": 7, "radius": 1}])"),
                   "/nodes/0/material", "expected a string");
}

TEST_CASE("Missing required fields are named", "[scene]") {
    checkLoadError("missing1.json", withNodes(R"([{"type": "sphere", "material": "m"}])"),
                   "/nodes/0", "missing required key \"radius\"");
    checkLoadError("missing2.json", withNodes(R"([{"material": "m", "radius": 1}])"), "/nodes/0",
                   "missing required key \"type\"; node types: group, instance, mesh");
    checkLoadError("missing3.json", withNodes(R"([{"type": "sphere", "radius": 1}])"), "/nodes/0",
                   "missing required key \"material\"");
    checkLoadError("missing4.json",
                   withSphere(R"("lights": [{"type": "point", "position": [0, 1, 0]}])"),
                   "/lights/0", "missing required key \"intensity\"");
    checkLoadError("missing5.json", withNodes(R"([{"type": "mesh", "material": "m",
                       "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}])"),
                   "/nodes/0", "missing required key \"indices\"");
}

TEST_CASE("Non-finite numbers are rejected", "[scene]") {
    // JSON cannot spell NaN or Inf, but 1e999 parses to infinity and 1e39 overflows a float.
    checkLoadError("inf1.json",
                   withNodes(R"([{"type": "sphere", "material": "m", "radius": 1e999}])"),
                   "/nodes/0/radius", "finite");
    checkLoadError("inf2.json", withSphere(R"("camera": {"position": [0, -1e39, 0]})"),
                   "/camera/position/1", "finite");
    checkLoadError("inf3.json", withSphere(R"("render": {"seed": 1e999})"), "/render/seed",
                   "finite");
    checkLoadError("inf4.json", withSphere(R"("lights": [{"type": "point", "position": [0, 1, 0],
                       "intensity": [1, -1e400, 1]}])"),
                   "/lights/0/intensity/1", "-1e400 overflows");
    checkLoadError("inf5.json", withSphere(R"("render": {"seed": 1e30})"), "/render/seed",
                   "out of range");
}

TEST_CASE("Unknown names and types list the known ones", "[scene]") {
    checkLoadError("names1.json",
                   withNodes(R"([{"type": "sphere", "material": "steel", "radius": 1}])"),
                   "/nodes/0/material", "unknown material \"steel\"; known materials: m");
    checkLoadError("names2.json", withNodes(R"([{"type": "cube", "material": "m"}])"),
                   "/nodes/0/type",
                   "unknown node type \"cube\"; known types: group, instance, mesh, obj, quad, "
                   "rectangle, sphere, disk, grid");
    checkLoadError(
        "names3.json",
        R"({"materials": {"m": {"type": "metal"}}, )" + std::string(kOneSphere) + "}",
        "/materials/m/type",
        "unknown material type \"metal\"; known types: diffuse, mirror, dielectric, glossy");
    checkLoadError(
        "names4.json", withSphere(R"("lights": [{"type": "area"}])"), "/lights/0/type",
        "unknown light type \"area\"; known types: point, spot, directional, environment");
    checkLoadError("names5.json", withNodes(R"([{"type": "instance", "prototype": "tree"}])"),
                   "/nodes/0/prototype", "unknown prototype \"tree\"; known prototypes: (none)");
    checkLoadError("names7.json",
                   std::string("{") + kOneMaterial + R"(, "prototypes": {"rock": {}, "bush": {}},
                       "nodes": [{"type": "instance", "prototype": "tree"}]})",
                   "/nodes/0/prototype", "known prototypes: rock, bush");
    checkLoadError("names8.json",
                   R"({"materials": {"__mine": {"type": "diffuse"}}, )" + std::string(kOneSphere) +
                       "}",
                   "/materials/__mine", "reserved");
}

TEST_CASE("Duplicate names are rejected", "[scene]") {
    checkLoadError("dup1.json",
                   R"({"materials": {"m": {"type": "diffuse"}, "m": {"type": "mirror"}}, )" +
                       std::string(kOneSphere) + "}",
                   "/materials/m", "duplicate material name \"m\"");
    checkLoadError("dup2.json", withSphere(R"("prototypes": {"tree": {}, "tree": {}})"),
                   "/prototypes/tree", "duplicate prototype name \"tree\"");
    checkLoadError("dup3.json",
                   withNodes(R"([{"type": "sphere", "material": "m", "radius": 1, "radius": 2}])"),
                   "/nodes/0/radius", "duplicate key \"radius\"");
}

TEST_CASE("OBJ files must exist and have faces", "[scene]") {
    std::string resolved = (sceneTestDir() / "meshes" / "missing.obj").string();
    checkLoadError("obj1.json",
                   withNodes(R"([{"type": "obj", "material": "m", "file": "meshes/missing.obj"}])"),
                   "/nodes/0/file", "OBJ file not found: " + resolved);
    writeTestFile("meshes/nofaces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    checkLoadError("obj2.json",
                   withNodes(R"([{"type": "obj", "material": "m", "file": "meshes/nofaces.obj"}])"),
                   "/nodes/0/file", "no faces");
    writeTestFile("meshes/badindex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    checkLoadError(
        "obj3.json",
        withNodes(R"([{"type": "obj", "material": "m", "file": "meshes/badindex.obj"}])"),
        "/nodes/0/file", "badindex.obj");
}

TEST_CASE("Mesh indices must be in range and come in threes", "[scene]") {
    const std::string tri = R"("positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]])";
    checkLoadError("mesh1.json",
                   withNodes(R"([{"type": "mesh", "material": "m", )" + tri +
                             R"(, "indices": [[0, 1, 2], [0, 1, 3]]}])"),
                   "/nodes/0/indices/1/2", "index 3 out of range");
    checkLoadError("mesh2.json",
                   withNodes(R"([{"type": "mesh", "material": "m", )" + tri +
                             R"(, "indices": [0, 1, 2, 0]}])"),
                   "/nodes/0/indices", "triangle index count 4 is not a multiple of 3");
    checkLoadError(
        "mesh3.json",
        withNodes(R"([{"type": "mesh", "material": "m", )" + tri + R"(, "indices": [0, 1, -1]}])"),
        "/nodes/0/indices/2", "out of range");
    checkLoadError(
        "mesh4.json",
        withNodes(R"([{"type": "mesh", "material": "m", )" + tri + R"(, "indices": [[0, 1]]}])"),
        "/nodes/0/indices/0", "expected an array of 3 integers");
    checkLoadError("mesh5.json",
                   withNodes(R"([{"type": "mesh", "material": "m", )" + tri +
                             R"(, "indices": [0, 1, 2], "normals": [[0, 0, 1]]}])"),
                   "/nodes/0/normals", "one per position");
}

TEST_CASE("Negative and zero sizes are rejected where meaningless", "[scene]") {
    checkLoadError("size1.json",
                   withNodes(R"([{"type": "sphere", "material": "m", "radius": -1}])"),
                   "/nodes/0/radius", "negative");
    checkLoadError("size2.json", withNodes(R"([{"type": "disk", "material": "m", "radius": 0}])"),
                   "/nodes/0/radius", "zero");
    checkLoadError("size3.json",
                   withNodes(R"([{"type": "rectangle", "material": "m", "size": [0, 1]}])"),
                   "/nodes/0/size/0", "positive");
    checkLoadError("size4.json", withNodes(R"([{"type": "quad", "material": "m",
                       "corners": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]]}])"),
                   "/nodes/0/corners", "zero area");
    checkLoadError(
        "size5.json",
        withNodes(R"([{"type": "disk", "material": "m", "radius": 1, "normal": [0, 0, 0]}])"),
        "/nodes/0/normal", "non-zero");
    checkLoadError("size6.json", withNodes(R"([{"type": "sphere", "material": "m", "radius": 1,
                       "transform": {"scale": [1, 0, 1]}}])"),
                   "/nodes/0/transform/scale", "non-zero");
    checkLoadError("size7.json", withSphere(R"("lights": [{"type": "directional",
                       "direction": [0, 0, 0], "irradiance": [1, 1, 1]}])"),
                   "/lights/0/direction", "non-zero");
    checkLoadError("size8.json", withSphere(R"("lights": [{"type": "point", "position": [0, 1, 0],
                       "intensity": [1, -1, 1]}])"),
                   "/lights/0/intensity/1", "negative");
    checkLoadError(
        "size9.json",
        withNodes(R"([{"type": "grid", "material": "m", "size": [1, 1], "segments": [0, 4]}])"),
        "/nodes/0/segments/0", "out of range");
    checkLoadError("size10.json",
                   R"({"materials": {"m": {"type": "glossy", "roughness": 1.5}}, )" +
                       std::string(kOneSphere) + "}",
                   "/materials/m/roughness", "out of range");
}

TEST_CASE("Scenes without geometry are rejected, scenes without lights are not", "[scene]") {
    checkLoadError("empty1.json", withNodes("[]"), "/nodes", "scene has no geometry");
    checkLoadError("empty2.json", std::string("{") + kOneMaterial + "}", "/",
                   "scene has no geometry");
    checkLoadError("empty3.json",
                   std::string("{") + kOneMaterial + R"(, "prototypes": {"nothing": {}},
                       "nodes": [{"type": "group", "children": [{"type": "group"}]},
                                 {"type": "instance", "prototype": "nothing"}]})",
                   "/nodes", "scene has no geometry");
    std::string path = writeTestFile("nolight.json", withNodes(R"([{"type": "sphere",
        "material": "m", "radius": 1}])"));
    auto scene = loadScene(path);
    CHECK(scene->lights.empty());
}

TEST_CASE("Image size and sample counts have limits", "[scene]") {
    checkLoadError("image1.json", withSphere(R"("camera": {"resolution": [0, 10]})"),
                   "/camera/resolution/0", "out of range");
    checkLoadError("image2.json", withSphere(R"("camera": {"resolution": [16385, 1]})"),
                   "/camera/resolution/0", "out of range");
    checkLoadError("image3.json", withSphere(R"("camera": {"resolution": [16384, 8192]})"),
                   "/camera/resolution", "image too large");
    checkLoadError("image4.json", withSphere(R"("camera": {"resolution": [640]})"),
                   "/camera/resolution", "expected an array of 2 integers");
    checkLoadError("image5.json", withSphere(R"("camera": {"fov": 180})"), "/camera/fov",
                   "between 0 and 180");
    checkLoadError("image6.json",
                   withSphere(R"("camera": {"position": [0, 0, 0], "look_at": [0, 0, 0]})"),
                   "/camera/look_at", "coincides");
    checkLoadError("spp1.json", withSphere(R"("render": {"spp": 0})"), "/render/spp",
                   "out of range");
    checkLoadError("spp2.json", withSphere(R"("render": {"spp": 1000001})"), "/render/spp",
                   "out of range");
    checkLoadError("spp3.json", withSphere(R"("render": {"max_depth": 0})"), "/render/max_depth",
                   "out of range");
    checkLoadError("spp4.json", withSphere(R"("render": {"seed": -1})"), "/render/seed",
                   "out of range");
    std::string ok =
        writeTestFile("image-ok.json", withSphere(R"("camera": {"resolution": [16384, 4096]})"));
    CHECK(loadScene(ok)->camera.width == 16384);
}

TEST_CASE("Instance cycles and bad prototypes are rejected", "[scene]") {
    checkLoadError("cycle1.json", std::string("{") + kOneMaterial + R"(, "prototypes": {
                       "a": {"children": [{"type": "instance", "prototype": "b"}]},
                       "b": {"children": [{"type": "instance", "prototype": "a"}]}},
                       "nodes": [{"type": "instance", "prototype": "a"}]})",
                   "/prototypes/b/children/0/prototype", "instance cycle: a -> b -> a");
    checkLoadError("cycle2.json", std::string("{") + kOneMaterial + R"(, "prototypes": {
                       "self": {"children": [{"type": "group", "children": [
                           {"type": "instance", "prototype": "self"}]}]}},
                       "nodes": [{"type": "instance", "prototype": "self"}]})",
                   "/prototypes/self/children/0/children/0/prototype",
                   "instance cycle: self -> self");
    checkLoadError("proto1.json", withSphere(R"("prototypes": {"p": {"type": "sphere"}})"),
                   "/prototypes/p/type", "a prototype is a group");
}

TEST_CASE("Transform mistakes are located", "[scene]") {
    auto sphereWith = [](const std::string& transform) {
        return withNodes(R"([{"type": "group", "transform": )" + transform +
                         R"(, "children": [{"type": "sphere", "material": "m", "radius": 1}]}])");
    };
    checkLoadError("xf1.json", sphereWith("[1, 0, 0]"), "/nodes/0/transform",
                   "expected an array of 12 or 16 numbers");
    checkLoadError("xf2.json", sphereWith("[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1]"),
                   "/nodes/0/transform", "last row");
    checkLoadError("xf3.json", sphereWith("[1,0,0,0, 0,1,0,0, 0,0,0,0]"), "/nodes/0/transform",
                   "singular");
    checkLoadError("xf4.json", sphereWith(R"({"rotate": {"angle": 30}})"),
                   "/nodes/0/transform/rotate", "missing required key \"axis\"");
    checkLoadError("xf5.json", sphereWith(R"({"rotate": [{"angle": 30, "axis": [0, 1, 0]}, 5]})"),
                   "/nodes/0/transform/rotate/1", "expected an object");
    checkLoadError("xf6.json", sphereWith(R"("big")"), "/nodes/0/transform",
                   "expected a transform");
}

TEST_CASE("Deep nesting is an error, not a stack overflow", "[scene]") {
    std::string nodes;
    for (int i = 0; i < 300; ++i) nodes += R"({"type": "group", "children": [)";
    nodes += R"({"type": "sphere", "material": "m", "radius": 1})";
    for (int i = 0; i < 300; ++i) nodes += "]}";
    std::string path = writeTestFile("deep.json", withNodes("[" + nodes + "]"));
    CHECK_THAT(loadErrorOf(path), Catch::Matchers::Contains("nested too deeply"));
    // Deeply nested JSON is refused while parsing, before it costs memory: each open
    // container takes the parser ~150 bytes per byte of input.
    std::string arrays = std::string(100000, '[') + std::string(100000, ']');
    path = writeTestFile("deep-arrays.json", withSphere(R"("lights": )" + arrays));
    CHECK_THAT(loadErrorOf(path),
               Catch::Matchers::Contains("/lights/0/0/0/0/0/0/0/0/0/0/0/...: nested more than "
                                         "1024 levels"));
    // 1024 levels are allowed (and are then only a type error).
    arrays = std::string(1023, '[') + std::string(1023, ']');
    path = writeTestFile("deep-arrays-ok.json", withSphere(R"("lights": )" + arrays));
    CHECK_THAT(loadErrorOf(path), Catch::Matchers::Contains("/lights/0: expected an object"));
}

TEST_CASE("Only one environment light", "[scene]") {
    checkLoadError("env.json",
                   withSphere(R"("lights": [{"type": "environment", "radiance": [1, 1, 1]},
                       {"type": "environment", "radiance": [1, 1, 1]}])"),
                   "/lights/1", "only one environment light");
}
