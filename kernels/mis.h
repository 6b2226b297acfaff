// Multiple importance sampling weights (Veach 1997, chapter 9).
#pragma once

#include <cmath>

namespace rayproc::kernels {

// Veach's power heuristic with beta = 2.
// Written as 1 / (1 + (pb/pa)^2) so that huge pdfs (a near-delta glossy lobe) cannot overflow
// the squares into inf / inf = NaN.
inline float powerHeuristic(float pa, float pb) {
    if (!(pa > 0)) return 0.0f;
    if (!(pb > 0) || std::isinf(pa)) return std::isinf(pb) ? 0.5f : 1.0f;
    if (std::isinf(pb)) return 0.0f;
    float r = pb / pa;
    return 1.0f / (1.0f + r * r);
}

} // namespace rayproc::kernels
