#include "gi/photon_emitter.h"

#include "engine/path_state.h"
#include "engine/spectral_render.h"
#include "gi/gi_pipeline.h"
#include "kernels/random.h"
#include "kernels/ray_offset.h"
#include "kernels/sampling.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace rayproc {

namespace {

// Power leaving a light, RGB (W), in double: it can pass float's range though every factor is
// within it (radiance 3e37 over a few m^2; a directional light over a 1e15-wide scene).
// Directional lights and the sky are measured through a disk of radius r covering the scene.
std::array<double, 3> emittedPower(const LightSource& l, double r) {
    double factor = 0;
    Vec3 base = l.kind == LightSource::Kind::AreaMesh || l.kind == LightSource::Kind::AreaSphere ||
                        l.kind == LightSource::Kind::AreaDisk
                    ? l.radiance
                    : l.intensity;
    switch (l.kind) {
    case LightSource::Kind::Point: factor = 4 * kPi * double(l.goniometricMean); break;
    case LightSource::Kind::Spot:
        factor = 2 * kPi * (1 - 0.5 * (double(l.cosCone) + double(l.cosFalloff)));
        break;
    case LightSource::Kind::Directional: factor = kPi * r * r; break;
    default: factor = kPi * double(l.area) * (l.twoSided ? 2.0 : 1.0); break;
    }
    return {double(base.x) * factor, double(base.y) * factor, double(base.z) * factor};
}

std::array<double, 3> environmentPower(const LightSet& lights, double r) {
    Vec3 avg = lights.environment.average(); // radiance from every direction through the disk
    double factor = 4 * kPi * kPi * r * r;
    return {double(avg.x) * factor, double(avg.y) * factor, double(avg.z) * factor};
}

Vec3 scaled(const Vec3& v, double factor) {
    return {float(double(v.x) * factor), float(double(v.y) * factor), float(double(v.z) * factor)};
}

// In units of `unit` (a power of two): the float power as it was computed before units existed
// where it is finite, so the same photons to the bit; the double one where float overflowed.
Vec3 inUnits(const Vec3& asFloat, const std::array<double, 3>& asDouble, double unit) {
    if (isFinite(asFloat)) return scaled(asFloat, 1 / unit);
    return {float(asDouble[0] / unit), float(asDouble[1] / unit), float(asDouble[2] / unit)};
}

double luminanceOf(const std::array<double, 3>& p) {
    return std::max(0.0, 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]);
}

float diskRadius(const Bounds3& bounds) {
    return bounds.empty() ? 1.0f : std::max(1e-6f, 0.5f * length(bounds.diagonal()));
}

} // namespace

double PhotonEmitter::powerUnit(const LightSet& lights, const Bounds3& sceneBounds) {
    double r = diskRadius(sceneBounds), total = 0;
    for (const LightSource& l : lights.lights) total += luminanceOf(emittedPower(l, r));
    if (lights.hasEnvironment()) total += luminanceOf(environmentPower(lights, r));
    if (!(total > 0) || !std::isfinite(total)) return 1.0;
    int e = std::ilogb(total);
    return std::abs(e) <= kWattsRange ? 1.0 : std::ldexp(1.0, e);
}

PhotonEmitter::PhotonEmitter(const LightSet& lights, const Bounds3& bounds, std::uint32_t count,
                             std::uint64_t seed, std::uint64_t tag, const Bounds3& focus,
                             float focusShare)
    : m_lights(lights), m_count(count), m_key(kernels::hashCombine(kernels::mix64(seed), tag)) {
    m_last = count;
    m_center = bounds.empty() ? Vec3(0.0f) : bounds.center();
    m_radius = diskRadius(bounds);
    m_unit = powerUnit(lights, bounds);
    if (!focus.empty() && focusShare > 0) {
        m_focusCenter = focus.center();
        m_focusRadius = 0.5f * length(focus.diagonal());
        if (m_focusRadius > 0 && std::isfinite(m_focusRadius))
            m_focusShare = std::min(focusShare, 1.0f);
    }
    float total = 0;
    auto add = [&](const Vec3& p) {
        m_power.push_back(p);
        m_totalPower += p;
        total += std::max(0.0f, luminance(p));
        m_cdf.push_back(total);
    };
    for (const LightSource& l : lights.lights) {
        Vec3 p = l.kind == LightSource::Kind::Directional
                     ? l.intensity * (kPi * m_radius * m_radius)
                     : l.power();
        add(inUnits(p, emittedPower(l, m_radius), m_unit));
    }
    if (lights.hasEnvironment()) // radiance L from every direction through a disk of radius r
        add(inUnits(lights.environment.average() * (4 * kPi * kPi * m_radius * m_radius),
                    environmentPower(lights, m_radius), m_unit));
    if (total <= 0) m_cdf.clear();
}

Vec3 PhotonEmitter::diskPoint(const Vec3& dir, Vec2 u, float uChoice, float& invDensity) const {
    // The plane lies 2r behind the scene's centre: every photon starts outside the scene.
    Vec3 planeCenter = m_center - dir * (2 * m_radius);
    Vec2 d = kernels::concentricDisk(u);
    if (m_focusShare <= 0) {
        invDensity = kPi * m_radius * m_radius;
        return planeCenter + kernels::toWorld({d.x * m_radius, d.y * m_radius, 0}, dir);
    }
    // The focus disk: the focus region's bounding sphere projected along dir onto the plane.
    Vec3 focusCenter = m_focusCenter - dir * dot(m_focusCenter - planeCenter, dir);
    bool toFocus = uChoice < m_focusShare;
    float r = toFocus ? m_focusRadius : m_radius;
    Vec3 p = (toFocus ? focusCenter : planeCenter) + kernels::toWorld({d.x * r, d.y * r, 0}, dir);
    // The mixture's density at p counts both disks wherever they overlap.
    float density = 0;
    if (lengthSquared(p - focusCenter) <= m_focusRadius * m_focusRadius * (1 + 1e-5f))
        density += m_focusShare / (kPi * m_focusRadius * m_focusRadius);
    if (lengthSquared(p - planeCenter) <= m_radius * m_radius * (1 + 1e-5f))
        density += (1 - m_focusShare) / (kPi * m_radius * m_radius);
    invDensity = density > 0 ? 1.0f / density : 0.0f;
    return p;
}

PhotonEmitter::Emission PhotonEmitter::emitOne(std::uint32_t index) const {
    Choice ch;
    // Stratified choices: each dimension pair permutes the photons independently (padded).
    ch.uPick = kernels::stratified2D(index, m_count, kernels::hashCombine(m_key, 1));
    ch.uPos = kernels::stratified2D(index, m_count, kernels::hashCombine(m_key, 2));
    ch.uDir = kernels::stratified2D(index, m_count, kernels::hashCombine(m_key, 3));
    float target = ch.uPick.x * m_cdf.back();
    std::size_t c = std::size_t(std::lower_bound(m_cdf.begin(), m_cdf.end(), target) - m_cdf.begin());
    c = std::min(c, m_cdf.size() - 1);
    float prev = c == 0 ? 0.0f : m_cdf[c - 1];
    ch.pChoice = (m_cdf[c] - prev) / m_cdf.back();
    if (ch.pChoice <= 0) return Emission();
    ch.light = c;
    ch.share = m_power[c] / (ch.pChoice * float(m_count)); // flux per photon of this light
    const bool sky = c == m_lights.lights.size();
    Emission e = sky ? emitFromSky(ch) : emitFromLight(m_lights.lights[c], ch);
    e.deltaOrSky = sky || m_lights.lights[c].delta();
    e.light = c;
    return e;
}

float PhotonEmitter::lambdaU(std::uint32_t index) const {
    // One stratum of [0, 1) per photon of the pass, in an order of its own (a fifth stream).
    const std::uint64_t key = kernels::hashCombine(m_key, 5);
    float u = (float(kernels::permute(index, m_count, key)) + kernels::uniform(key, index)) /
              float(m_count);
    return std::min(u, 0x1.fffffep-1f);
}

// The RGB power is the light's radiance (or intensity, or the sky's radiance) times a scalar:
// the light's illuminant spectrum takes the same scalar (SpectralRender::lightValue); the sky,
// whose value varies with direction, takes it as path mode's sky does (SpectralRender::sky).
Vec3 PhotonEmitter::spectralPower(const Emission& e, float u) const {
    const LaneSpectrum lane = m_spectral->lane(u);
    if (e.light < m_lights.lights.size()) return m_spectral->lightValue(e.light, e.power, lane);
    return m_spectral->sky(e.power, lane);
}

// Directional and sky photons start on a disk (uPick.y, unused by them otherwise, picks the
// focus or the whole disk); diskArea is the inverse density of the chosen point.
PhotonEmitter::Emission PhotonEmitter::emitFromSky(const Choice& ch) const {
    Emission e;
    float diskArea = 0;
    if (m_lights.environment.cosineSampled()) { // constant: uniform directions
        e.direction = kernels::toWorld(kernels::uniformCone(ch.uDir, -1.0f), {0, 0, 1});
        e.origin = diskPoint(e.direction, ch.uPos, ch.uPick.y, diskArea);
        e.power = m_focusShare > 0 ? ch.share * (diskArea / (kPi * m_radius * m_radius)) : ch.share;
        e.valid = diskArea > 0;
        return e;
    }
    // An image sky: the direction light arrives from is drawn by the sky's density, the
    // photon travels the opposite way through the disk; its flux is L / pdf times the
    // disk's area pi r^2, shared among this light's photons.
    EnvironmentSample s = m_lights.environment.sampleSphere(ch.uDir);
    if (!s.valid) return e;
    e.direction = -s.wi;
    e.origin = diskPoint(e.direction, ch.uPos, ch.uPick.y, diskArea);
    // L / pdf can pass float's range where L does not: then it is made in double.
    Vec3 weight = isFinite(s.weight)
                      ? scaled(s.weight, 1 / m_unit)
                      : scaled(m_lights.environment.radiance(s.wi), 1 / (double(s.pdf) * m_unit));
    e.power = weight * (diskArea / (ch.pChoice * float(m_count)));
    e.valid = isFinite(e.power);
    return e;
}

PhotonEmitter::Emission PhotonEmitter::emitFromLight(const LightSource& l, const Choice& ch) const {
    Emission e;
    switch (l.kind) {
    case LightSource::Kind::Point:
        e.origin = l.position;
        e.direction = kernels::toWorld(kernels::uniformCone(ch.uDir, -1.0f), {0, 0, 1});
        e.power = ch.share;
        if (l.goniometric) // uniform directions; the image's factor relative to its mean
            e.power = ch.share * (l.directionalFactor(e.direction) / l.goniometricMean);
        e.valid = !isBlack(e.power);
        return e;
    case LightSource::Kind::Spot: {
        // Uniform in the outer cone; the falloff scales the photon's power.
        e.origin = l.position;
        e.direction = kernels::toWorld(kernels::uniformCone(ch.uDir, l.cosFalloff), l.direction);
        float cosT = dot(e.direction, l.direction);
        float t = l.cosCone == l.cosFalloff ? 1.0f
                  : std::clamp((cosT - l.cosFalloff) / (l.cosCone - l.cosFalloff), 0.0f, 1.0f);
        float f = t * t * (3 - 2 * t);
        float solid = 2 * kPi * (1 - l.cosFalloff);
        e.power = scaled(l.intensity, 1 / m_unit) * (f * solid / (ch.pChoice * float(m_count)));
        e.valid = f > 0;
        return e;
    }
    case LightSource::Kind::Directional: {
        float diskArea = 0;
        e.direction = l.direction;
        e.origin = diskPoint(l.direction, ch.uPos, ch.uPick.y, diskArea);
        e.power = m_focusShare > 0 ? ch.share * (diskArea / (kPi * m_radius * m_radius)) : ch.share;
        e.valid = diskArea > 0;
        return e;
    }
    case LightSource::Kind::AreaMesh: {
        Vec3 err, n;
        Vec3 p = meshLightPoint(l, ch.uPos, err, n);
        return lambertian(p, err + l.placementError, n, l.twoSided, ch);
    }
    case LightSource::Kind::AreaSphere: {
        Vec3 n = kernels::toWorld(kernels::uniformCone(ch.uPos, -1.0f), {0, 0, 1});
        Vec3 p = l.center + n * l.radius;
        return lambertian(p, kernels::roundSurfaceError(p, l.center, l.radius) + l.placementError,
                          n, l.twoSided, ch);
    }
    case LightSource::Kind::AreaDisk: {
        Vec2 d = kernels::concentricDisk(ch.uPos);
        Vec3 p = l.center + kernels::toWorld({d.x * l.radius, d.y * l.radius, 0}, l.normal);
        return lambertian(p, kernels::roundSurfaceError(p, l.center, l.radius) + l.placementError,
                          l.normal, l.twoSided, ch);
    }
    }
    return e;
}

// Lambertian emitters: cosine-weighted directions carry the flux exactly. The photon starts
// off the surface on the side it leaves, like every spawned ray: from the surface point itself
// it could hit its own emitter at t ~ 0 and be stored there (an inward emitting sphere then
// kept a share of its photons at the emission points). `err` bounds the rounding of p
// (docs/robustness.md): the photon leaves its error box.
PhotonEmitter::Emission PhotonEmitter::lambertian(const Vec3& p, const Vec3& err, Vec3 n,
                                                  bool twoSided, const Choice& ch) const {
    Emission e;
    if (twoSided && ch.uPick.y < 0.5f) n = -n;
    e.direction = kernels::toWorld(kernels::cosineHemisphere(ch.uDir), n);
    e.origin = kernels::offsetRayOrigin(p, err, n, e.direction);
    e.power = ch.share;
    e.valid = true;
    return e;
}

void PhotonEmitter::setRange(std::uint64_t first, std::uint64_t last) {
    m_last = std::min<std::uint64_t>(last, m_count);
    m_first = std::min(first, m_last);
}

std::uint64_t PhotonEmitter::photonsEmitted() const {
    return std::min<std::uint64_t>(m_next.load() * kBatchSize, m_last - m_first);
}

bool PhotonEmitter::emit(StageContext& ctx) {
    if (m_cdf.empty()) return false;
    std::uint64_t unit = m_next.fetch_add(1);
    std::uint64_t first = m_first + unit * kBatchSize;
    if (first >= m_last) return false;
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, kPhotonStageId);
    ctx.flush(kPhotonRay); // a fresh batch: emitted photons queue behind bounces
    PhotonBatch& b = ctx.outPhotons(kPhotonRay);
    b.fresh = true;
    std::uint64_t last = std::min<std::uint64_t>(first + kBatchSize, m_last);
    for (std::uint64_t k = first; k < last; ++k) {
        Emission e = emitOne(std::uint32_t(k));
        if (!e.valid || isBlack(e.power)) continue;
        const float u = m_spectral ? lambdaU(std::uint32_t(k)) : 0.0f;
        if (m_spectral) e.power = spectralPower(e, u);
        int j = b.push(e.origin.x, e.origin.y, e.origin.z, e.direction.x, e.direction.y,
                       e.direction.z, 0.0f, kInfinity);
        b.index[j] = std::uint32_t(k);
        b.wr[j] = e.power.x; b.wg[j] = e.power.y; b.wb[j] = e.power.z;
        b.rngKey[j] = kernels::hashCombine(m_key, k + 0x1000);
        b.depth[j] = 0;
        b.flags[j] = e.deltaOrSky ? kPhotonDeltaOrSky : 0;
        b.lambdaU[j] = u;
    }
    stats.stages[int(kPhotonStageId)].raysOut += std::uint64_t(b.count);
    if (b.count == 0) b.fresh = false; // stays open for bounces
    ctx.flush(kPhotonRay);
    return true;
}

} // namespace rayproc
