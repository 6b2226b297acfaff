// Jakob & Hanika 2019, "A Low-Dimensional Function Space for Efficient Spectral Upsampling":
// the sigmoid-of-quadratic reflectance whose colour under a colour space's illuminant is a given
// RGB, found by Gauss-Newton iterations on the CIELAB difference (the paper's optimisation).
// tools/rgb2spec_gen.cpp runs it over the coefficient tables' grid at build time;
// src/spectral/rgb_spectrum.h looks the tables up.
#pragma once

#include "spectral/color_space.h"

#include <array>

namespace rayproc::spectral {

// Coefficients (c0, c1, c2) of s(l) = S(c0 t^2 + c1 t + c2), t = (l - 360) / 470
// (kernels::spectral::sigmoidPolynomial).
using SigmoidCoefficients = std::array<double, 3>;

class RgbFitter {
public:
    explicit RgbFitter(const ColorSpace& cs);

    // XYZ of the reflectance c under the colour space's illuminant (its white has Y = 1).
    Xyz reflectedXyz(const SigmoidCoefficients& c) const;
    Xyz reflectedXyz(const SigmoidCoefficients& c, double jacobian[3][3]) const;

    // Refines c (the start; the grid's neighbour, or 0) towards the reflectance whose colour is
    // `rgb` (each in [0, 1]); returns the CIELAB distance left (about 1e-6 once converged).
    double fit(const std::array<double, 3>& rgb, SigmoidCoefficients& c) const;

    const ColorSpace& colorSpace() const { return m_cs; }

private:
    const ColorSpace& m_cs;
    // Per 1 nm sample: the normalised wavelength and the illuminant times each matching
    // function over the illuminant's luminance sum.
    std::array<double, kDenseCount> m_t, m_wx, m_wy, m_wz;
};

} // namespace rayproc::spectral
