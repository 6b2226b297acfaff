#include "scene/pbrt/pbrt_spectrum.h"

#include <algorithm>
#include <cmath>

namespace rayproc::pbrt {

namespace {

constexpr double kLambdaMin = 360.0, kLambdaMax = 830.0; // the CIE tables' range, 1 nm steps

// One lobe of the fit: a Gaussian with different widths below and above its mean.
double lobe(double nm, double mean, double invSigmaBelow, double invSigmaAbove) {
    double t = (nm - mean) * (nm < mean ? invSigmaBelow : invSigmaAbove);
    return std::exp(-0.5 * t * t);
}

// Integrates f(nm) * cmf(nm) over the visible range; f returns the spectrum's value.
template <class F>
void integrateXyz(F&& f, double& x, double& y, double& z) {
    x = y = z = 0;
    for (double nm = kLambdaMin; nm <= kLambdaMax; nm += 1.0) {
        double cx, cy, cz;
        cieColorMatch(nm, cx, cy, cz);
        double v = f(nm);
        x += v * cx;
        y += v * cy;
        z += v * cz;
    }
}

Vec3 clampedToLuminanceOne(Vec3 rgb) {
    rgb = vmax(rgb, Vec3(0.0f));
    float lum = luminance(rgb);
    return lum > 0 ? rgb / lum : Vec3(1.0f);
}

} // namespace

// Wyman, Sloan and Shirley, "Simple Analytic Approximations to the CIE XYZ Color Matching
// Functions", JCGT 2(2), 2013: the multi-lobe piecewise Gaussian fit of the 1931 observer.
void cieColorMatch(double nm, double& x, double& y, double& z) {
    x = 0.362 * lobe(nm, 442.0, 0.0624, 0.0374) + 1.056 * lobe(nm, 599.8, 0.0264, 0.0323) -
        0.065 * lobe(nm, 501.1, 0.0490, 0.0382);
    y = 0.821 * lobe(nm, 568.8, 0.0213, 0.0247) + 0.286 * lobe(nm, 530.9, 0.0613, 0.0322);
    z = 1.217 * lobe(nm, 437.0, 0.0845, 0.0278) + 0.681 * lobe(nm, 459.0, 0.0385, 0.0725);
}

Vec3 xyzToLinearSrgb(double x, double y, double z) {
    return {float(3.2404542 * x - 1.5371385 * y - 0.4985314 * z),
            float(-0.9692660 * x + 1.8760108 * y + 0.0415560 * z),
            float(0.0556434 * x - 0.2040259 * y + 1.0572252 * z)};
}

double planck(double nm, double kelvin) {
    if (kelvin <= 0) return 0;
    const double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
    double l = nm * 1e-9;
    return (2 * h * c * c) / (std::pow(l, 5) * (std::exp((h * c) / (l * kb * kelvin)) - 1));
}

Vec3 blackbodyRgb(double kelvin) {
    double x, y, z;
    integrateXyz([&](double nm) { return planck(nm, kelvin); }, x, y, z);
    if (!(y > 0)) return Vec3(1.0f);
    return clampedToLuminanceOne(xyzToLinearSrgb(x / y, 1.0, z / y));
}

double sampledValueAt(const std::vector<double>& pairs, double nm) {
    std::size_t n = pairs.size() / 2;
    if (n == 0) return 0;
    if (nm <= pairs[0]) return pairs[1];
    if (nm >= pairs[2 * (n - 1)]) return pairs[2 * n - 1];
    for (std::size_t i = 0; i + 1 < n; ++i) {
        double l0 = pairs[2 * i], l1 = pairs[2 * i + 2];
        if (nm >= l0 && nm <= l1) {
            double t = l1 > l0 ? (nm - l0) / (l1 - l0) : 0;
            return pairs[2 * i + 1] * (1 - t) + pairs[2 * i + 3] * t;
        }
    }
    return 0;
}

// Outside its sampled range an emission spectrum is zero (pbrt's PiecewiseLinearSpectrum).
static double sampledOrZero(const std::vector<double>& pairs, double nm) {
    std::size_t n = pairs.size() / 2;
    if (n == 0 || nm < pairs[0] || nm > pairs[2 * (n - 1)]) return 0;
    return sampledValueAt(pairs, nm);
}

Vec3 sampledEmissionRgb(const std::vector<double>& pairs) {
    double x, y, z;
    integrateXyz([&](double nm) { return sampledOrZero(pairs, nm); }, x, y, z);
    if (!(y > 0)) return Vec3(0.0f);
    return clampedToLuminanceOne(xyzToLinearSrgb(x / y, 1.0, z / y));
}

Vec3 sampledReflectanceRgb(const std::vector<double>& pairs) {
    const double kD65Cct = 6504.0;
    double x, y, z, wx, wy, wz;
    // Reflectance data often stops short of the CIE range; its end values carry on (a
    // reflectance does not fall to zero beyond the last sample).
    integrateXyz([&](double nm) { return sampledValueAt(pairs, nm) * planck(nm, kD65Cct); }, x, y,
                 z);
    integrateXyz([&](double nm) { return planck(nm, kD65Cct); }, wx, wy, wz);
    Vec3 rgb = xyzToLinearSrgb(x / wy, y / wy, z / wy);
    Vec3 white = xyzToLinearSrgb(wx / wy, 1.0, wz / wy);
    return vmin(vmax(rgb / white, Vec3(0.0f)), Vec3(1.0f));
}

bool namedGlassIor(const std::string& name, double& ior) {
    // Schott catalogue n_d values; pbrt's "glass-F5", "F10" and "F11" are the SF5, SF10 and
    // SF11 glasses.
    static const std::pair<const char*, double> kGlasses[] = {
        {"glass-BK7", 1.5168},   {"glass-BAF10", 1.6700}, {"glass-FK51A", 1.4866},
        {"glass-LASF9", 1.8503}, {"glass-F5", 1.6727},    {"glass-F10", 1.7283},
        {"glass-F11", 1.7847}};
    for (const auto& [n, v] : kGlasses) {
        if (name == n) {
            ior = v;
            return true;
        }
    }
    return false;
}

} // namespace rayproc::pbrt
