#include "scene/metals.h"

namespace rayproc {

namespace {

struct Metal {
    const char* name;
    Vec3 eta, k;
};

// Complex refractive indices at the sRGB primaries' bands: silver, aluminium, gold and copper
// from the measured data (Palik / Rakic) behind pbrt-v4's spectra, as tabulated for RGB
// renderers (Tungsten's ComplexIorData); brass (CuZn) from its measured spectrum, magnesium
// oxide and titanium dioxide are dielectrics (k ~ 0).
const Metal kMetals[] = {
    {"Ag", {0.1552646489f, 0.1167232965f, 0.1383806959f}, {4.8283433224f, 3.1222459278f, 2.1469504455f}},
    {"Al", {1.6574599595f, 0.8803689579f, 0.5212287346f}, {9.2238691996f, 6.2695232477f, 4.8370012281f}},
    {"Au", {0.1431189557f, 0.3749570432f, 1.4424785571f}, {3.9831604247f, 2.3857207478f, 1.6032152899f}},
    {"Cu", {0.2004376970f, 0.9240334304f, 1.1022119527f}, {3.9129485033f, 2.4528477015f, 2.1421879552f}},
    {"CuZn", {0.444f, 0.527f, 1.094f}, {3.695f, 2.765f, 1.829f}},
    {"MgO", {2.0895885542f, 1.6507224525f, 1.5948759692f}, {0.0f, 0.0f, 0.0f}},
    {"TiO2", {3.4566203131f, 2.8017076558f, 2.9051485020f}, {0.0f, 0.0f, 0.0f}},
};

} // namespace

bool namedMetal(const std::string& element, Vec3& eta, Vec3& k) {
    for (const Metal& m : kMetals) {
        if (element == m.name) {
            eta = m.eta;
            k = m.k;
            return true;
        }
    }
    return false;
}

bool namedMetalSpectrum(const std::string& name, Vec3& out) {
    // "metal-<element>-eta" or "metal-<element>-k"
    if (name.rfind("metal-", 0) != 0) return false;
    std::size_t dash = name.rfind('-');
    if (dash <= 6) return false;
    std::string element = name.substr(6, dash - 6), part = name.substr(dash + 1);
    if (part != "eta" && part != "k") return false;
    Vec3 eta, k;
    if (!namedMetal(element, eta, k)) return false;
    out = part == "eta" ? eta : k;
    return true;
}

} // namespace rayproc
