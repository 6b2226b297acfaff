#include "scene/emission_spectrum.h"

#include "spectral/color_space.h"
#include "spectral/rgb_spectrum.h"

#include <cmath>

namespace rayproc {

namespace {

// The spectral counterpart of an emitter's RGB value `value`: its own spectrum times k, or the
// RGB illuminant spectrum of the value (sRGB's, refined as the spectral mode sets lights up).
spectral::DenseSpectrum spectrumOf(const Vec3& value, const EmissionSpectrumRef& own) {
    spectral::DenseSpectrum d;
    if (own) {
        float k = emissionScale(*own, value);
        for (int i = 0; i < spectral::kDenseCount; ++i) d.values[i] = own->values.values[i] * k;
        return d;
    }
    if (!(maxComponent(value) > 0)) return d;
    spectral::RgbIlluminantSpectrum s(spectral::colorSpace(spectral::ColorSpaceId::Srgb), value.x,
                                      value.y, value.z);
    for (int i = 0; i < spectral::kDenseCount; ++i)
        d.values[i] = s(float(spectral::kLambdaMin + i));
    return d;
}

} // namespace

EmissionSpectrumRef emissionAtLuminance1(const spectral::DenseSpectrum& s, const Vec3& rgb,
                                         std::string label) {
    // Luminance relative to the 1 nm y-bar sum, as cieIlluminant normalises its spectra.
    const double y = spectral::toXyz(s).y;
    if (!(y > 0) || !std::isfinite(y)) return nullptr;
    auto e = std::make_shared<EmissionSpectrum>();
    for (int i = 0; i < spectral::kDenseCount; ++i) e->values.values[i] = float(s.values[i] / y);
    e->rgb = rgb;
    e->label = std::move(label);
    return e;
}

float emissionScale(const EmissionSpectrum& e, const Vec3& value) {
    int c = largestComponent(e.rgb);
    return e.rgb[c] > 0 ? value[c] / e.rgb[c] : 0.0f;
}

EmissionSpectrumRef sumOfEmissions(const Vec3& a, const EmissionSpectrumRef& sa, const Vec3& b,
                                   const EmissionSpectrumRef& sb) {
    if (!sa && !sb) return nullptr;
    if (!sa && !(maxComponent(a) > 0)) return sb; // nothing to add to
    if (!sb && !(maxComponent(b) > 0)) return sa;
    auto e = std::make_shared<EmissionSpectrum>();
    spectral::DenseSpectrum da = spectrumOf(a, sa), db = spectrumOf(b, sb);
    for (int i = 0; i < spectral::kDenseCount; ++i)
        e->values.values[i] = da.values[i] + db.values[i];
    e->rgb = a + b;
    e->label = (sa ? sa->label : "rgb") + " + " + (sb ? sb->label : "rgb");
    return e;
}

} // namespace rayproc
