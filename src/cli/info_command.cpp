#include "accel/embree_scene.h"
#include "cli/commands.h"
#include "lighting/light_set.h"
#include "modes/render_plan.h"
#include "scene/scene_loader.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <map>
#include <memory>

namespace rayproc::cli {

namespace {

struct NodeCounts {
    std::size_t groups = 0, instances = 0, shapes = 0;
};

void countNodes(const Node& n, NodeCounts& c) {
    switch (n.kind) {
    case Node::Kind::Group: ++c.groups; break;
    case Node::Kind::Instance: ++c.instances; break;
    case Node::Kind::Shape: ++c.shapes; break;
    }
    for (auto& ch : n.children) countNodes(*ch, c);
}

// The scene analysis for the modes that sample the scene's lights as they are (raytrace, gi,
// path); preview analyses its point-light approximation the same way when it renders.
nlohmann::ordered_json describePlan(const Scene& scene, const EmbreeScene& accel) {
    LightSet lights = LightSet::build(scene, accel);
    RenderPlan p = analyseScene(scene, accel, lights);
    nlohmann::ordered_json j;
    j["render"] = p.render;
    j["radiating_lights"] = p.radiatingLights;
    j["delta_lights_only"] = p.deltaLightsOnly;
    j["caustic_map"] = p.causticMap;
    j["global_map_gather_cache"] = p.globalMap;
    j["reflection_stage"] = p.reflectionStage;
    j["refraction_stage"] = p.refractionStage;
    j["shadow_stage"] = p.shadowStage;
    j["light_stratification"] = p.lightStratification;
    nlohmann::ordered_json ls = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < p.lights.size(); ++i)
        ls.push_back({{"index", i}, {"sampled", p.lights[i].sampled}, {"reason", p.lights[i].reason}});
    j["lights"] = ls;
    nlohmann::ordered_json sk = nlohmann::ordered_json::array();
    for (const PlanSkip& s : p.skipped) {
        nlohmann::ordered_json modes = nlohmann::ordered_json::array();
        const char* names[] = {"preview", "raytrace", "gi", "path"};
        for (int m = 0; m < 4; ++m)
            if (s.modes & (1u << m)) modes.push_back(names[m]);
        sk.push_back({{"what", s.what}, {"why", s.why}, {"modes", modes}});
    }
    j["skipped"] = sk;
    return j;
}

nlohmann::ordered_json describe(const Scene& scene, const EmbreeScene& accel) {
    NodeCounts nodes;
    if (scene.root) countNodes(*scene.root, nodes);
    for (auto& p : scene.prototypes) countNodes(*p, nodes);
    const AccelStats& a = accel.stats();

    std::map<std::string, std::size_t> lights{{"area", accel.emitters().size()},
                                              {"point", 0}, {"spot", 0}, {"directional", 0},
                                              {"environment", 0}, {"goniometric", 0}};
    for (const Light& l : scene.lights) {
        switch (l.type) {
        case LightType::Point: ++lights["point"]; break;
        case LightType::Spot: ++lights["spot"]; break;
        case LightType::Directional: ++lights["directional"]; break;
        case LightType::Environment: ++lights["environment"]; break;
        case LightType::Goniometric: ++lights["goniometric"]; break;
        }
    }
    std::map<std::string, std::size_t> materials{
        {"diffuse", 0}, {"mirror", 0}, {"dielectric", 0}, {"glossy", 0}};
    for (const Material& m : scene.materials) ++materials[materialTypeName(m.type)];

    Bounds3 b = scene.worldBounds();
    nlohmann::ordered_json j;
    j["scene"] = scene.path;
    j["camera"] = {{"resolution", {scene.camera.width, scene.camera.height}},
                   {"fov", scene.camera.fovY}};
    j["nodes"] = {{"groups", nodes.groups}, {"instances", nodes.instances},
                  {"shapes", nodes.shapes}, {"prototypes", scene.prototypes.size()}};
    j["geometry"] = {{"triangles_unique", a.uniqueTriangles},
                     {"triangles_placed", a.placedTriangles},
                     {"triangles_exact", a.exactTriangles},
                     {"spheres", a.spheres},
                     {"disks", a.disks},
                     {"leaves_placed", a.leaves}};
    j["lights"] = lights;
    j["materials"] = materials;
    j["bounds"] = {{"min", {b.lo.x, b.lo.y, b.lo.z}}, {"max", {b.hi.x, b.hi.y, b.hi.z}}};
    j["acceleration"] = {{"embree_prototype_scenes", a.prototypes},
                         {"embree_instances", a.instances},
                         {"memory_bytes", a.memoryBytes},
                         {"build_seconds", a.buildSeconds}};
    j["plan"] = describePlan(scene, accel);
    return j;
}

void printText(const nlohmann::ordered_json& j) {
    auto& g = j["geometry"];
    auto& n = j["nodes"];
    auto& l = j["lights"];
    auto& m = j["materials"];
    auto& a = j["acceleration"];
    auto& b = j["bounds"];
    std::printf("scene        %s\n", j["scene"].get<std::string>().c_str());
    std::printf("camera       %dx%d, fov %.4g deg\n", j["camera"]["resolution"][0].get<int>(),
                j["camera"]["resolution"][1].get<int>(), j["camera"]["fov"].get<double>());
    std::printf("nodes        %zu groups, %zu instances, %zu shapes, %zu prototypes\n",
                n["groups"].get<std::size_t>(), n["instances"].get<std::size_t>(),
                n["shapes"].get<std::size_t>(), n["prototypes"].get<std::size_t>());
    std::printf("triangles    %zu unique, %zu placed", g["triangles_unique"].get<std::size_t>(),
                g["triangles_placed"].get<std::size_t>());
    if (g["triangles_exact"].get<std::size_t>() > 0)
        std::printf(", %zu huge ones intersected in double precision",
                    g["triangles_exact"].get<std::size_t>());
    std::printf("\n");
    std::printf("spheres      %zu\ndisks        %zu\n", g["spheres"].get<std::size_t>(),
                g["disks"].get<std::size_t>());
    std::printf("lights       %zu area, %zu point, %zu spot, %zu directional, %zu environment",
                l["area"].get<std::size_t>(), l["point"].get<std::size_t>(),
                l["spot"].get<std::size_t>(), l["directional"].get<std::size_t>(),
                l["environment"].get<std::size_t>());
    if (l["goniometric"].get<std::size_t>() > 0)
        std::printf(", %zu goniometric", l["goniometric"].get<std::size_t>());
    std::printf("\nmaterials    %zu diffuse, %zu mirror, %zu dielectric, %zu glossy",
                m["diffuse"].get<std::size_t>(), m["mirror"].get<std::size_t>(),
                m["dielectric"].get<std::size_t>(), m["glossy"].get<std::size_t>());
    // pbrt-v4's other materials, where the scene has them.
    for (const auto& [name, count] : m.items())
        if (name != "diffuse" && name != "mirror" && name != "dielectric" && name != "glossy" &&
            count.get<std::size_t>() > 0)
            std::printf(", %zu %s", count.get<std::size_t>(), name.c_str());
    std::printf("\n");
    std::printf("bounds       (%g, %g, %g) - (%g, %g, %g)\n", b["min"][0].get<double>(),
                b["min"][1].get<double>(), b["min"][2].get<double>(), b["max"][0].get<double>(),
                b["max"][1].get<double>(), b["max"][2].get<double>());
    std::printf("embree       %zu prototype scenes, %zu instances, %.1f KiB, built in %.3f s\n",
                a["embree_prototype_scenes"].get<std::size_t>(),
                a["embree_instances"].get<std::size_t>(),
                double(a["memory_bytes"].get<std::size_t>()) / 1024.0,
                a["build_seconds"].get<double>());
    const auto& p = j["plan"];
    std::printf("plan         %zu lights and sky that radiate into the scene; %s\n",
                p["radiating_lights"].get<std::size_t>(),
                p["skipped"].empty() ? "nothing skipped" : "skipped:");
    for (const auto& s : p["skipped"]) {
        std::string modes;
        for (const auto& m : s["modes"]) {
            if (!modes.empty()) modes += ",";
            modes += m.get<std::string>();
        }
        std::printf("  - %s: %s [%s]\n", s["what"].get<std::string>().c_str(),
                    s["why"].get<std::string>().c_str(), modes.c_str());
    }
}

} // namespace

std::function<int()> addInfoCommand(CLI::App& app) {
    auto scenePath = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    CLI::App* cmd = app.add_subcommand(
        "info", "Print what a scene holds: nodes, instances, triangles, spheres, lights and "
                "materials by type, world bounds, acceleration memory and build time");
    cmd->add_option("scene", *scenePath, "Scene file: JSON or pbrt-v4")->required()->check(CLI::ExistingFile);
    cmd->add_flag("--json", *json, "Print the figures as JSON");
    return [scenePath, json] {
        std::unique_ptr<Scene> scene = loadScene(*scenePath);
        EmbreeScene accel(*scene);
        nlohmann::ordered_json j = describe(*scene, accel);
        if (*json) std::printf("%s\n", j.dump(2).c_str());
        else printText(j);
        return 0;
    };
}

} // namespace rayproc::cli
