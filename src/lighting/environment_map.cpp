#include "lighting/environment_map.h"

#include "core/named_loop.h"
#include "core/uninitialized.h"
#include "lighting/sphere_mapping.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace rayproc {

namespace {

float channelMean(const Vec3& c) { return (c.x + c.y + c.z) / 3.0f; }

// sin theta at the centre of lat-long row y of h rows.
float rowSinTheta(int y, int h) { return std::sin(kPi * (float(y) + 0.5f) / float(h)); }

// body(rows) over blocks of the map's h rows, on every thread.
template <typename Body>
void forEachRowBlock(int h, const Body& body) {
    namedLoop("environment_rows",
              [&] { tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), body); });
}

} // namespace

EnvironmentLight::Map::Map(const Light& light)
    : image(light.image), scale(light.intensity), mapping(light.mapping), toWorld(light.toWorld),
      toLight(light.toWorld.inverse()) {
    const int w = image->width, h = image->height;
    const std::size_t n = std::size_t(w) * std::size_t(h);
    std::vector<float> weights(n);
    // Equal-area pixels all cover 4 pi / N; lat-long pixels cover 2 pi^2 sin(theta) / N.
    auto areaOf = [&](int y) {
        return mapping == EnvironmentMapping::LatLong ? rowSinTheta(y, h) : 1.0f;
    };
    // Each pixel's radiance times its area and channel mean, rows in parallel; then the sums
    // over the pixels in one order, as one loop over them made them.
    UninitializedFloats weighted(3 * n), means(n);
    forEachRowBlock(h, [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) {
            const float area = areaOf(y);
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                const Vec3 L = pixelRadiance(x, y), a = L * area;
                means[i] = channelMean(L);
                weights[i] = means[i] * area;
                weighted[3 * i] = a.x, weighted[3 * i + 1] = a.y, weighted[3 * i + 2] = a.z;
            }
        }
    });
    double sumW = 0;
    Vec3 sum{0, 0, 0};
    for (int y = 0; y < h; ++y) {
        const float area = areaOf(y);
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            sum += Vec3(weighted[3 * i], weighted[3 * i + 1], weighted[3 * i + 2]);
            sumW += area;
        }
    }
    if (mapping == EnvironmentMapping::LatLong) // the sphere's 4 pi = sum of 2 pi^2 sin / N
        average = sum * float(2 * kPi * kPi / (4 * kPi * double(w) * h));
    else
        average = sum / float(sumW);
    // The compensated density: each pixel's excess over the sphere's mean, times its area
    // (rows in parallel: no sum crosses them; the sum above stays in one order).
    const float mean = channelMean(average);
    std::vector<float> excess(weights.size());
    std::vector<char> rowAny(std::size_t(h), 0);
    forEachRowBlock(h, [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) {
            const float area = areaOf(y);
            for (int x = 0; x < w; ++x) {
                float e = std::max(0.0f, means[std::size_t(y) * w + x] - mean) * area;
                excess[std::size_t(y) * w + x] = e;
                rowAny[std::size_t(y)] |= char(e > 0);
            }
        }
    });
    const bool any = std::find(rowAny.begin(), rowAny.end(), char(1)) != rowAny.end();
    distribution = Distribution2D(std::move(weights), w, h);
    compensated = any ? Distribution2D(std::move(excess), w, h) : distribution;
}

void EnvironmentLight::Map::pixelOf(const Vec3& d, int& x, int& y) const {
    const int w = image->width, h = image->height;
    if (mapping == EnvironmentMapping::EqualArea) {
        Vec2 uv = equalAreaSphereToSquare(d);
        x = int(std::floor(uv.x * float(w)));
        y = int(std::floor(uv.y * float(h)));
        wrapEqualAreaPixel(x, y, w); // uv == 1 lands one past the edge: fold it back
        return;
    }
    Vec2 uv = sphereToLatLong(d);
    x = int(std::floor(uv.x * float(w))) % w;
    y = std::clamp(int(std::floor(uv.y * float(h))), 0, h - 1);
}

Vec3 EnvironmentLight::Map::pixelRadiance(int x, int y) const {
    const float* p = image->at(x, y);
    Vec3 c{std::max(0.0f, p[0]), std::max(0.0f, p[1]), std::max(0.0f, p[2])};
    return isFinite(c) ? c * scale : Vec3(0.0f);
}

// Equal-area: d(omega) = 4 pi d(uv); lat-long: d(omega) = 2 pi^2 sin(theta) d(uv), with
// sin theta from the direction's xy (accurate near the poles, unlike sqrt(1 - z^2)).
float EnvironmentLight::Map::solidAnglePdf(float pdfUv, const Vec3& d) const {
    if (mapping == EnvironmentMapping::EqualArea) return pdfUv / (4 * kPi);
    float sinTheta = std::sqrt(d.x * d.x + d.y * d.y);
    return sinTheta > 0 ? pdfUv / (2 * kPi * kPi * sinTheta) : 0.0f;
}

Vec3 EnvironmentLight::Map::radiance(const Vec3& dirWorld) const {
    Vec3 d = toLight.vector(dirWorld);
    float len = length(d);
    if (!(len > 0)) return Vec3(0.0f);
    int x, y;
    pixelOf(d / len, x, y);
    return pixelRadiance(x, y);
}

float EnvironmentLight::Map::pdf(const Vec3& dirWorld, bool comp) const {
    Vec3 d = toLight.vector(dirWorld);
    float len = length(d);
    if (!(len > 0)) return 0.0f;
    d = d / len;
    int x, y;
    pixelOf(d, x, y);
    return solidAnglePdf((comp ? compensated : distribution).pdfCell(x, y), d);
}

Vec3 EnvironmentLight::Map::sample(Vec2 u, float& pdf, Vec3& L, bool comp) const {
    pdf = 0;
    const Distribution2D& dist = comp ? compensated : distribution;
    if (!dist.valid()) return Vec3(0.0f);
    float pdfUv;
    int x, y;
    Vec2 uv = dist.sample(u, pdfUv, x, y);
    Vec3 d = mapping == EnvironmentMapping::EqualArea ? equalAreaSquareToSphere(uv)
                                                      : latLongToSphere(uv);
    pdf = solidAnglePdf(pdfUv, d);
    // The radiance and density of the pixel the direction maps back to (the same pixel up to
    // rounding at its edges), so that weight and pdf() agree exactly.
    int px, py;
    pixelOf(d, px, py);
    L = pixelRadiance(px, py);
    if (px != x || py != y) pdf = this->pdf(toWorld.vector(d), comp);
    return normalize(toWorld.vector(d));
}

} // namespace rayproc
