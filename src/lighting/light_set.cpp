#include "lighting/light_set.h"

#include "kernels/ray_offset.h"
#include "kernels/sampling.h"
#include "lighting/sphere_mapping.h"

#include <algorithm>
#include <cmath>

namespace rayproc {

namespace {

float smoothStep(float a, float b, float x) {
    if (a == b) return x >= b ? 1.0f : 0.0f;
    float t = std::clamp((x - a) / (b - a), 0.0f, 1.0f);
    return t * t * (3 - 2 * t);
}

// Uniform scale factor of a transform (the cube root of its volume change).
float uniformScale(const Affine& a) { return std::cbrt(std::abs(a.determinant())); }

float pixelMean(const Image& img, int x, int y) {
    const float* p = img.at(x, y);
    float m = (p[0] + p[1] + p[2]) / 3.0f;
    return m > 0 && std::isfinite(m) ? m : 0.0f;
}

// Equal-area pixels all cover 4 pi / N, so the mean over the sphere is the pixel mean.
float goniometricMean(const Image& img) {
    double sum = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) sum += pixelMean(img, x, y);
    return float(sum / (double(img.width) * img.height));
}

LightSource fromSceneLight(const Light& l) {
    LightSource s;
    s.position = l.position;
    s.direction = normalize(l.direction);
    s.intensity = l.intensity;
    s.spectrum = l.spectrum;
    switch (l.type) {
    case LightType::Point: s.kind = LightSource::Kind::Point; break;
    case LightType::Spot:
        s.kind = LightSource::Kind::Spot;
        s.cosCone = std::cos(l.coneAngle * kPi / 180.0f);
        s.cosFalloff = std::cos((l.coneAngle + l.falloffAngle) * kPi / 180.0f);
        break;
    case LightType::Directional: s.kind = LightSource::Kind::Directional; break;
    case LightType::Environment: break; // handled by LightSet::environment
    case LightType::Goniometric:
        s.kind = LightSource::Kind::Point;
        if (l.image && l.image->width > 0 && l.image->height > 0) {
            s.goniometric = l.image;
            s.toLight = l.toWorld.inverse();
            s.goniometricMean = goniometricMean(*l.image);
        }
        break;
    }
    return s;
}

LightSource fromEmitter(const EmitterRecord& e) {
    const Shape& sh = *e.shape;
    LightSource s;
    s.radiance = sh.emission;
    s.spectrum = sh.emissionSpectrum;
    s.twoSided = sh.twoSided;
    switch (sh.type) {
    case ShapeType::Mesh: {
        s.kind = LightSource::Kind::AreaMesh;
        const TriangleMesh& m = *sh.mesh;
        float total = 0;
        for (const Vec3& v : m.positions)
            s.placementError = vmax(s.placementError,
                                    kernels::transformedPointError(e.toWorld, v, Vec3(0.0f)));
        for (std::size_t t = 0; t < m.triangleCount(); ++t) {
            Vec3 a = e.toWorld.point(m.positions[m.indices[3 * t]]);
            Vec3 b = e.toWorld.point(m.positions[m.indices[3 * t + 1]]);
            Vec3 c = e.toWorld.point(m.positions[m.indices[3 * t + 2]]);
            s.triangles.insert(s.triangles.end(), {a, b, c});
            s.triangleNormals.push_back(normalize(cross(b - a, c - a)));
            total += triangleArea(a, b, c);
            s.areaCdf.push_back(total);
        }
        s.area = total;
        Vec3 lo(kInfinity), hi(-kInfinity);
        for (const Vec3& v : s.triangles) {
            lo = vmin(lo, v);
            hi = vmax(hi, v);
        }
        s.boundCenter = 0.5f * (lo + hi);
        s.boundRadius = 0.5f * length(hi - lo);
        // Flat: every triangle's normal within 1e-4 of the first's.
        if (s.triangles.size() >= 3) {
            auto normalOf = [&](std::size_t t) {
                const Vec3* v = &s.triangles[t];
                return normalize(cross(v[1] - v[0], v[2] - v[0]));
            };
            Vec3 n0 = normalOf(0);
            bool flat = isFinite(n0);
            for (std::size_t t = 3; flat && t < s.triangles.size(); t += 3) {
                Vec3 n = normalOf(t);
                flat = isFinite(n) && dot(n, n0) > 1.0f - 1e-4f;
            }
            if (flat) s.flatNormal = n0;
        }
        break;
    }
    case ShapeType::Sphere:
        s.kind = LightSource::Kind::AreaSphere;
        s.center = e.toWorld.point(sh.center);
        s.placementError = kernels::transformedPointError(e.toWorld, sh.center, Vec3(0.0f));
        s.radius = sh.radius * uniformScale(e.toWorld);
        s.area = 4 * kPi * s.radius * s.radius;
        s.boundCenter = s.center;
        s.boundRadius = s.radius;
        break;
    case ShapeType::Disk:
        s.kind = LightSource::Kind::AreaDisk;
        s.center = e.toWorld.point(sh.center);
        s.placementError = kernels::transformedPointError(e.toWorld, sh.center, Vec3(0.0f));
        s.normal = normalize(e.toLocal.normalByInverse(sh.normal));
        s.radius = sh.radius * uniformScale(e.toWorld);
        s.area = kPi * s.radius * s.radius;
        s.boundCenter = s.center;
        s.boundRadius = s.radius;
        s.flatNormal = s.normal;
        break;
    }
    return s;
}

// Radiance leaving a surface point towards `towardsReceiver`.
Vec3 areaRadiance(const LightSource& l, const Vec3& n, const Vec3& towardsReceiver, float& cosL) {
    cosL = dot(n, towardsReceiver);
    if (l.twoSided) cosL = std::abs(cosL);
    return cosL > 0 ? l.radiance : Vec3(0.0f);
}

// A sample at point q (error bound qErr) of an area light with unit normal n. Degenerate
// geometry (a zero normal, a point coinciding with p, a pdf that under- or overflows) gives an
// invalid sample, never a NaN or infinite weight.
LightSample fromAreaPoint(const LightSource& l, const Vec3& p, const Vec3& q, const Vec3& qErr,
                          const Vec3& n, float pdfArea) {
    LightSample s;
    Vec3 d = q - p;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0)) return s;
    s.distance = std::sqrt(dist2);
    s.wi = d / s.distance;
    float cosL;
    Vec3 L = areaRadiance(l, n, -s.wi, cosL);
    if (!(cosL > 0)) return s;
    s.pdf = pdfArea * dist2 / cosL;
    if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return s;
    s.weight = L / s.pdf;
    s.point = q;
    s.pointError = qErr + l.placementError;
    s.normal = n;
    s.valid = isFinite(s.weight);
    return s;
}

// A point or spot light (with a cosine lobe where it stands for a piece of an area light).
LightSample samplePointLight(const LightSource& l, const Vec3& p) {
    LightSample s;
    Vec3 d = l.position - p;
    float dist2 = lengthSquared(d);
    if (dist2 <= 0) return s;
    s.distance = std::sqrt(dist2);
    s.wi = d / s.distance;
    float f = l.directionalFactor(-s.wi);
    if (l.lobe) {
        float c = dot(l.lobeNormal, -s.wi);
        f *= l.lobeTwoSided ? std::abs(c) : std::max(0.0f, c);
    }
    if (f <= 0) return s;
    s.weight = l.intensity * (f / dist2);
    s.point = l.position;
    s.valid = isFinite(s.weight);
    return s;
}

// A mesh light: a triangle picked by area with u.x, then the remainder of u.x reused inside it.
LightSample sampleMeshLight(const LightSource& l, const Vec3& p, Vec2 u) {
    Vec3 qErr, n;
    Vec3 q = meshLightPoint(l, u, qErr, n);
    return fromAreaPoint(l, p, q, qErr, n, 1.0f / l.area);
}

// A sphere light: uniform over the cone of directions it subtends from p, or over its area
// from inside it.
LightSample sampleSphereLight(const LightSource& l, const Vec3& p, Vec2 u) {
    LightSample s;
    Vec3 toC = l.center - p;
    float d2 = lengthSquared(toC);
    if (d2 <= l.radius * l.radius * 1.0001f) {
        // Inside (or on) the sphere: uniform area sampling.
        Vec3 dir = kernels::toWorld(kernels::uniformCone(u, -1.0f), {0, 0, 1});
        Vec3 q = l.center + dir * l.radius;
        return fromAreaPoint(l, p, q, kernels::roundSurfaceError(q, l.center, l.radius), dir,
                             1.0f / l.area);
    }
    // Uniform over the cone of directions the sphere subtends (pdf 1 / solid angle).
    float dist = std::sqrt(d2);
    float sinMax2 = l.radius * l.radius / d2;
    float cosMax = std::sqrt(std::max(0.0f, 1.0f - sinMax2));
    Vec3 axis = toC / dist;
    Vec3 wi = kernels::toWorld(kernels::uniformCone(u, cosMax), axis);
    // Distance to the near intersection with the sphere.
    float b = dot(wi, toC);
    float disc = b * b - (d2 - l.radius * l.radius);
    float t = b - std::sqrt(std::max(0.0f, disc));
    s.wi = wi;
    s.distance = t;
    s.pdf = 1.0f / (2 * kPi * (1 - cosMax));
    if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return s; // the cone is too thin for float
    s.weight = l.radiance / s.pdf;
    // The point on the sphere, re-projected onto it (p + t wi carries the error of p and t).
    Vec3 n = normalize(p + wi * t - l.center);
    s.point = l.center + n * l.radius;
    s.pointError = kernels::roundSurfaceError(s.point, l.center, l.radius) + l.placementError;
    s.normal = n;
    s.valid = isFinite(s.weight);
    return s;
}

} // namespace

Vec3 meshLightPoint(const LightSource& l, Vec2 u, Vec3& err, Vec3& n) {
    float target = u.x * l.area;
    std::size_t t =
        std::lower_bound(l.areaCdf.begin(), l.areaCdf.end(), target) - l.areaCdf.begin();
    t = std::min(t, l.areaCdf.size() - 1);
    float lo = t == 0 ? 0.0f : l.areaCdf[t - 1];
    float width = l.areaCdf[t] - lo;
    float ux = width > 0 ? std::clamp((target - lo) / width, 0.0f, 0.99999994f) : 0.5f;
    Vec2 b = kernels::uniformTriangle({ux, u.y});
    const Vec3 &a = l.triangles[3 * t], &bb = l.triangles[3 * t + 1], &c = l.triangles[3 * t + 2];
    n = l.triangleNormals[t];
    return kernels::trianglePoint(a, bb, c, b.x, b.y, err);
}

LightSample LightSource::sample(const Vec3& p, Vec2 u) const {
    switch (kind) {
    case Kind::Point:
    case Kind::Spot:
        return samplePointLight(*this, p);
    case Kind::Directional: {
        LightSample s;
        s.wi = -direction;
        s.distance = kInfinity;
        s.weight = intensity;
        s.valid = true;
        return s;
    }
    case Kind::AreaMesh:
        return sampleMeshLight(*this, p, u);
    case Kind::AreaSphere:
        return sampleSphereLight(*this, p, u);
    case Kind::AreaDisk: {
        Vec2 d = kernels::concentricDisk(u);
        Vec3 q = kernels::toWorld({d.x * radius, d.y * radius, 0}, normal) + center;
        return fromAreaPoint(*this, p, q, kernels::roundSurfaceError(q, center, radius), normal,
                             1.0f / area);
    }
    }
    return LightSample();
}

float LightSource::directionalFactor(const Vec3& wOut) const {
    if (kind == Kind::Spot) return smoothStep(cosFalloff, cosCone, dot(wOut, direction));
    if (!goniometric) return 1.0f;
    Vec3 d = toLight.vector(wOut);
    float len = length(d);
    if (!(len > 0)) return 0.0f;
    Vec2 uv = equalAreaSphereToSquare(d / len);
    int res = goniometric->width;
    int x = int(std::floor(uv.x * float(res))), y = int(std::floor(uv.y * float(res)));
    wrapEqualAreaPixel(x, y, res);
    return pixelMean(*goniometric, x, y);
}

float LightSource::pdf(const Vec3& p, const Vec3& q, const Vec3& nq) const {
    if (delta()) return 0.0f;
    Vec3 d = q - p;
    float dist2 = lengthSquared(d);
    if (dist2 <= 0) return 0.0f;
    if (kind == Kind::AreaSphere) {
        float c2 = lengthSquared(center - p);
        if (c2 > radius * radius * 1.0001f) {
            float cosMax = std::sqrt(std::max(0.0f, 1.0f - radius * radius / c2));
            return 1.0f / (2 * kPi * (1 - cosMax));
        }
    }
    float cosL = std::abs(dot(nq, d)) / std::sqrt(dist2);
    if (cosL <= 0) return 0.0f;
    return dist2 / (cosL * area);
}

Vec3 LightSource::power() const {
    switch (kind) {
    case Kind::Point: return intensity * (4 * kPi * goniometricMean);
    case Kind::Spot: return intensity * (2 * kPi * (1 - 0.5f * (cosCone + cosFalloff)));
    case Kind::Directional: return Vec3(0.0f); // needs the scene's extent; see photon emitter
    default: return radiance * (kPi * area * (twoSided ? 2.0f : 1.0f));
    }
}

namespace {
double luminanceD(const Vec3& c) {
    return std::max(0.0, 0.2126 * double(c.x) + 0.7152 * double(c.y) + 0.0722 * double(c.z));
}
} // namespace

double LightSource::boundsPower() const {
    switch (kind) {
    case Kind::Directional: return 0;
    // A spot as a point light of its intensity (pbrt-v4's SpotLight::Bounds): inside its cone
    // it lights a point as I / d^2 whatever the cone's width, and its total power would rate a
    // narrow spot far below what it gives there (a glossy highlight of it was a firefly of
    // 1 / pmf); the cone cuts the rest off. A lobe point light I cos(theta) likewise, the
    // cone's cosine its lobe.
    case Kind::Spot: return luminanceD(intensity) * 4 * double(kPi);
    case Kind::Point:
        return luminanceD(intensity) * 4 * double(kPi) * (lobe ? 1.0 : double(goniometricMean));
    default:
        return luminanceD(radiance) * double(kPi) * double(area) * (twoSided ? 2.0 : 1.0);
    }
}

LightBounds LightSource::makeBounds(double powerScale) const {
    LightBounds b;
    if (kind == Kind::Directional) return b; // no position: LightSampler's fixed share
    b.phi = float(boundsPower() * powerScale);
    if (kind == Kind::Point || kind == Kind::Spot) {
        b.center = position;
        if (kind == Kind::Spot) {
            b.axis = direction;
            b.thetaO = std::acos(std::clamp(cosCone, -1.0f, 1.0f));
            // The smooth step's edge: at thetaO + thetaE the intensity is 0.
            b.thetaE = std::max(0.0f, std::acos(std::clamp(cosFalloff, -1.0f, 1.0f)) - b.thetaO);
        } else if (lobe) {
            b.axis = lobeNormal;
            b.thetaO = 0;
            b.twoSided = lobeTwoSided;
        }
    } else {
        b.center = boundCenter;
        b.radius = boundRadius * (1.0f + 1e-5f) + length(placementError);
        if (!isBlack(flatNormal)) {
            // A Lambertian plane: the cone of its normal, thetaE = pi/2 beyond it.
            b.axis = flatNormal;
            b.thetaO = 0;
            b.twoSided = twoSided;
        }
    }
    b.updateCone();
    return b;
}

double LightSet::radianceScale(const Bounds3& sceneBounds) const {
    double r2 = 1;
    if (!sceneBounds.empty()) {
        double dx = double(sceneBounds.hi.x) - sceneBounds.lo.x,
               dy = double(sceneBounds.hi.y) - sceneBounds.lo.y,
               dz = double(sceneBounds.hi.z) - sceneBounds.lo.z;
        r2 = std::max(0.25 * (dx * dx + dy * dy + dz * dz), 1e-300);
    }
    double brightest = 0;
    for (const LightSource& l : lights) {
        bool delta = l.kind == LightSource::Kind::Point || l.kind == LightSource::Kind::Spot;
        Vec3 v = delta || l.kind == LightSource::Kind::Directional ? l.intensity : l.radiance;
        brightest = std::max(brightest, double(maxComponent(v)) / (delta ? r2 : 1.0));
    }
    if (hasEnvironment()) brightest = std::max(brightest, double(maxComponent(environment.average())));
    return brightest;
}

LightSet::Choice LightSet::choiceAt(std::size_t i, const Vec3& p, int n) const {
    Choice c;
    c.samples = areaSamples(p, n);
    c.probability = c.samples > 0 ? areaSampler.pmf(p, i) : 0.0f;
    return c;
}

int LightSet::areaSamples(const Vec3& p, int n) const {
    float effective = areaSampler.effectiveChoices(p);
    if (!(effective > 0)) return 0;
    return std::max(n, int(std::lround(double(n) * effective)));
}

LightSet LightSet::build(const Scene& scene, const EmbreeScene& accel) {
    LightSet set;
    for (const Light& l : scene.lights) {
        if (l.type == LightType::Environment && !isBlack(l.intensity)) set.environment.add(l);
        else set.lights.push_back(fromSceneLight(l));
    }
    for (const EmitterRecord& e : accel.emitters()) {
        LightSource a = fromEmitter(e);
        // A light without area (degenerate triangles, radius 0) emits nothing and cannot be
        // sampled (its pdf would be 1/0); rays cannot hit it either.
        if (!(a.area > 0) || !std::isfinite(a.area)) continue;
        set.m_areaIndex.push_back({{e.shape, e.instance}, int(set.lights.size())});
        set.lights.push_back(std::move(a));
        ++set.m_areaLights;
    }
    std::sort(set.m_areaIndex.begin(), set.m_areaIndex.end());
    for (std::size_t i = 0; i < set.lights.size(); ++i) set.lights[i].stream = std::uint32_t(i);
    set.buildSampler();
    return set;
}

void LightSet::buildSampler() {
    // Powers relative to the strongest light's (in double), so that lights up to float's limit
    // weigh without overflowing.
    double strongest = 0;
    for (const LightSource& l : lights)
        if (std::isfinite(l.boundsPower())) strongest = std::max(strongest, l.boundsPower());
    const double scale = strongest > 0 ? 1.0 / strongest : 1.0;
    std::vector<LightBounds> bounds;
    std::vector<bool> infinite;
    for (LightSource& l : lights) {
        l.bounds = l.makeBounds(scale);
        bounds.push_back(l.bounds);
        infinite.push_back(l.kind == LightSource::Kind::Directional);
    }
    // Lights without a position weigh by the irradiance they can give a point (a directional
    // light's own, the sky's pi times its mean radiance), relative to the largest (in double).
    std::vector<double> irradiance(lights.size(), 0.0);
    for (std::size_t i = 0; i < lights.size(); ++i)
        if (infinite[i]) irradiance[i] = luminanceD(lights[i].intensity);
    if (hasEnvironment()) {
        bounds.emplace_back();
        infinite.push_back(true);
        irradiance.push_back(double(kPi) * luminanceD(environment.average()));
    }
    double largest = 0;
    for (double e : irradiance)
        if (std::isfinite(e)) largest = std::max(largest, e);
    for (std::size_t i = 0; i < bounds.size(); ++i)
        if (infinite[i] && largest > 0)
            bounds[i].phi = std::isfinite(irradiance[i]) ? float(irradiance[i] / largest) : 1.0f;
    sampler.build(bounds, infinite);
    // The same choice among the area lights alone (raytrace and gi sample delta lights and the
    // sky apart).
    std::vector<bool> notArea(bounds.size(), true);
    for (std::size_t i = 0; i < lights.size(); ++i) notArea[i] = lights[i].delta();
    areaSampler.build(bounds, infinite, notArea);
}

int LightSet::indexOf(const Shape* shape, int instance) const {
    auto key = std::make_pair(shape, instance);
    auto it = std::lower_bound(m_areaIndex.begin(), m_areaIndex.end(), key,
                               [](const auto& e, const auto& k) { return e.first < k; });
    return it != m_areaIndex.end() && it->first == key ? it->second : -1;
}

LightSet LightSet::buildPreview(const Scene& scene, const EmbreeScene& accel) {
    LightSet set;
    for (const Light& l : scene.lights) {
        if (l.type == LightType::Environment && !isBlack(l.intensity)) set.environment.add(l);
        else set.lights.push_back(fromSceneLight(l));
    }
    EmissionSpectrumRef spectrum; // the emitter's whose points addPoint adds
    auto addPoint = [&](const Vec3& pos, const Vec3& n, const Vec3& intensity, bool twoSided,
                        bool lobe) {
        LightSource p;
        p.spectrum = spectrum;
        p.kind = LightSource::Kind::Point;
        p.position = pos;
        p.intensity = intensity;
        p.lobe = lobe;
        p.lobeNormal = n;
        p.lobeTwoSided = twoSided;
        set.lights.push_back(p);
    };
    for (const EmitterRecord& e : accel.emitters()) {
        LightSource a = fromEmitter(e);
        if (!(a.area > 0) || !std::isfinite(a.area)) continue; // emits nothing
        spectrum = a.spectrum;
        const Shape& sh = *e.shape;
        // A Lambertian emitter of area A radiates I(theta) = L A cos(theta): split among points.
        if (a.kind == LightSource::Kind::AreaMesh && sh.isQuad) {
            const TriangleMesh& m = *sh.mesh;
            Vec3 n = normalize(cross(a.triangles[1] - a.triangles[0], a.triangles[2] - a.triangles[0]));
            for (std::size_t i = 0; i < 4 && i < m.positions.size(); ++i)
                addPoint(e.toWorld.point(m.positions[i]), n, a.radiance * (a.area / 4), a.twoSided, true);
        } else if (a.kind == LightSource::Kind::AreaMesh) {
            for (std::size_t t = 0; t < a.areaCdf.size(); ++t) {
                const Vec3 *v = &a.triangles[3 * t];
                Vec3 c = cross(v[1] - v[0], v[2] - v[0]);
                float area = triangleArea(v[0], v[1], v[2]);
                addPoint((v[0] + v[1] + v[2]) / 3.0f, normalize(c), a.radiance * area, a.twoSided, true);
            }
        } else if (a.kind == LightSource::Kind::AreaSphere) {
            // A sphere radiates L * pi r^2 in every direction.
            addPoint(a.center, {0, 1, 0}, a.radiance * (kPi * a.radius * a.radius), false, false);
        } else {
            addPoint(a.center, a.normal, a.radiance * a.area, a.twoSided, true);
        }
    }
    for (std::size_t i = 0; i < set.lights.size(); ++i) set.lights[i].stream = std::uint32_t(i);
    set.buildSampler();
    return set;
}

LightSet LightSet::subset(const std::vector<bool>& keep) const {
    LightSet out;
    out.environment = environment;
    std::vector<int> index(lights.size(), -1);
    for (std::size_t i = 0; i < lights.size(); ++i) {
        if (i < keep.size() && !keep[i]) continue;
        index[i] = int(out.lights.size());
        out.lights.push_back(lights[i]);
        if (!lights[i].delta()) ++out.m_areaLights;
    }
    for (const auto& e : m_areaIndex)
        if (index[std::size_t(e.second)] >= 0) out.m_areaIndex.push_back({e.first, index[std::size_t(e.second)]});
    out.buildSampler();
    return out;
}

} // namespace rayproc
