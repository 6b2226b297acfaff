// Multiple importance sampling of a glossy lobe in raytrace and gi (ShadingPolicy::glossyMis),
// and of the rest of the BSDF under area lights (ShadingPolicy::diffuseMis).
//
// Those modes light a surface by light samples (the shadow stage: `lightSamples` of each light,
// or per light that matters over several area lights, each sample picking one) and continue a
// glossy lobe by one sampled reflection ray (the reflection stage: a rough coat's reflection
// alone, or the whole BSDF of a rough metal or glass and of rayproc's glossy material). A
// near-mirror lobe's highlight of a small light is found almost only by the reflection ray, a
// wide lobe's almost only by light samples; each strategy alone is unbiased
// but one of them is very noisy. Weighting both by Veach's power heuristic, with the light
// strategy's density n * p_light (n the light's expected samples at the point: lightSamples, or
// lightSamples times its choice probability), keeps each where it is good:
//   light sample:    f_rest + w_l f_lobe,  w_l = (n p_l)^2 / ((n p_l)^2 + p_b^2)
//   reflection ray:  L_e * w_b,            w_b = p_b^2 / (p_b^2 + (n p_l)^2)
// f_lobe is the part of f the reflection stage samples (kernels::sampledLobeEvalCos), f_rest
// the rest (a coated surface's base, a diffuse surface whole). With ShadingPolicy::diffuseMis
// the rest is shared the same way for area lights: the shadow stage spawns one cosine-sampled
// ray (p_c = cos / pi) that collects only emission, f_rest cos / p_c its weight, and
//   light sample:    w_r f_rest,  w_r = (n p_l)^2 / ((n p_l)^2 + p_c^2)
//   cosine ray:      L_e * w_c,   w_c = p_c^2 / (p_c^2 + (n p_l)^2)   (reflectionEmissionWeight)
// so a point right under a light's edge, where a light sample's 1 / distance^2 is a firefly,
// gets its light from the ray. The sky counts likewise: the shadow stage samples it for
// diffuse-class surfaces and, with MIS, glossy-class ones; a transmitted glossy ray's sky is
// never light sampled and counts whole.
#pragma once

#include "engine/render_context.h"
#include "kernels/mis.h"
#include "lighting/light_set.h"

#include <algorithm>

namespace rayproc {

// The shadow stage's samples of one light (a delta light takes one).
inline int lightSampleCount(const ShadingPolicy& policy, const LightSource& light) {
    return light.delta() ? 1 : policy.lightSamples;
}

// Whether the shadow stage chooses among the area lights (ShadingPolicy::lightChoice).
inline bool choosesLights(const ShadingPolicy& policy, const LightSet& lights) {
    return policy.lightChoice && lights.choosesAreaLights();
}

// The expected number of the shadow stage's samples at p that go to light i: its sample count,
// times the probability that a sample picks it when the stage chooses among the lights.
inline float expectedLightSamples(const ShadingPolicy& policy, const LightSet& lights,
                                  std::size_t i, const Vec3& p) {
    if (!choosesLights(policy, lights) || lights.lights[i].delta())
        return float(lightSampleCount(policy, lights.lights[i]));
    LightSet::Choice c = lights.choiceAt(i, p, policy.lightSamples);
    return float(c.samples) * c.probability;
}

// Weight of the emission a glossy reflection ray finds on light i at q (normal nq), the ray
// sampled at p with solid-angle pdf bsdfPdf; bsdfPdf 0: no light sample covered that path.
inline float reflectionEmissionWeight(const ShadingPolicy& policy, const LightSet& lights,
                                      std::size_t i, const Vec3& p, const Vec3& q, const Vec3& nq,
                                      float bsdfPdf) {
    if (!(bsdfPdf > 0)) return 1.0f;
    float pl = expectedLightSamples(policy, lights, i, p) * lights.lights[i].pdf(p, q, nq);
    return kernels::powerHeuristic(bsdfPdf, pl);
}

// Weight of the sky a glossy reflection ray escapes to in direction d; cosOrigin is the cosine
// of d with the facing shading normal it left (a constant sky is sampled cosine-weighted).
inline float reflectionEnvironmentWeight(const ShadingPolicy& policy, const EnvironmentLight& env,
                                         const Vec3& d, float cosOrigin, float bsdfPdf) {
    if (!(bsdfPdf > 0)) return 1.0f;
    float pe = env.cosineSampled() ? std::max(0.0f, cosOrigin) * kInvPi : env.pdf(d, Vec3(0.0f));
    return kernels::powerHeuristic(bsdfPdf, float(policy.lightSamples) * pe);
}

} // namespace rayproc
