// Spectral render mode (--spectral, docs/spectral.md): a path carries three hero wavelengths
// (Wilkie et al. 2014; pbrt-v4 carries four) and the three floats of every radiance,
// throughput and BSDF triple along it hold the spectrum at those wavelengths instead of RGB, so
// the engine's arithmetic is unchanged. RGB values enter a path here, upsampled as pbrt-v4 does
// (Jakob & Hanika 2019, src/spectral/rgb_spectrum.h): reflectances as RGBAlbedoSpectrum, a
// conductor's eta and k as RGBUnboundedSpectrum, emission and skies as RGBIlluminantSpectrum,
// except where an emitter has a spectrum of its own (a pbrt-v4 blackbody, sampled or named
// illuminant: scene/emission_spectrum.h), which is evaluated itself.
// At the film a path's three values become CIE XYZ (kernels::spectral::sampledToXyz, pbrt-v4's
// "cie1931" sensor without white balance) and then linear sRGB, the film's colour space, so the
// film, its outputs, adaptive sampling and MPI are those of RGB mode.
#pragma once

#include "core/math.h"
#include "kernels/spectrum.h"
#include "spectral/color_space.h"

#include <cmath>
#include <cstddef>
#include <memory>
#include <vector>

namespace rayproc {

struct Scene;
struct Material;
struct LightSet;
struct Shape;
struct EmissionSpectrum;
struct ReflectanceSpectrum;

// The wavelengths of one path, from its one number u (RayBatch::lambdaU).
using PathWavelengths = kernels::spectral::SampledWavelengthsN<3>;

// An RGB value's spectrum: scale * S(c0 t^2 + c1 t + c2), times the colour space's illuminant
// for an illuminant. Set up once for constant values (refined), per texel from the table.
// A reflectance with a spectrum of its own (scene/reflectance_spectrum.h) takes that instead:
// `own`, its values at every nanometre, read at the lane's nearest nanometre.
struct UpsampledRgb {
    float c[3] = {0, 0, 0};
    float scale = 1;
    bool valid = false; // false: not precomputed (a textured parameter)
    const float* own = nullptr; // kDenseCount values (SpectralRender keeps them alive)
};

// A lane's wavelengths with what every conversion at them reads: the normalised wavelength of
// the sigmoid polynomial, the illuminant's value, and the film's linear sRGB of a unit value at
// each wavelength (its matching functions over its density, over 3 y-bar integrals).
struct LaneSpectrum {
    PathWavelengths w;
    float t[3];
    float illuminant[3];
    Vec3 film[3];
    int nm[3]; // the nearest nanometre's index into a DenseSpectrum (denseAt's sample)
};

class SpectralRender {
public:
    // Precomputes every material's constant colours and every light's emission.
    SpectralRender(const Scene& scene, const LightSet& lights);

    // The lane's wavelengths from its number u: the hero at u, the others at u + i/3 (mod 1),
    // through the visible density's inverse CDF tabulated at kInverseCdfCells + 1 exact nodes
    // and linear between them. The density of that map is the cell's mean of the visible
    // density (its CDF is exact at the nodes), and that is the pdf a lane carries: exact for
    // the map, and no transcendental function per lane (they were a fifth of a spectral
    // render's time).
    // A path past a dispersive interface (engine/material_bsdf.h, dispersive) keeps its hero
    // wavelength alone, pbrt-v4's SampledWavelengths::TerminateSecondary: its number carries
    // the mark (terminatedU: the sign bit, -0 for 0, which every successor ray inherits), and
    // its lane's secondary wavelengths have density 0 (they add nothing at the film) and the
    // hero's is divided by 3 (it carries the whole estimate).
    LaneSpectrum lane(float u) const;
    static float terminatedU(float u) { return -std::fabs(u); }
    static constexpr int kInverseCdfCells = 1024;

    // RGB values at a lane's wavelengths, through the table (textures, skies).
    Vec3 albedo(const Vec3& rgb, const LaneSpectrum& l) const;
    Vec3 unbounded(const Vec3& rgb, const LaneSpectrum& l) const;
    Vec3 illuminant(const Vec3& rgb, const LaneSpectrum& l) const;
    // A precomputed value (unbounded; an illuminant also takes the illuminant's values).
    static Vec3 evaluate(const UpsampledRgb& s, const LaneSpectrum& l, bool illuminant);

    // A material's constant parameters, precomputed (invalid where textured); `color` and
    // `transmittance` the material's own spectra where it has them.
    struct MaterialSpectra {
        UpsampledRgb color, eta, k, transmittance, albedo;
    };
    const MaterialSpectra& material(int index) const { return m_materials[std::size_t(index)]; }
    // The emission of light i (LightSet::lights) at the lane's wavelengths, for a value that is
    // its radiance (an area light) or intensity (a delta light) times a scalar, as a light
    // sample's weight and an emitter's radiance are.
    // A light with a spectrum of its own takes that spectrum (the value over the light's RGB
    // colour is the scalar), the others their RGB illuminant spectrum.
    Vec3 lightValue(std::size_t light, const Vec3& value, const LaneSpectrum& l) const;
    // The emission `le` of a shape that a ray found, light `light` of the light set (or -1: an
    // emitter the set does not sample, such as preview's area lights), at the lane's wavelengths.
    Vec3 emitted(const Shape& shape, int light, const Vec3& le, const LaneSpectrum& l) const;
    // The sky's radiance `rgb` (LightSet::environment's, in some direction) at the lane's
    // wavelengths: a constant sky with a spectrum of its own takes it, others the table's
    // illuminant spectrum.
    Vec3 sky(const Vec3& rgb, const LaneSpectrum& l) const;

    // The film's linear sRGB of a path's values at its wavelengths: XYZ as pbrt-v4's "cie1931"
    // sensor (imaging ratio 1, no white balance: a file's sensor is applied to the resolved
    // image, engine/film_sensor.h), then the colour space's XYZ -> RGB.
    Vec3 toFilm(const Vec3& values, const LaneSpectrum& l) const;
    // The same values' CIE XYZ (toFilm is xyzToRgb of it): non-negative for non-negative values,
    // which gi's photon maps store (their RGBE power cannot hold the negative sRGB channels of a
    // photon's three wavelengths).
    Vec3 toXyz(const Vec3& values, const LaneSpectrum& l) const;
    // The colour space's linear RGB of an XYZ value.
    Vec3 xyzToRgb(const Vec3& xyz) const;
    // For the toXyz `xyz` of a path of one wavelength `lambda` (nm, a terminated lane's
    // hero): its value over that wavelength's density, the factor toXyz took the matching
    // functions at `lambda` by (0 where they are 0). gi's caustic photons of one wavelength.
    float oneWavelengthWeight(float lambda, const Vec3& xyz) const;

    const spectral::ColorSpace& colorSpace() const { return m_cs; }

private:
    UpsampledRgb lookup(const Vec3& rgb, bool unbounded) const;
    void buildWavelengthTables();

    const spectral::ColorSpace& m_cs;
    std::vector<MaterialSpectra> m_materials;
    std::vector<std::shared_ptr<const ReflectanceSpectrum>> m_reflectances; // their `own`s
    struct LightSpectrum {
        UpsampledRgb s;
        Vec3 base;  // the RGB it was set up from (own's colour where it has one)
        int channel; // base's largest channel: value / base in it is the scalar
        std::shared_ptr<const EmissionSpectrum> own; // the light's own spectrum, or nullptr
    };
    // An emitter's own spectrum at the lane's wavelengths (times the scalar of its value).
    static Vec3 ownAt(const EmissionSpectrum& own, const LaneSpectrum& l);
    std::vector<LightSpectrum> m_lights;
    std::shared_ptr<const EmissionSpectrum> m_sky; // the constant sky's own spectrum
    float m_xyzToRgb[3][3];
    // The visible density's inverse CDF at u = k / kInverseCdfCells, and each cell's density.
    std::vector<float> m_lambdaNodes, m_cellPdf;
    // Per nanometre (kernels::spectral::denseAt's samples): the illuminant, and the film's
    // linear sRGB of the matching functions over 3 y-bar integrals.
    std::vector<float> m_illuminantNm;
    std::vector<Vec3> m_filmNm;
    std::vector<Vec3> m_xyzNm; // the matching functions over 3 y-bar integrals
};

} // namespace rayproc
