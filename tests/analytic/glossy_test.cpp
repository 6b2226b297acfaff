// A glossy (GGX, Schlick) plane under a constant sky of radiance L, seen at a fixed angle
// (a 1-degree field of view): it reflects L times its directional albedo
//   E(wo) = integral over the hemisphere of f(wo, wi) cos(theta_i) d(wi),
// which has no closed form with Smith masking but is a plain integral of glossyEvalCos: it is
// computed here by a fine midpoint rule, independently of any sampling. Path mode must converge
// to L E(wo) through both of its strategies (cosine-weighted sky samples and GGX samples,
// weighted by the power heuristic), raytrace through its GGX-sampled reflection ray. Preview's
// glossy ambient term (L * F0) is an approximation, not checked here.
#include "analytic.h"

#include "kernels/bsdf.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

// E(wo) per channel: 2048 x 1024 midpoints over (cos theta, phi), where d(omega) =
// d(cos theta) d(phi). The lobe is smooth at these roughnesses: the rule is exact to ~1e-5.
Vec3 directionalAlbedo(const Vec3& wo, const Vec3& f0, float alpha) {
    const Vec3 n(0, 0, 1);
    const int nc = 2048, np = 1024;
    double sum[3] = {0, 0, 0};
    for (int j = 0; j < nc; ++j) {
        double c = (j + 0.5) / nc, s = std::sqrt(1 - c * c);
        for (int i = 0; i < np; ++i) {
            double phi = 2 * kPi * (i + 0.5) / np;
            Vec3 wi(float(s * std::cos(phi)), float(s * std::sin(phi)), float(c));
            Vec3 f = kernels::glossyEvalCos(wo, wi, n, f0, alpha);
            for (int k = 0; k < 3; ++k) sum[k] += f[k];
        }
    }
    double w = 2 * kPi / (double(nc) * np);
    return Vec3(float(sum[0] * w), float(sum[1] * w), float(sum[2] * w));
}

} // namespace

TEST_CASE("Glossy plane under a constant sky: L times the directional albedo", "[analytic]") {
    const Vec3 f0(1.0f, 0.6f, 0.2f), sky(0.8f, 0.8f, 1.0f);
    const float thetaDeg = 50.0f;
    for (float roughness : {0.3f, 0.6f}) {
        // Camera in the xz-plane, 10 units away at 50 degrees from the normal (+z), looking
        // at the origin.
        float t = thetaDeg * kPi / 180.0f;
        Vec3 eye(10 * std::sin(t), 0, 10 * std::cos(t));
        auto scene = sceneFromJson(
            R"({"camera": {"position": )" + jsonVec(eye) +
            R"(, "look_at": [0, 0, 0], "fov": 1, "resolution": [16, 16]},
               "materials": {"gloss": {"type": "glossy", "color": )" + jsonVec(f0) +
            R"(, "roughness": )" + std::to_string(roughness) + R"(}},
               "lights": [{"type": "environment", "radiance": )" + jsonVec(sky) + R"(}],
               "nodes": [{"type": "rectangle", "material": "gloss", "size": [100, 100],
                          "normal": [0, 0, 1]}]})");
        EmbreeScene accel(*scene);
        Vec3 wo = normalize(eye);
        Vec3 e = directionalAlbedo(wo, f0, kernels::ggxAlpha(roughness));
        Vec3 expected = e * sky;
        INFO("roughness " << roughness << ", directional albedo " << e.x << " " << e.y << " "
                          << e.z);
        // Unlike the diffuse plane, the two strategies' pdfs differ: each sample is noisy.
        checkMeanRadiance(renderMode(*scene, accel, "path", 256), expected, 0.01,
                          "path roughness " + std::to_string(roughness));
        // Raytrace's single GGX-sampled ray per hit loses the samples reflected below the
        // horizon: noisier, hence 4x the samples.
        checkMeanRadiance(renderMode(*scene, accel, "raytrace", 1024), expected, 0.01,
                          "raytrace roughness " + std::to_string(roughness));
    }
}
