#include "scene/pbrt/pbrt_spectrum.h"

#include "spectral/color_space.h"
#include "spectral/rgb_spectrum.h"
#include "spectral/spectra.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

namespace rayproc::pbrt {

namespace {

const spectral::ColorSpace& srgb() { return spectral::colorSpace(spectral::ColorSpaceId::Srgb); }

Vec3 toSrgb(const spectral::Xyz& c) { return xyzToLinearSrgb(c.x, c.y, c.z); }

// An emission spectrum's colour: its chromaticity in sRGB at luminance 1.
Vec3 emissionRgb(const std::function<double(double)>& f) {
    spectral::Xyz c = spectral::toXyz(f);
    if (!(c.y > 0)) return Vec3(0.0f);
    Vec3 rgb = vmax(xyzToLinearSrgb(c.x / c.y, 1.0, c.z / c.y), Vec3(0.0f));
    float lum = luminance(rgb);
    return lum > 0 ? rgb / lum : Vec3(1.0f);
}

// A reflectance spectrum's colour: its XYZ under D65, sRGB's illuminant (luminance 1), in sRGB
// (not clamped).
Vec3 reflectanceRgb(const std::function<double(double)>& f) {
    const spectral::DenseSpectrum& d65 = *srgb().illuminant;
    return toSrgb(spectral::toXyz([&](double nm) { return f(nm) * d65.at(float(nm)); }));
}

} // namespace

void cieColorMatch(double nm, double& x, double& y, double& z) {
    // The 1 nm tables hold the 5 nm data linearly interpolated; between integers, interpolate
    // again (exact for the piecewise-linear functions they sample).
    double lo = std::floor(nm), t = nm - lo;
    auto at = [&](const spectral::DenseSpectrum& s) {
        return s.at(float(lo)) * (1 - t) + s.at(float(lo + 1)) * t;
    };
    x = at(spectral::cieX());
    y = at(spectral::cieY());
    z = at(spectral::cieZ());
}

Vec3 xyzToLinearSrgb(double x, double y, double z) {
    spectral::ColorSpace::Rgb c = srgb().fromXyz({x, y, z});
    return {float(c.r), float(c.g), float(c.b)};
}

double planck(double nm, double kelvin) { return kernels::spectral::planck(nm, kelvin); }

Vec3 blackbodyRgb(double kelvin) {
    return emissionRgb([kelvin](double nm) { return planck(nm, kelvin); });
}

double sampledValueAt(const std::vector<double>& pairs, double nm) {
    std::size_t n = pairs.size() / 2;
    if (n == 0) return 0;
    if (nm <= pairs[0]) return pairs[1];
    if (nm >= pairs[2 * (n - 1)]) return pairs[2 * n - 1];
    return spectral::piecewiseLinear(pairs, nm);
}

Vec3 sampledEmissionRgb(const std::vector<double>& pairs) {
    return emissionRgb([&pairs](double nm) { return spectral::piecewiseLinear(pairs, nm); });
}

Vec3 sampledReflectanceRgb(const std::vector<double>& pairs) {
    Vec3 rgb = reflectanceRgb([&](double nm) { return spectral::piecewiseLinear(pairs, nm); });
    return vmin(vmax(rgb, Vec3(0.0f)), Vec3(1.0f));
}

bool namedIlluminantRgb(const std::string& name, Vec3& rgb) {
    static const char* const kNames[] = {"A",  "D50", "D65", "F1",  "F2",  "F3",  "F4", "F5",
                                         "F6", "F7",  "F8",  "F9", "F10", "F11", "F12"};
    if (name == "illum-acesD60") {
        const spectral::DenseSpectrum& d60 = spectral::acesD60Illuminant();
        rgb = emissionRgb([&d60](double nm) { return double(d60.at(float(nm))); });
        return true;
    }
    const std::string prefix = "stdillum-";
    if (name.compare(0, prefix.size(), prefix) != 0) return false;
    std::string id = name.substr(prefix.size());
    if (std::find(std::begin(kNames), std::end(kNames), id) == std::end(kNames)) return false;
    const spectral::DenseSpectrum* s = spectral::cieIlluminant(id);
    if (!s) return false;
    rgb = emissionRgb([s](double nm) { return double(s->at(float(nm))); });
    return true;
}

EmissionSpectrumRef blackbodyEmission(double kelvin) {
    auto f = [kelvin](double nm) { return kernels::spectral::blackbodyNormalized(nm, kelvin); };
    char label[64];
    std::snprintf(label, sizeof label, "blackbody %g", kelvin);
    return emissionAtLuminance1(spectral::DenseSpectrum::sample(f), blackbodyRgb(kelvin), label);
}

EmissionSpectrumRef sampledEmission(const std::vector<double>& pairs) {
    auto f = [&pairs](double nm) { return spectral::piecewiseLinear(pairs, nm); };
    return emissionAtLuminance1(spectral::DenseSpectrum::sample(f), sampledEmissionRgb(pairs),
                                "sampled spectrum");
}

EmissionSpectrumRef namedIlluminantEmission(const std::string& name) {
    Vec3 rgb;
    if (!namedIlluminantRgb(name, rgb)) return nullptr;
    const spectral::DenseSpectrum* s = name == "illum-acesD60"
                                           ? &spectral::acesD60Illuminant()
                                           : spectral::cieIlluminant(name.substr(9));
    return s ? emissionAtLuminance1(*s, rgb, name) : nullptr;
}

namespace {

// A reflectance-like spectrum's colour under D65, sRGB's illuminant (luminance 1).
template <class S> Vec3 underD65(const S& s) {
    return reflectanceRgb([&](double nm) { return double(s(float(nm))); });
}

bool isSrgb(const spectral::ColorSpace& cs) { return cs.id == spectral::ColorSpaceId::Srgb; }

} // namespace

Vec3 rgbAlbedoToSrgb(const Vec3& rgb, const spectral::ColorSpace& cs) {
    if (isSrgb(cs)) return rgb;
    Vec3 c = underD65(spectral::RgbAlbedoSpectrum(cs, rgb.x, rgb.y, rgb.z));
    return vmin(vmax(c, Vec3(0.0f)), Vec3(1.0f));
}

Vec3 rgbUnboundedToSrgb(const Vec3& rgb, const spectral::ColorSpace& cs) {
    if (isSrgb(cs)) return rgb;
    return vmax(underD65(spectral::RgbUnboundedSpectrum(cs, rgb.x, rgb.y, rgb.z)), Vec3(0.0f));
}

Vec3 rgbIlluminantToSrgb(const Vec3& rgb, const spectral::ColorSpace& cs) {
    if (isSrgb(cs)) return rgb;
    spectral::RgbIlluminantSpectrum s(cs, rgb.x, rgb.y, rgb.z);
    return vmax(toSrgb(spectral::toXyz([&](double nm) { return double(s(float(nm))); })),
                Vec3(0.0f));
}

EmissionSpectrumRef rgbIlluminantEmission(const Vec3& rgb, const spectral::ColorSpace& cs) {
    if (isSrgb(cs) || !(maxComponent(rgb) > 0)) return nullptr;
    spectral::RgbIlluminantSpectrum s(cs, rgb.x, rgb.y, rgb.z);
    auto e = std::make_shared<EmissionSpectrum>();
    e->values = spectral::DenseSpectrum::sample([&](double nm) { return double(s(float(nm))); });
    e->rgb = rgbIlluminantToSrgb(rgb, cs);
    e->label = std::string("rgb in ") + cs.name;
    return e;
}

namespace {

// f at every nanometre, clamped to [0, top].
ReflectanceSpectrumRef clampedSpectrum(const std::function<double(double)>& f, double top,
                                       std::string label) {
    auto r = std::make_shared<ReflectanceSpectrum>();
    r->values =
        spectral::DenseSpectrum::sample([&](double nm) { return std::clamp(f(nm), 0.0, top); });
    r->label = std::move(label);
    return r;
}

ReflectanceSpectrumRef clampedReflectance(const std::function<double(double)>& f,
                                          std::string label) {
    return clampedSpectrum(f, 1.0, std::move(label));
}

constexpr double kUnboundedTop = std::numeric_limits<double>::max();

} // namespace

ReflectanceSpectrumRef sampledReflectance(const std::vector<double>& pairs) {
    return clampedReflectance([&pairs](double nm) { return spectral::piecewiseLinear(pairs, nm); },
                              "sampled spectrum");
}

ReflectanceSpectrumRef rgbAlbedoReflectance(const Vec3& rgb, const spectral::ColorSpace& cs) {
    if (isSrgb(cs)) return nullptr;
    spectral::RgbAlbedoSpectrum s(cs, rgb.x, rgb.y, rgb.z);
    return clampedReflectance([&s](double nm) { return double(s(float(nm))); },
                              std::string("rgb in ") + cs.name);
}

ReflectanceSpectrumRef sampledUnbounded(const std::vector<double>& pairs) {
    return clampedSpectrum([&pairs](double nm) { return spectral::piecewiseLinear(pairs, nm); },
                           kUnboundedTop, "sampled spectrum");
}

ReflectanceSpectrumRef rgbUnboundedValues(const Vec3& rgb, const spectral::ColorSpace& cs) {
    if (isSrgb(cs)) return nullptr;
    spectral::RgbUnboundedSpectrum s(cs, rgb.x, rgb.y, rgb.z);
    return clampedSpectrum([&s](double nm) { return double(s(float(nm))); }, kUnboundedTop,
                           std::string("rgb in ") + cs.name);
}

} // namespace rayproc::pbrt
