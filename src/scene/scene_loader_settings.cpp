// Scene loading: the flat sections of a scene file (camera, render settings, materials,
// lights). Each key is optional unless noted; the defaults are those of scene.h.
#include "core/error.h"
#include "scene/scene_loader_detail.h"

#include <nlohmann/json.hpp>

#include <climits>

namespace rayproc::scene_json {

namespace {

float nonNegative(const JsonRef& v) {
    float x = v.number();
    if (x < 0) v.fail("must not be negative");
    return x;
}

} // namespace

Camera parseCamera(const JsonRef& v) {
    v.expectObject({"position", "look_at", "up", "fov", "resolution", "aperture", "focus_distance"},
                   "the camera");
    Camera c;
    if (v.has("position")) c.position = v["position"].vec3();
    if (v.has("look_at")) c.lookAt = v["look_at"].vec3();
    if (v.has("up")) c.up = v["up"].direction();
    if (v.has("fov")) {
        c.fovY = v["fov"].number();
        if (c.fovY <= 0 || c.fovY >= 180)
            v["fov"].fail("field of view must lie strictly between 0 and 180 degrees");
    }
    if (v.has("resolution")) {
        JsonRef r = v["resolution"];
        if (!r.isArray() || r.arraySize() != 2)
            r.fail("expected an array of 2 integers [width, height]");
        long long w = r[std::size_t(0)].integer(1, kMaxImageSide);
        long long h = r[1].integer(1, kMaxImageSide);
        if (w * h > kMaxImagePixels) {
            r.fail("image too large: " + std::to_string(w) + " x " + std::to_string(h) +
                   " pixels exceeds the limit of " + std::to_string(kMaxImagePixels) +
                   " (2^26) pixels");
        }
        c.width = int(w);
        c.height = int(h);
    }
    if (v.has("aperture")) c.apertureRadius = nonNegative(v["aperture"]);
    if (v.has("focus_distance")) c.focusDistance = nonNegative(v["focus_distance"]);

    // A view direction must exist and must not be parallel to up.
    Vec3 view = c.lookAt - c.position;
    if (lengthSquared(view) == 0)
        v.child("look_at").fail("look_at coincides with the camera position (zero-length view)");
    if (length(cross(normalize(view), normalize(c.up))) < 1e-6f)
        v.child("up").fail(v.has("up") ? "up is parallel to the view direction"
                                       : "the default up [0, 1, 0] is parallel to the view "
                                         "direction; give \"up\"");
    return c;
}

SceneRenderSettings parseRenderSettings(const JsonRef& v) {
    v.expectObject({"mode", "spp", "max_depth", "light_samples", "seed"}, "the render settings");
    SceneRenderSettings s;
    if (v.has("mode")) s.mode = v["mode"].nonEmptyString(); // the CLI checks the name
    if (v.has("spp")) s.spp = int(v["spp"].integer(1, 1000000));
    if (v.has("max_depth")) s.maxDepth = int(v["max_depth"].integer(1, 10000));
    if (v.has("light_samples")) s.lightSamples = int(v["light_samples"].integer(1, 65536));
    if (v.has("seed")) s.seed = v["seed"].integer(0, LLONG_MAX);
    return s;
}

void parseMaterials(const JsonRef& v, Scene& scene) {
    if (!v.isObject()) v.fail("expected an object mapping material names to materials");
    static const std::vector<std::string> kTypes = {"diffuse", "mirror", "dielectric", "glossy"};
    for (const std::string& name : v.keys()) {
        JsonRef m = v[name];
        if (name.empty()) m.fail("material name must not be empty");
        if (name.rfind("__", 0) == 0)
            m.fail("material names starting with \"__\" are reserved for the loader");
        std::string type = parseType(m, "material", kTypes);

        Material mat;
        mat.name = name;
        mat.color = Vec3(1.0f);
        if (type == "diffuse") {
            m.expectObject({"type", "color"}, "a diffuse material");
            mat.type = MaterialType::Diffuse;
            mat.color = Vec3(0.5f);
        } else if (type == "mirror") {
            m.expectObject({"type", "color"}, "a mirror material");
            mat.type = MaterialType::Mirror;
        } else if (type == "dielectric") {
            m.expectObject({"type", "color", "ior"}, "a dielectric material");
            mat.type = MaterialType::Dielectric;
            if (m.has("ior")) mat.ior = m["ior"].positive();
        } else {
            m.expectObject({"type", "color", "roughness"}, "a glossy material");
            mat.type = MaterialType::Glossy;
            if (m.has("roughness")) mat.roughness = m["roughness"].numberIn(0, 1);
        }
        if (m.has("color")) mat.color = m["color"].albedo();
        scene.materials.push_back(mat);
    }
}

void parseLights(const JsonRef& v, Scene& scene) {
    if (!v.isArray()) v.fail("expected an array of lights");
    static const std::vector<std::string> kTypes = {"point", "spot", "directional", "environment"};
    bool haveEnvironment = false;
    for (std::size_t i = 0; i < v.arraySize(); ++i) {
        JsonRef l = v[i];
        std::string type = parseType(l, "light", kTypes);
        Light light;
        if (type == "point") {
            l.expectObject({"type", "name", "position", "intensity"}, "a point light");
            light.type = LightType::Point;
            light.position = l["position"].vec3();
            light.intensity = l["intensity"].color();
        } else if (type == "spot") {
            l.expectObject({"type", "name", "position", "direction", "intensity", "cone_angle",
                            "falloff_angle"},
                           "a spot light");
            light.type = LightType::Spot;
            light.position = l["position"].vec3();
            light.direction = l["direction"].direction();
            light.intensity = l["intensity"].color();
            if (l.has("cone_angle")) light.coneAngle = l["cone_angle"].positive();
            if (l.has("falloff_angle")) light.falloffAngle = nonNegative(l["falloff_angle"]);
            if (light.coneAngle + light.falloffAngle > 180) {
                l.child(l.has("falloff_angle") ? "falloff_angle" : "cone_angle")
                    .fail("cone_angle + falloff_angle must not exceed 180 degrees");
            }
        } else if (type == "directional") {
            l.expectObject({"type", "name", "direction", "irradiance"}, "a directional light");
            light.type = LightType::Directional;
            light.direction = l["direction"].direction();
            light.intensity = l["irradiance"].color();
        } else {
            l.expectObject({"type", "name", "radiance"}, "an environment light");
            if (haveEnvironment) l.fail("a scene may have only one environment light");
            haveEnvironment = true;
            light.type = LightType::Environment;
            light.intensity = l["radiance"].color();
        }
        if (l.has("name")) light.name = l["name"].string();
        scene.lights.push_back(light);
    }
}

} // namespace rayproc::scene_json
