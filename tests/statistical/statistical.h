// The statistical suite's shared constants: how many chi-square tests it runs (for the Sidak
// correction), the sample count per test and the histogram resolution.
#pragma once

#include "chi_square.h"

namespace rayproc::test {

// Chi-square tests in tests/statistical/: diffuse 3, glossy 9 (bsdf_sampling_test.cpp), lights
// 4 (light_sampling_test.cpp); rough conductor 14, rough dielectric 13, diffuse transmission 3
// (microfacet_bsdf_test.cpp); coated diffuse 4 weighted-histogram tests
// (coated_diffuse_bsdf_test.cpp); the analytic coat 4 (tests/kernels/coated_analytic_test.cpp);
// pixel filters 11 (filter_sampling_test.cpp); sphere mappings 1 and image skies 3
// (tests/lighting/sphere_mapping_test.cpp, environment_light_test.cpp); the light sampler 42
// (tests/lighting/light_sampler_test.cpp). That is 111, rounded up to 114: a larger count only
// makes each test stricter. Every one of them rejects at testSignificance(), so a correct suite
// fails by chance with probability at most 1% (docs/testing.md, "Statistical tests").
constexpr int kChiSquareTests = 114;
constexpr double kOverallSignificance = 0.01;
inline double testSignificance() { return sidakSignificance(kOverallSignificance, kChiSquareTests); }

// 10 x 20 bins as pbrt-v4 and Mitsuba; 10^6 samples (~0.1 s per test) expect ~5000 per bin, so a
// bin whose pdf integral is off by 5% adds ~12 to a statistic of ~200 degrees of freedom. The
// expected counts are integrated adaptively to 2% of each bin's Poisson noise.
constexpr int kThetaBins = 10, kPhiBins = 20, kSamples = 1000000;

} // namespace rayproc::test
