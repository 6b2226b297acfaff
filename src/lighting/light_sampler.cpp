#include "lighting/light_sampler.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>

namespace rayproc {

namespace {

// The bounds of two clusters together: a sphere around both spheres, the power summed, a cone
// around both cones.
LightBounds merge(const LightBounds& a, const LightBounds& b) {
    if (!(a.phi > 0)) return b;
    if (!(b.phi > 0)) return a;
    LightBounds m;
    Vec3 d = b.center - a.center;
    float dist = length(d);
    if (dist + b.radius <= a.radius) {
        m.center = a.center;
        m.radius = a.radius;
    } else if (dist + a.radius <= b.radius) {
        m.center = b.center;
        m.radius = b.radius;
    } else {
        m.radius = 0.5f * (dist + a.radius + b.radius);
        m.center = a.center + d * ((m.radius - a.radius) / dist);
        m.radius *= 1.0f + 1e-5f; // rounding of the centre
    }
    m.phi = a.phi + b.phi;
    unionCone(a.axis, a.thetaO, b.axis, b.thetaO, m.axis, m.thetaO);
    m.thetaE = std::max(a.thetaE, b.thetaE);
    m.twoSided = a.twoSided || b.twoSided;
    m.updateCone();
    return m;
}

} // namespace

void LightSampler::build(const std::vector<LightBounds>& bounds, const std::vector<bool>& infinite,
                         const std::vector<bool>& excluded) {
    RAYPROC_CHECK(bounds.size() == infinite.size());
    RAYPROC_CHECK(excluded.size() <= bounds.size());
    m_infinite = infinite;
    m_infiniteList.clear();
    m_boundedList.clear();
    m_nodes.clear();
    m_trail.assign(bounds.size(), 0);
    m_trailLen.assign(bounds.size(), 0);
    for (std::size_t i = 0; i < bounds.size(); ++i)
        if (!(i < excluded.size() && excluded[i]))
            (infinite[i] ? m_infiniteList : m_boundedList).push_back(i);
    // Among the lights without a position: by phi (the irradiance each can give a point), or
    // alike when none has a positive, finite one.
    m_infiniteCdf.clear();
    double total = 0;
    for (std::size_t l : m_infiniteList) {
        double w = std::isfinite(bounds[l].phi) ? std::max(0.0f, bounds[l].phi) : 0.0;
        total += w;
        m_infiniteCdf.push_back(total);
    }
    if (!(total > 0))
        for (std::size_t k = 0; k < m_infiniteCdf.size(); ++k) m_infiniteCdf[k] = double(k + 1);
    for (double& c : m_infiniteCdf) c /= m_infiniteCdf.empty() ? 1.0 : m_infiniteCdf.back();
    m_soa = Components{};
    for (std::size_t l : m_boundedList) {
        const LightBounds& b = bounds[l];
        m_soa.cx.push_back(b.center.x);
        m_soa.cy.push_back(b.center.y);
        m_soa.cz.push_back(b.center.z);
        m_soa.r2.push_back(b.radius * b.radius);
        m_soa.phi.push_back(b.phi);
        m_soa.ax.push_back(b.axis.x);
        m_soa.ay.push_back(b.axis.y);
        m_soa.az.push_back(b.axis.z);
        m_soa.cosO.push_back(b.cosO);
        m_soa.sinO.push_back(b.sinO);
        m_soa.cosE.push_back(b.cosE);
        m_soa.twoSided.push_back(b.twoSided ? 1.0f : 0.0f);
    }
    for (std::vector<float>* v : {&m_soa.cx, &m_soa.cy, &m_soa.cz, &m_soa.r2, &m_soa.phi, &m_soa.ax,
                                  &m_soa.ay, &m_soa.az, &m_soa.cosO, &m_soa.sinO, &m_soa.cosE,
                                  &m_soa.twoSided})
        v->resize((v->size() + 7) / 8 * 8, 0.0f);
    if (m_boundedList.size() > kExhaustiveLimit) {
        std::vector<std::size_t> lights = m_boundedList;
        m_nodes.reserve(2 * lights.size());
        buildNode(bounds, lights, 0, lights.size(), 0, 0);
    }
}

// Splits at the median of the centres along the widest axis of their box; a leaf per light.
int LightSampler::buildNode(const std::vector<LightBounds>& bounds, std::vector<std::size_t>& lights,
                            std::size_t begin, std::size_t end, std::uint64_t trail, int depth) {
    int index = int(m_nodes.size());
    m_nodes.emplace_back();
    if (end - begin == 1) {
        std::size_t l = lights[begin];
        m_nodes[std::size_t(index)].bounds = bounds[l];
        m_nodes[std::size_t(index)].child[0] = int(l);
        m_trail[l] = trail;
        m_trailLen[l] = std::uint8_t(depth);
        return index;
    }
    Vec3 lo(kInfinity), hi(-kInfinity);
    for (std::size_t k = begin; k < end; ++k) {
        lo = vmin(lo, bounds[lights[k]].center);
        hi = vmax(hi, bounds[lights[k]].center);
    }
    Vec3 ext = hi - lo;
    int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    auto coord = [&](std::size_t l) { return bounds[l].center[axis]; };
    std::size_t mid = begin + (end - begin) / 2;
    std::nth_element(lights.begin() + std::ptrdiff_t(begin), lights.begin() + std::ptrdiff_t(mid),
                     lights.begin() + std::ptrdiff_t(end), [&](std::size_t a, std::size_t b) {
                         return coord(a) < coord(b) || (coord(a) == coord(b) && a < b);
                     });
    int left = buildNode(bounds, lights, begin, mid, trail, depth + 1);
    int right = buildNode(bounds, lights, mid, end, trail | (std::uint64_t(1) << depth), depth + 1);
    Node& n = m_nodes[std::size_t(index)];
    n.child[0] = left;
    n.child[1] = right;
    n.bounds = merge(m_nodes[std::size_t(left)].bounds, m_nodes[std::size_t(right)].bounds);
    return index;
}

float LightSampler::infiniteShare() const {
    if (m_infiniteList.empty()) return 0.0f;
    if (m_boundedList.empty()) return 1.0f;
    return float(m_infiniteList.size()) / float(m_infiniteList.size() + 1);
}

float LightSampler::infiniteProbability(std::size_t k) const {
    return float(m_infiniteCdf[k] - (k == 0 ? 0.0 : m_infiniteCdf[k - 1]));
}

LightSampler::Pick LightSampler::sample(const Vec3& p, float u) const {
    Pick pick;
    float share = infiniteShare();
    if (u < share) {
        double v = double(u) / double(share);
        std::size_t k = 0;
        while (k + 1 < m_infiniteCdf.size() && !(v < m_infiniteCdf[k])) ++k;
        pick.index = m_infiniteList[k];
        pick.pmf = share * infiniteProbability(k);
        if (pick.pmf > 0) return pick;
        // A light of no weight picked by rounding: nothing (unbiased, a lost sample).
        return Pick{};
    }
    if (m_boundedList.empty()) return pick;
    float rest = 1.0f - share;
    pick = sampleBounded(p, std::min((u - share) / rest, 0.99999994f));
    pick.pmf *= rest;
    return pick;
}

float LightSampler::pmf(const Vec3& p, std::size_t index) const {
    if (index >= m_infinite.size()) return 0.0f;
    float share = infiniteShare();
    if (m_infinite[index]) {
        auto at = std::find(m_infiniteList.begin(), m_infiniteList.end(), index);
        if (at == m_infiniteList.end()) return 0.0f; // excluded
        return share * infiniteProbability(std::size_t(at - m_infiniteList.begin()));
    }
    if (!std::binary_search(m_boundedList.begin(), m_boundedList.end(), index)) return 0.0f;
    return (1.0f - share) * pmfBounded(p, index);
}

float LightSampler::effectiveChoices(const Vec3& p) const {
    double sum = 0, sumSq = 0;
    auto add = [&](double w) {
        sum += w;
        sumSq += w * w;
    };
    // Lights without a position count by their share (it does not depend on p).
    float share = infiniteShare();
    for (std::size_t k = 0; k < m_infiniteList.size(); ++k) add(double(share * infiniteProbability(k)));
    if (!m_boundedList.empty()) {
        static_assert(kExhaustiveLimit <= 16 && (1 << kEffectiveDepth) <= 16);
        alignas(32) float weights[16];
        int count = 0;
        if (m_boundedList.size() == 1) {
            // One light: wherever it can light p it is the choice (sampleBounded).
            weights[count++] = 1.0f;
        } else if (m_nodes.empty()) {
            boundedImportances(p, weights);
            count = int(m_boundedList.size());
        } else {
            // The clusters kEffectiveDepth levels down (or leaves above), by their importance.
            int frontier[1 << kEffectiveDepth];
            frontier[0] = 0;
            count = 1;
            for (int level = 0; level < kEffectiveDepth; ++level) {
                int next[1 << kEffectiveDepth], n = 0;
                for (int k = 0; k < count; ++k) {
                    const Node& node = m_nodes[std::size_t(frontier[k])];
                    if (node.child[1] < 0) next[n++] = frontier[k];
                    else {
                        next[n++] = node.child[0];
                        next[n++] = node.child[1];
                    }
                }
                std::copy(next, next + n, frontier);
                count = n;
            }
            for (int k = 0; k < count; ++k)
                weights[k] = m_nodes[std::size_t(frontier[k])].bounds.importance(p);
        }
        double total = 0;
        for (int k = 0; k < count; ++k) total += double(weights[k]);
        const double rest = 1.0 - double(share);
        if (total > 0)
            for (int k = 0; k < count; ++k) add(rest * double(weights[k]) / total);
    }
    return sumSq > 0 ? float(sum * sum / sumSq) : 0.0f;
}

LightSampler::Pick LightSampler::sampleBounded(const Vec3& p, float u) const {
    Pick pick;
    if (m_boundedList.size() == 1) {
        // One light: wherever it can light p it is the choice; where it cannot, its sample is
        // invalid anyway (and a BSDF ray cannot meet its emitting side).
        pick.index = m_boundedList[0];
        pick.pmf = 1.0f;
        return pick;
    }
    if (m_nodes.empty()) {
        // Few lights: each by its own importance.
        alignas(32) float weights[kExhaustiveLimit];
        float total = boundedImportances(p, weights);
        if (!(total > 0)) return pick;
        // The first light whose running sum passes u total, else (rounding) the last one of
        // positive weight; its pmf divided once, for the light picked.
        float target = u * total, below = 0;
        std::size_t picked = 0;
        for (std::size_t k = 0; k < m_boundedList.size(); ++k) {
            if (!(weights[k] > 0)) continue;
            picked = k;
            if (target < below + weights[k]) break;
            below += weights[k];
        }
        pick.index = m_boundedList[picked];
        pick.pmf = weights[picked] / total;
        return pick;
    }
    // Many: descend by the clusters' importance, reusing u within the chosen child.
    int node = 0;
    float pmf = 1;
    while (m_nodes[std::size_t(node)].child[1] >= 0) {
        const Node& n = m_nodes[std::size_t(node)];
        float w0 = m_nodes[std::size_t(n.child[0])].bounds.importance(p);
        float w1 = m_nodes[std::size_t(n.child[1])].bounds.importance(p);
        if (!(w0 + w1 > 0)) return pick;
        float p0 = w0 / (w0 + w1);
        if (u < p0) {
            u = std::min(u / p0, 0.99999994f);
            pmf *= p0;
            node = n.child[0];
        } else {
            u = std::min((u - p0) / (1 - p0), 0.99999994f);
            pmf *= 1 - p0;
            node = n.child[1];
        }
    }
    pick.index = std::size_t(m_nodes[std::size_t(node)].child[0]);
    pick.pmf = pmf;
    return pick;
}

// Eight lights at a time (kernels/light_importance.h): the components are padded to a multiple
// of 8 with lights of no power.
float LightSampler::boundedImportances(const Vec3& p, float* weights) const {
    const Components& c = m_soa;
    const kernels::BoundsLanes lanes{c.cx.data(),  c.cy.data(),   c.cz.data(),   c.r2.data(),
                                     c.phi.data(), c.ax.data(),   c.ay.data(),   c.az.data(),
                                     c.cosO.data(), c.sinO.data(), c.cosE.data(), c.twoSided.data()};
    const std::size_t n = m_boundedList.size();
    for (std::size_t k = 0; k < n; k += 8) kernels::boundsImportance8(p.x, p.y, p.z, lanes, int(k), weights + k);
    float total = 0;
    for (std::size_t k = 0; k < n; ++k) total += weights[k];
    return total;
}

float LightSampler::pmfBounded(const Vec3& p, std::size_t index) const {
    if (m_boundedList.size() == 1) return 1.0f;
    if (m_nodes.empty()) {
        alignas(32) float weights[kExhaustiveLimit];
        float total = boundedImportances(p, weights);
        if (!(total > 0)) return 0.0f;
        std::size_t k = std::size_t(std::lower_bound(m_boundedList.begin(), m_boundedList.end(), index) -
                                    m_boundedList.begin());
        return weights[k] / total;
    }
    // The same turns the descent would take to this light, each with its probability.
    int node = 0;
    float pmf = 1;
    for (int level = 0; level < m_trailLen[index]; ++level) {
        const Node& n = m_nodes[std::size_t(node)];
        float w0 = m_nodes[std::size_t(n.child[0])].bounds.importance(p);
        float w1 = m_nodes[std::size_t(n.child[1])].bounds.importance(p);
        if (!(w0 + w1 > 0)) return 0.0f;
        bool right = (m_trail[index] >> level) & 1u;
        pmf *= (right ? w1 : w0) / (w0 + w1);
        node = n.child[right ? 1 : 0];
    }
    return pmf;
}

} // namespace rayproc
