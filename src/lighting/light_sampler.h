// The one light choice of every mode: which light (or the sky) a shading point samples, with a
// probability that depends on the point. Lights without a position (directional lights, the
// sky) share a fixed probability, as pbrt-v4's BVH light sampler gives them: n / (n + 1) for n
// such lights when there are lights with a position, else 1; within it each by the irradiance
// it can give a point (LightBounds::phi: a directional light's irradiance, the sky's pi times
// its mean radiance), where pbrt-v4 takes them alike (a sun giving most of an interior's light
// got half the picks). The rest goes to the
// lights with a position in proportion to LightBounds::importance at the point: exactly, light by
// light, when there are few of them, and through a bounding hierarchy of lights when there are
// many (Conty Estevez & Kulla 2018; pbrt-v4's BVHLightSampler), which descends by the
// importance of each child's cluster and so costs O(log n) per choice.
// pmf(p, i) is the probability that sample(p, .) picks choice i: path mode's multiple importance
// sampling weighs a BSDF ray that finds a light with it, taken at the ray's origin.
#pragma once

#include "core/math.h"
#include "lighting/light_bounds.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rayproc {

class LightSampler {
public:
    // Above this many lights with a position, the choice descends a hierarchy instead of
    // weighing every light.
    static constexpr std::size_t kExhaustiveLimit = 16;

    // bounds[i]: light i's bounds, or nullptr-like (infinite[i] true) for a light without a
    // position. Choice `choices - 1` is the sky when hasSky. Choices with excluded[i] set
    // (missing entries: none) are never picked and have pmf 0: raytrace and gi choose among
    // their area lights only (LightSet::areaSampler).
    void build(const std::vector<LightBounds>& bounds, const std::vector<bool>& infinite,
               const std::vector<bool>& excluded = {});

    struct Pick {
        std::size_t index = 0;
        float pmf = 0; // 0: nothing can be picked at p
    };
    // Picks a choice with u in [0, 1).
    Pick sample(const Vec3& p, float u) const;
    float pmf(const Vec3& p, std::size_t index) const;
    std::size_t choices() const { return m_infinite.size(); }
    // How many choices matter at p: the inverse Simpson index (sum w)^2 / sum w^2 of their
    // weights, between 1 (one choice gives everything) and the count of pickable choices (all
    // alike); 0 when nothing can be picked. Over the lights one by one when they are few, over
    // the hierarchy's clusters kEffectiveDepth levels down when they are many (O(1) per point).
    // Raytrace and gi take this many times lightSamples samples at a point.
    float effectiveChoices(const Vec3& p) const;
    static constexpr int kEffectiveDepth = 4;
    bool usesHierarchy() const { return !m_nodes.empty(); }

private:
    struct Node {
        LightBounds bounds;
        // Children for an interior node; the light for a leaf (child[1] < 0).
        int child[2] = {-1, -1};
    };
    float infiniteShare() const;
    float infiniteProbability(std::size_t k) const; // of m_infiniteList[k], within the share
    Pick sampleBounded(const Vec3& p, float u) const;
    float pmfBounded(const Vec3& p, std::size_t index) const;
    int buildNode(const std::vector<LightBounds>& bounds, std::vector<std::size_t>& lights,
                  std::size_t begin, std::size_t end, std::uint64_t trail, int depth);

    // The importance of every light with a position at p, into weights (few lights); their sum.
    float boundedImportances(const Vec3& p, float* weights) const;

    // The lights with a position, their bounds by component (boundedImportances' loop).
    struct Components {
        std::vector<float> cx, cy, cz, r2, phi, ax, ay, az, cosO, sinO, cosE, twoSided;
    } m_soa;
    std::vector<bool> m_infinite;
    std::vector<std::size_t> m_infiniteList, m_boundedList;
    std::vector<double> m_infiniteCdf; // cumulative weights of m_infiniteList, last 1
    std::vector<Node> m_nodes;            // the hierarchy, root first (many lights only)
    std::vector<std::uint64_t> m_trail;   // per choice: the left/right turns from the root
    std::vector<std::uint8_t> m_trailLen; // and how many
};

} // namespace rayproc
