#include "engine/spectral_render.h"

#include "lighting/light_set.h"
#include "scene/reflectance_spectrum.h"
#include "scene/scene.h"
#include "spectral/rgb_spectrum.h"
#include "spectral/spectra.h"

#include <algorithm>
#include <cmath>

namespace rayproc {

namespace {

namespace ks = kernels::spectral;

// The index of the nanometre sample nearest `lambda` (nm, in the visible range), as
// kernels::spectral::denseAt takes it.
int nearestNm(float lambda) {
    return std::min(std::max(int(lambda - ks::kLambdaMin + 0.5f), 0), ks::kDenseCount - 1);
}

UpsampledRgb fromPolynomial(const spectral::SigmoidPolynomial& p, float scale) {
    UpsampledRgb u;
    for (int q = 0; q < 3; ++q) u.c[q] = p.c[q];
    u.scale = scale;
    u.valid = true;
    return u;
}

// A constant value set up once with the refined coefficients.
UpsampledRgb refinedAlbedo(const spectral::ColorSpace& cs, const Vec3& rgb) {
    return fromPolynomial(spectral::RgbAlbedoSpectrum(cs, rgb.x, rgb.y, rgb.z).p, 1.0f);
}
UpsampledRgb refinedUnbounded(const spectral::ColorSpace& cs, const Vec3& rgb) {
    spectral::RgbUnboundedSpectrum s(cs, rgb.x, rgb.y, rgb.z);
    return fromPolynomial(s.p, s.scale);
}
UpsampledRgb constantAlbedo(const spectral::ColorSpace& cs, const ColorParam& p) {
    return p.textured() ? UpsampledRgb{} : refinedAlbedo(cs, p.value);
}
UpsampledRgb constantUnbounded(const spectral::ColorSpace& cs, const ColorParam& p) {
    return p.textured() ? UpsampledRgb{} : refinedUnbounded(cs, p.value);
}

} // namespace

SpectralRender::SpectralRender(const Scene& scene, const LightSet& lights)
    : m_cs(spectral::colorSpace(spectral::ColorSpaceId::Srgb)) {
    // A constant reflectance (or conductor's eta or k) with a spectrum of its own takes it (the
    // material keeps it alive, and so does m_reflectances).
    auto own = [this](const ReflectanceSpectrumRef& r, UpsampledRgb& u) {
        if (!r) return;
        m_reflectances.push_back(r);
        u = UpsampledRgb{};
        u.valid = true;
        u.own = r->values.values.data();
    };
    for (const Material& m : scene.materials) {
        MaterialSpectra s;
        if (m.colorTexture < 0) {
            s.color = refinedAlbedo(m_cs, m.color);
            own(m.colorSpectrum, s.color);
        }
        s.eta = constantUnbounded(m_cs, m.eta);
        s.k = constantUnbounded(m_cs, m.k);
        if (!m.eta.textured()) own(m.etaSpectrum, s.eta);
        if (!m.k.textured()) own(m.kSpectrum, s.k);
        s.transmittance = constantAlbedo(m_cs, m.transmittance);
        if (!m.transmittance.textured()) own(m.transmittanceSpectrum, s.transmittance);
        s.albedo = constantAlbedo(m_cs, m.albedo);
        if (!m.albedo.textured()) own(m.albedoSpectrum, s.albedo);
        m_materials.push_back(s);
    }
    for (const LightSource& l : lights.lights) {
        LightSpectrum s;
        s.own = l.spectrum;
        s.base = s.own ? s.own->rgb : l.delta() ? l.intensity : l.radiance;
        s.channel = largestComponent(s.base);
        if (!s.own) s.s = refinedUnbounded(m_cs, s.base);
        m_lights.push_back(s);
    }
    if (const EmissionSpectrum* sky = lights.environment.constantSpectrum())
        m_sky = std::make_shared<const EmissionSpectrum>(*sky);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) m_xyzToRgb[r][c] = float(m_cs.xyzToRgb.m[r][c]);
    buildWavelengthTables();
}

void SpectralRender::buildWavelengthTables() {
    const int n = kInverseCdfCells;
    for (int k = 0; k <= n; ++k)
        m_lambdaNodes.push_back(k == 0   ? ks::kLambdaMin
                                : k == n ? ks::kLambdaMax
                                         : ks::sampleVisibleWavelength(float(k) / n));
    for (int k = 0; k < n; ++k)
        m_cellPdf.push_back(1.0f / (float(n) * (m_lambdaNodes[k + 1] - m_lambdaNodes[k])));
    const float norm = 1.0f / (3.0f * float(spectral::cieYIntegral()));
    for (int i = 0; i < ks::kDenseCount; ++i) {
        m_illuminantNm.push_back(m_cs.illuminant->values[std::size_t(i)]);
        float x = spectral::cieX().values[std::size_t(i)] * norm;
        float y = spectral::cieY().values[std::size_t(i)] * norm;
        float z = spectral::cieZ().values[std::size_t(i)] * norm;
        m_xyzNm.push_back({x, y, z});
        m_filmNm.push_back(xyzToRgb(m_xyzNm.back()));
    }
}

LaneSpectrum SpectralRender::lane(float u) const {
    LaneSpectrum l;
    const bool terminated = std::signbit(u);
    u = std::fabs(u);
    const float n = float(kInverseCdfCells);
    for (int i = 0; i < 3; ++i) {
        float x = PathWavelengths::offset(u, i) * n;
        int k = std::min(int(x), kInverseCdfCells - 1);
        float lo = m_lambdaNodes[std::size_t(k)], hi = m_lambdaNodes[std::size_t(k) + 1];
        float lambda = lo + (x - float(k)) * (hi - lo);
        l.w.lambda[i] = lambda;
        l.w.pdf[i] = m_cellPdf[std::size_t(k)];
        l.t[i] = (lambda - ks::kLambdaMin) * (1.0f / (ks::kLambdaMax - ks::kLambdaMin));
        const int nm = nearestNm(lambda);
        l.nm[i] = nm;
        l.illuminant[i] = m_illuminantNm[std::size_t(nm)];
        l.film[i] = m_filmNm[std::size_t(nm)] * (1.0f / l.w.pdf[i]);
    }
    if (terminated) {
        l.w.terminateSecondary();
        l.film[0] = l.film[0] * 3.0f;
        l.film[1] = l.film[2] = Vec3(0.0f);
    }
    return l;
}

Vec3 SpectralRender::evaluate(const UpsampledRgb& s, const LaneSpectrum& l, bool illuminant) {
    if (s.own) // a reflectance's own spectrum (never an illuminant's)
        return {s.own[l.nm[0]], s.own[l.nm[1]], s.own[l.nm[2]]};
    float v[3];
    for (int i = 0; i < 3; ++i) {
        v[i] = s.scale * ks::sigmoid((s.c[0] * l.t[i] + s.c[1]) * l.t[i] + s.c[2]);
        if (illuminant) v[i] *= l.illuminant[i];
    }
    return {v[0], v[1], v[2]};
}

UpsampledRgb SpectralRender::lookup(const Vec3& rgb, bool unbounded) const {
    if (!unbounded) return fromPolynomial(spectral::rgbToCoefficients(m_cs, rgb.x, rgb.y, rgb.z), 1);
    float m = std::max({rgb.x, rgb.y, rgb.z});
    float scale = 2 * m;
    if (!(scale > 0) || !std::isfinite(scale)) return fromPolynomial({}, 0.0f); // no light, no NaN
    return fromPolynomial(
        spectral::rgbToCoefficients(m_cs, rgb.x / scale, rgb.y / scale, rgb.z / scale), scale);
}

Vec3 SpectralRender::albedo(const Vec3& rgb, const LaneSpectrum& l) const {
    return evaluate(lookup(rgb, false), l, false);
}
Vec3 SpectralRender::unbounded(const Vec3& rgb, const LaneSpectrum& l) const {
    return evaluate(lookup(rgb, true), l, false);
}
Vec3 SpectralRender::illuminant(const Vec3& rgb, const LaneSpectrum& l) const {
    return evaluate(lookup(rgb, true), l, true);
}

Vec3 SpectralRender::lightValue(std::size_t light, const Vec3& value, const LaneSpectrum& l) const {
    const LightSpectrum& s = m_lights[light];
    float base = s.base[s.channel];
    if (!(base > 0)) return Vec3(0.0f);
    // base is the own spectrum's colour where there is one: the same scalar emissionScale takes.
    const float k = value[s.channel] / base;
    return (s.own ? ownAt(*s.own, l) : evaluate(s.s, l, true)) * k;
}

Vec3 SpectralRender::ownAt(const EmissionSpectrum& own, const LaneSpectrum& l) {
    const auto& v = own.values.values;
    return Vec3(v[std::size_t(l.nm[0])], v[std::size_t(l.nm[1])], v[std::size_t(l.nm[2])]);
}

Vec3 SpectralRender::emitted(const Shape& shape, int light, const Vec3& le,
                             const LaneSpectrum& l) const {
    if (light >= 0) return lightValue(std::size_t(light), le, l);
    const EmissionSpectrum* own = shape.emissionSpectrum.get();
    return own ? ownAt(*own, l) * emissionScale(*own, le) : illuminant(le, l);
}

Vec3 SpectralRender::sky(const Vec3& rgb, const LaneSpectrum& l) const {
    return m_sky ? ownAt(*m_sky, l) * emissionScale(*m_sky, rgb) : illuminant(rgb, l);
}

// The XYZ of kernels::spectral::sampledToXyz (each value times the matching functions over
// its density, averaged, over the y-bar integral) through the colour space's matrix, both
// linear: the lane's film vectors hold the product per wavelength.
Vec3 SpectralRender::toFilm(const Vec3& values, const LaneSpectrum& l) const {
    return l.film[0] * values.x + l.film[1] * values.y + l.film[2] * values.z;
}

Vec3 SpectralRender::toXyz(const Vec3& values, const LaneSpectrum& l) const {
    Vec3 xyz(0.0f);
    for (int i = 0; i < 3; ++i) {
        if (l.w.pdf[i] == 0) continue; // a terminated secondary wavelength
        xyz += m_xyzNm[std::size_t(l.nm[i])] * (values[i] / l.w.pdf[i]); // as the film's
    }
    return xyz;
}

float SpectralRender::oneWavelengthWeight(float lambda, const Vec3& xyz) const {
    // toXyz: xyz = m_xyzNm[nm] * value / pdf, the pdf of a terminated hero; its largest
    // matching function's channel is the photon's largest (RGBE keeps that one best).
    const Vec3& m = m_xyzNm[std::size_t(nearestNm(lambda))];
    const int c = largestComponent(m);
    return m[c] > 0 ? xyz[c] / m[c] : 0.0f;
}

Vec3 SpectralRender::xyzToRgb(const Vec3& v) const {
    const float(&m)[3][3] = m_xyzToRgb;
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

} // namespace rayproc
