// A dielectric's index of refraction over wavelength (dispersion, docs/spectral.md,
// "Dispersion"): a pbrt-v4 named glass ("glass-BK7", ...) as its Sellmeier formula, or a file's
// `spectrum eta [l1 v1 l2 v2 ...]` as its pairs, kept beside the scalar Material::ior that RGB
// mode renders with (the index at 587.6 nm), as a reflectance keeps its spectrum beside its
// colour (scene/reflectance_spectrum.h). The spectral mode refracts a path at its hero
// wavelength with it and ends the path's other wavelengths (engine/material_bsdf.h).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace rayproc {

struct IorSpectrum {
    enum class Form { Sellmeier, Pairs };
    Form form = Form::Pairs;
    // Sellmeier: n^2(l) = 1 + sum_i b_i l^2 / (l^2 - c_i), l in micrometres (c_i in um^2).
    std::array<double, 3> b{}, c{};
    // Pairs: (nm, index), ascending wavelengths; linear between them (pbrt-v4's
    // PiecewiseLinearSpectrum), the end values held beyond the ends (pbrt-v4's spectrum is 0
    // there, which its dielectric takes as index 1).
    std::vector<double> pairs;
    std::string label; // what the file said ("glass-BK7", "sampled spectrum")

    // The index at `nm` nanometres.
    float at(float nm) const;
};
using IorSpectrumRef = std::shared_ptr<const IorSpectrum>;

// pbrt-v4's named glasses ("glass-BK7", "-BAF10", "-FK51A", "-LASF9", "-F5", "-F10", "-F11":
// Schott's N-BK7, N-BAF10, N-FK51A, N-LASF9, SF5, SF10, SF11): the catalogue index n_d at the
// helium d line (587.56 nm), which RGB mode renders with, and the Sellmeier formula with the
// catalogue coefficients; false and nullptr for other names.
bool namedGlassIndex(const std::string& name, double& nd);
IorSpectrumRef namedGlassDispersion(const std::string& name);

// (wavelength nm, index) pairs; nullptr when every index is the same (a constant eta, which
// disperses nothing) or there are no pairs.
IorSpectrumRef sampledIor(const std::vector<double>& pairs);

} // namespace rayproc
