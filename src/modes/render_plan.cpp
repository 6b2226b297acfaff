#include "modes/render_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

namespace rayproc {

namespace {

// A shape as placed in the world: the same composition of transforms as EmbreeScene::place,
// so a placement can be matched with its EmitterRecord bit for bit.
struct PlacedLeaf {
    const Shape* shape;
    Affine toWorld;
};

void collectPlaced(const Node& group, const Affine& toWorld, std::vector<PlacedLeaf>& out) {
    for (auto& c : group.children) {
        switch (c->kind) {
        case Node::Kind::Shape: out.push_back({&c->shape, toWorld}); break;
        case Node::Kind::Group:
            if (c->transform.isIdentity()) collectPlaced(*c, toWorld, out);
            else collectPlaced(*c, toWorld * c->transform, out);
            break;
        case Node::Kind::Instance:
            if (c->prototype)
                collectPlaced(*c->prototype, toWorld * c->transform * c->prototype->transform, out);
            break;
        }
    }
}

bool sameTransform(const Affine& a, const Affine& b) {
    return std::memcmp(a.m, b.m, sizeof(a.m)) == 0;
}

// Zero power: the light adds exactly nothing wherever it is sampled or hit.
bool zeroPower(const LightSource& l) {
    switch (l.kind) {
    case LightSource::Kind::Point:
    case LightSource::Kind::Spot:
    case LightSource::Kind::Directional: return !(maxComponent(l.intensity) > 0);
    default: return !(maxComponent(l.radiance) > 0) || !(l.area > 0);
    }
}

// The half-space a one-sided light radiates into, {x : dot(x - origin, normal) > 0}; false
// for lights that radiate into more than a half-space (or whose side cannot be told).
bool emittingHalfSpace(const LightSource& l, float planeTolerance, Vec3& origin, Vec3& normal) {
    switch (l.kind) {
    case LightSource::Kind::Point:
        if (!l.lobe || l.lobeTwoSided) return false;
        origin = l.position;
        normal = l.lobeNormal;
        return true;
    case LightSource::Kind::Spot:
        // The falloff cone must lie within the half-space: an outer half angle below 90 deg.
        if (!(l.cosFalloff > 0)) return false;
        origin = l.position;
        normal = l.direction;
        return true;
    case LightSource::Kind::AreaDisk:
        if (l.twoSided) return false;
        origin = l.center;
        normal = l.normal;
        return true;
    case LightSource::Kind::AreaMesh: {
        // A planar one-sided mesh whose triangles all face the same way.
        if (l.twoSided || l.triangles.size() < 3) return false;
        bool found = false;
        for (std::size_t t = 0; t + 2 < l.triangles.size(); t += 3) {
            const Vec3 *v = &l.triangles[t];
            Vec3 c = cross(v[1] - v[0], v[2] - v[0]);
            if (!(length(c) > 0)) continue; // degenerate triangles emit nothing
            Vec3 n = normalize(c);
            if (!found) {
                origin = v[0];
                normal = n;
                found = true;
            } else if (dot(n, normal) < 0.9999f) {
                return false;
            }
        }
        if (!found) return false;
        for (const Vec3& v : l.triangles)
            if (std::abs(dot(v - origin, normal)) > planeTolerance) return false;
        return true;
    }
    default: return false; // spheres radiate in every direction; directional lights everywhere
    }
}

// Farthest signed distance of a box in front of the plane (origin, normal).
float frontDistance(const Bounds3& b, const Vec3& origin, const Vec3& normal) {
    float best = -kInfinity;
    for (int i = 0; i < 8; ++i) {
        Vec3 c{(i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z};
        best = std::max(best, dot(c - origin, normal));
    }
    return best;
}

const char* kindName(LightSource::Kind k) {
    switch (k) {
    case LightSource::Kind::Point: return "point";
    case LightSource::Kind::Spot: return "spot";
    case LightSource::Kind::Directional: return "directional";
    case LightSource::Kind::AreaMesh: return "area mesh";
    case LightSource::Kind::AreaSphere: return "area sphere";
    case LightSource::Kind::AreaDisk: return "area disk";
    }
    return "?";
}

} // namespace

std::size_t RenderPlan::sampledLightCount() const {
    return std::size_t(std::count_if(lights.begin(), lights.end(),
                                     [](const LightDecision& d) { return d.sampled; }));
}

LightSet RenderPlan::sampledLights(const LightSet& all) const {
    std::vector<bool> keep(all.lights.size(), true);
    for (std::size_t i = 0; i < keep.size() && i < lights.size(); ++i) keep[i] = lights[i].sampled;
    return all.subset(keep);
}

void RenderPlan::apply(ShadingPolicy& policy) const {
    policy.refractionStage = refractionStage;
    policy.reflectionStage = reflectionStage;
    policy.shadowStage = shadowStage;
    // Delta lights take one unstratified sample each whatever the setting.
    if (!lightStratification) policy.lightSamples = 1;
}

std::vector<std::string> RenderPlan::logLines(unsigned mode) const {
    std::vector<std::string> out;
    for (const PlanSkip& s : skipped)
        if (s.modes & mode) out.push_back("skipped " + s.what + ": " + s.why);
    return out;
}

namespace {

// Counts a leaf of materials[m] into the stages its material needs (both of a mix's).
void countMaterial(const std::vector<Material>& materials, int m, RenderPlan& p, int depth) {
    const Material& mat = materials[std::size_t(m)];
    const bool delta = materialClass(materials, m) == MaterialClass::Specular;
    switch (mat.type) {
    case MaterialType::Diffuse: ++p.diffuseLeaves; break;
    case MaterialType::Glossy: ++p.glossyLeaves; break;
    case MaterialType::Mirror: ++p.mirrorLeaves; break;
    case MaterialType::Dielectric:
        ++p.dielectricLeaves;
        if (!delta) ++p.glossyLeaves; // light sampling and a sampled continuation
        break;
    case MaterialType::Conductor:
    case MaterialType::CoatedConductor: ++(delta ? p.mirrorLeaves : p.glossyLeaves); break;
    case MaterialType::ThinDielectric:
        ++p.dielectricLeaves;
        ++p.mirrorLeaves;
        break;
    case MaterialType::CoatedDiffuse:
        ++p.diffuseLeaves;
        ++p.glossyLeaves; // the coat's reflection
        ++p.coatLeaves;
        break;
    case MaterialType::DiffuseTransmission:
        ++p.diffuseLeaves;
        ++p.dielectricLeaves; // transmitted rays
        break;
    case MaterialType::Mix:
        if (depth < 16)
            for (int k = 0; k < 2; ++k)
                if (mat.mix[k] >= 0) countMaterial(materials, mat.mix[k], p, depth + 1);
        break;
    }
}

} // namespace

RenderPlan fullPlan(const LightSet& lights) {
    RenderPlan p;
    p.lights.resize(lights.lights.size());
    p.environment = lights.hasEnvironment();
    return p;
}

namespace {

// Which lights are sampled (zero power, or radiating away from everything) and what radiates.
void decideLights(const Scene& scene, const EmbreeScene& accel, const LightSet& lights,
                  const std::vector<PlacedLeaf>& leaves, RenderPlan& p) {
    // Lights. Tolerances are relative to the scene's extent: a plane test must not be fooled
    // by the rounding of world-space vertices.
    Bounds3 world = scene.worldBounds();
    float extent = world.empty() ? 1.0f
                                 : std::max({std::abs(world.lo.x), std::abs(world.lo.y),
                                             std::abs(world.lo.z), std::abs(world.hi.x),
                                             std::abs(world.hi.y), std::abs(world.hi.z)});
    const float tolerance = 1e-5f * (1.0f + extent);
    // Which placed leaf each area light is (to leave it out of its own blockers).
    std::vector<int> leafOfLight(lights.lights.size(), -1);
    for (const EmitterRecord& e : accel.emitters()) {
        int li = lights.indexOf(e.shape, e.instance);
        if (li < 0) continue;
        for (std::size_t k = 0; k < leaves.size(); ++k)
            if (leaves[k].shape == e.shape && sameTransform(leaves[k].toWorld, e.toWorld))
                leafOfLight[std::size_t(li)] = int(k);
    }
    std::vector<Bounds3> leafBounds;
    leafBounds.reserve(leaves.size());
    for (const PlacedLeaf& l : leaves) leafBounds.push_back(l.toWorld.bounds(l.shape->bounds()));
    const Camera& cam = scene.camera;

    bool deltaOnly = !lights.hasEnvironment();
    for (std::size_t i = 0; i < lights.lights.size(); ++i) {
        const LightSource& l = lights.lights[i];
        LightDecision& d = p.lights[i];
        if (zeroPower(l)) {
            d.sampled = false;
            d.reason = l.delta() || maxComponent(l.radiance) <= 0 ? "zero power" : "zero area";
        } else {
            Vec3 o, n;
            if (emittingHalfSpace(l, tolerance, o, n)) {
                // Unreachable: every other surface and the camera's lens lie on or behind the
                // plane the light radiates from, so whatever it emits leaves the scene, no
                // light sample from any surface point sees its front, and no camera ray does.
                bool blocked = true;
                for (std::size_t k = 0; k < leaves.size() && blocked; ++k) {
                    if (int(k) == leafOfLight[i]) continue;
                    if (frontDistance(leafBounds[k], o, n) > tolerance) blocked = false;
                }
                if (blocked && dot(cam.position - o, n) + cam.apertureRadius < -tolerance) {
                    d.sampled = false;
                    d.reason = "radiates away from every surface and from the camera";
                }
            }
        }
        if (d.sampled) {
            ++p.radiatingLights;
            if (!l.delta()) deltaOnly = false;
        }
    }
    if (lights.hasEnvironment()) ++p.radiatingLights;
    p.deltaLightsOnly = deltaOnly && p.radiatingLights > 0;
}

// The skips, each with its reason and the modes it concerns.
void decideSkips(const LightSet& lights, bool diffuse, bool glossy, bool specular,
                 RenderPlan& p) {
    // Decisions, in the order the issue lists them.
    auto skip = [&](const std::string& what, const std::string& why, unsigned modes) {
        p.skipped.push_back({what, why, modes});
    };
    if (p.radiatingLights == 0) {
        p.render = false;
        skip("render", "nothing in the scene emits light (no light of non-zero power reaching "
                       "a surface or the camera, no sky): the image is black",
             kPlanAllModes);
    }
    // gi: caustic photons are stored at the first diffuse or glossy surface after one or more
    // mirror or glass bounces, and read only at diffuse surfaces.
    if (!(specular && diffuse)) {
        p.causticMap = false;
        skip("caustic photon map",
             !specular ? "no mirror, glass or coated surface to focus light" : "no diffuse surface to receive caustics",
             kPlanGi);
    }
    // gi: the gather stage (final gather, cache lookups, global-map estimates) only runs at
    // diffuse hits; with none, neither the global map nor the cache is ever read.
    if (!diffuse) {
        p.globalMap = false;
        skip("global photon map, final gather, irradiance cache", "no diffuse surface", kPlanGi);
    }
    if (p.dielectricLeaves == 0) {
        p.refractionStage = false;
        skip("refraction stage", "no dielectric (glass) surface", kPlanAllModes);
    }
    if (p.mirrorLeaves + p.glossyLeaves == 0) {
        p.reflectionStage = false;
        skip("reflection stage", "no mirror or glossy surface",
             kPlanPreview | kPlanRaytrace | kPlanGi);
    }
    if (!diffuse && !glossy) {
        p.shadowStage = false;
        skip("shadow stage (light sampling)", "no diffuse or glossy surface", kPlanAllModes);
    }
    if (p.deltaLightsOnly) {
        p.lightStratification = false;
        skip("light-sample stratification", "only point, spot and directional lights: one "
                                             "shadow ray per light",
             kPlanPreview | kPlanRaytrace | kPlanGi);
    }
    for (std::size_t i = 0; i < p.lights.size(); ++i) {
        if (p.lights[i].sampled) continue;
        std::ostringstream what;
        what << "light " << i << " (" << kindName(lights.lights[i].kind) << ")";
        skip(what.str(), p.lights[i].reason, kPlanAllModes);
    }
}

} // namespace

RenderPlan analyseScene(const Scene& scene, const EmbreeScene& accel, const LightSet& lights) {
    RenderPlan p = fullPlan(lights);
    p.analysed = true;

    std::vector<PlacedLeaf> leaves;
    if (scene.root) collectPlaced(*scene.root, scene.root->transform, leaves);
    for (const PlacedLeaf& l : leaves) {
        int m = l.shape->material;
        if (m < 0 || std::size_t(m) >= scene.materials.size()) continue;
        countMaterial(scene.materials, m, p, 0);
    }
    const bool diffuse = p.diffuseLeaves > 0, glossy = p.glossyLeaves > 0;
    // Coats reflect light onto other surfaces too (gi's caustic photons follow them).
    const bool specular = p.mirrorLeaves + p.dielectricLeaves + p.coatLeaves > 0;
    decideLights(scene, accel, lights, leaves, p);
    decideSkips(lights, diffuse, glossy, specular, p);
    return p;
}

RenderPlan planRender(const Scene& scene, const EmbreeScene& accel, const LightSet& lights,
                      const EngineSettings& engine, unsigned mode) {
    if (!engine.sceneAnalysis) return fullPlan(lights);
    RenderPlan p = analyseScene(scene, accel, lights);
    if (!engine.quiet) {
        for (const std::string& line : p.logLines(mode))
            std::fprintf(stderr, "rayproc: %s\n", line.c_str());
    }
    if (!p.render)
        std::fprintf(stderr, "rayproc: warning: %s: nothing emits light; writing a black image "
                             "without rendering (--no-scene-analysis renders it anyway)\n",
                     scene.path.c_str());
    return p;
}

RenderResult blackRender(const Scene& scene) {
    RenderResult r;
    r.image = Image(scene.camera.width, scene.camera.height);
    r.stats.peakMemoryBytes = peakResidentBytes();
    return r;
}

} // namespace rayproc
