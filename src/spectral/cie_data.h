// The tabulated data behind the spectral core, generated at build time from Debian's colord-data
// (tools/spectral_data_gen.cpp): CIE 1931 2-degree colour matching functions, 360-830 nm in 5 nm
// steps, the CIE daylight basis, and the CIE illuminants by name (5 nm steps, A's 1 nm) ("A", "D65", "F11", ...). Scales are the files' own;
// src/spectral/spectra.cpp normalises.
#pragma once

namespace rayproc::spectral::data {

struct TabulatedSpectrum {
    const char* name;
    double startNm, stepNm;
    int count;
    const float* values;
};

constexpr int kCmfCount = 95; // 360, 365, ..., 830 nm
extern const float kCmfX[kCmfCount], kCmfY[kCmfCount], kCmfZ[kCmfCount];
// The CIE daylight basis S0, S1, S2 (300-830 nm, 5 nm; colord's CIE-1986-daylight-SPD.cmf).
extern const TabulatedSpectrum kDaylightBasis[3];
extern const TabulatedSpectrum kIlluminants[];
extern const int kIlluminantCount;

} // namespace rayproc::spectral::data
