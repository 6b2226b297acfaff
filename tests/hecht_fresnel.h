// Hecht's angle form of the unpolarised Fresnel reflectance (the mean of R_perp and R_par), typed
// from the textbook rather than from kernels/fresnel.h: the independent truth of the Fresnel and
// coated-model tests. A ray in a medium of index n1 meets one of index n2 at theta; 1 past the
// critical angle.
#pragma once

#include <cmath>

namespace rayproc::test {

inline double fresnelHecht(double theta, double n1, double n2) {
    double s = n1 / n2 * std::sin(theta);
    if (s >= 1.0) return 1.0;
    if (theta == 0.0) return std::pow((n1 - n2) / (n1 + n2), 2);
    double t = std::asin(s);
    double rPerp = std::sin(theta - t) / std::sin(theta + t);
    double rPar = std::tan(theta - t) / std::tan(theta + t);
    return 0.5 * (rPerp * rPerp + rPar * rPar);
}

} // namespace rayproc::test
