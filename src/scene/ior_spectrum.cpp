#include "scene/ior_spectrum.h"

#include "spectral/spectra.h"

#include <algorithm>
#include <cmath>

namespace rayproc {

float IorSpectrum::at(float nm) const {
    if (form == Form::Sellmeier) {
        const double l2 = double(nm) * double(nm) * 1e-6; // um^2
        double n2 = 1;
        for (int i = 0; i < 3; ++i) n2 += b[std::size_t(i)] * l2 / (l2 - c[std::size_t(i)]);
        return float(std::sqrt(n2));
    }
    const std::size_t n = pairs.size() / 2;
    if (n == 0) return 1.0f;
    const double x = std::clamp(double(nm), pairs[0], pairs[2 * (n - 1)]);
    return float(spectral::piecewiseLinear(pairs, x));
}

namespace {

// Schott's catalogue data of pbrt-v4's named glasses: n_d (587.56 nm) and the Sellmeier
// coefficients (B1, B2, B3; C1, C2, C3 in um^2), published physical data.
// tests/scene/ior_spectrum_test.cpp checks each formula against two independent catalogue
// figures: its n_d, and the Abbe number v_d.
struct Glass {
    const char* name;
    double nd;
    double b[3], c[3];
};
const Glass kGlasses[] = {
    {"glass-BK7", 1.5168, {1.03961212, 0.231792344, 1.01046945},
     {0.00600069867, 0.0200179144, 103.560653}},
    {"glass-BAF10", 1.6700, {1.5851495, 0.143559385, 1.08521269},
     {0.00926681282, 0.0424489805, 105.613573}},
    {"glass-FK51A", 1.4866, {0.971247817, 0.216901417, 0.904651666},
     {0.00472301995, 0.0153575612, 168.68133}},
    {"glass-LASF9", 1.8503, {2.00029547, 0.298926886, 1.80691843},
     {0.0121426017, 0.0538736236, 156.530829}},
    {"glass-F5", 1.6727, {1.46141885, 0.247713019, 0.949995832},
     {0.0111826126, 0.0508594669, 112.041888}},
    {"glass-F10", 1.7283, {1.61625977, 0.259229334, 1.07762317},
     {0.0127534559, 0.0581983954, 116.60768}},
    {"glass-F11", 1.7847, {1.73759695, 0.313747346, 1.89878101},
     {0.013188707, 0.0623068142, 155.23629}},
};

const Glass* findGlass(const std::string& name) {
    for (const Glass& g : kGlasses)
        if (name == g.name) return &g;
    return nullptr;
}

} // namespace

bool namedGlassIndex(const std::string& name, double& nd) {
    const Glass* g = findGlass(name);
    if (g) nd = g->nd;
    return g != nullptr;
}

IorSpectrumRef namedGlassDispersion(const std::string& name) {
    const Glass* g = findGlass(name);
    if (!g) return nullptr;
    auto s = std::make_shared<IorSpectrum>();
    s->form = IorSpectrum::Form::Sellmeier;
    for (int i = 0; i < 3; ++i) {
        s->b[std::size_t(i)] = g->b[i];
        s->c[std::size_t(i)] = g->c[i];
    }
    s->label = name;
    return s;
}

IorSpectrumRef sampledIor(const std::vector<double>& pairs) {
    if (pairs.size() < 2) return nullptr;
    bool constant = true;
    for (std::size_t i = 3; i < pairs.size(); i += 2) constant = constant && pairs[i] == pairs[1];
    if (constant) return nullptr;
    auto s = std::make_shared<IorSpectrum>();
    s->form = IorSpectrum::Form::Pairs;
    s->pairs = pairs;
    s->label = "sampled spectrum";
    return s;
}

} // namespace rayproc
