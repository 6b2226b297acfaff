// gi at coated conductors (pbrt-v4's coatedconductor): routed as a conductor is, a glossy one
// (light sampling with MIS, one sampled continuation, photons read with the BSDF) or an all-delta
// one (mirror-like). The Cornell box's spheres as coated conductors must then agree with path
// mode in their mean radiance, per channel.
#include "../analytic/analytic.h"

#include "scene/metals.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

// cornell-spheres with its mirror sphere a coated gold and its glass sphere a coated copper;
// `rough`: rough coats over rough metals with a scattering slab under the copper's coat, else
// smooth coats over smooth metals (all delta).
std::unique_ptr<Scene> coatedSpheres(bool rough) {
    auto scene = loadSceneAt("cornell-spheres", 32, 32);
    for (Material& m : scene->materials) {
        const bool gold = m.type == MaterialType::Mirror;
        if (!gold && m.type != MaterialType::Dielectric) continue;
        m.type = MaterialType::CoatedConductor;
        Vec3 eta, k;
        namedMetal(gold ? "Au" : "Cu", eta, k);
        m.eta = ColorParam{eta};
        m.k = ColorParam{k};
        const float coat = rough ? (gold ? 0.0f : 0.05f) : 0.0f;
        const float metal = rough ? 0.1f : 0.0f;
        m.uRoughness = m.vRoughness = FloatParam{coat};
        m.conductorURoughness = m.conductorVRoughness = FloatParam{metal};
        m.albedo = ColorParam{rough && !gold ? Vec3(0.5f) : Vec3(0.0f)};
    }
    return scene;
}

} // namespace

TEST_CASE("gi agrees with path on coated conductors, glossy and all-delta",
          "[gi][coated-conductor]") {
    // Measured here (gi / path, R G B): glossy 0.9997 1.0009 1.0013, all delta 0.9938 0.9997
    // 1.0010 (the CLI at the same size, bare rough conductors in the glossy scene's places:
    // 1.0012 1.0034 1.0037).
    for (bool rough : {true, false}) {
        auto scene = coatedSpheres(rough);
        CHECK(materialClass(scene->materials, scene->findMaterial("Mirror")) ==
              (rough ? MaterialClass::Glossy : MaterialClass::Specular));
        EmbreeScene accel(*scene);
        checkGiMeanMatchesPath(*scene, accel, 16, 1024, 0.02, rough ? "glossy" : "all delta");
    }
}
