#include "spectral/spectra.h"

#include "spectral/cie_data.h"

#include <cmath>
#include <map>
#include <memory>

namespace rayproc::spectral {

namespace {

// A tabulated spectrum at `nm`: linear between its samples, zero outside.
double tabulatedAt(const float* v, int count, double startNm, double stepNm, double nm) {
    double x = (nm - startNm) / stepNm;
    if (x < 0 || x > count - 1) return 0;
    int i = std::min(int(x), count - 2);
    double t = x - i;
    return v[i] * (1 - t) + v[i + 1] * t;
}

DenseSpectrum cmf(const float* table) {
    return DenseSpectrum::sample([table](double nm) {
        return tabulatedAt(table, data::kCmfCount, 360.0, 5.0, nm);
    });
}

} // namespace

DenseSpectrum DenseSpectrum::sample(const std::function<double(double)>& f) {
    DenseSpectrum s;
    for (int i = 0; i < kDenseCount; ++i) s.values[i] = float(f(kLambdaMin + i));
    return s;
}

const DenseSpectrum& cieX() {
    static const DenseSpectrum s = cmf(data::kCmfX);
    return s;
}
const DenseSpectrum& cieY() {
    static const DenseSpectrum s = cmf(data::kCmfY);
    return s;
}
const DenseSpectrum& cieZ() {
    static const DenseSpectrum s = cmf(data::kCmfZ);
    return s;
}

double cieYIntegral() {
    static const double sum = [] {
        double s = 0;
        for (float v : cieY().values) s += v;
        return s;
    }();
    return sum;
}

Xyz toXyz(const std::function<double(double)>& f) {
    Xyz r;
    const auto &x = cieX().values, &y = cieY().values, &z = cieZ().values;
    for (int i = 0; i < kDenseCount; ++i) {
        double v = f(kLambdaMin + i);
        r.x += v * x[i];
        r.y += v * y[i];
        r.z += v * z[i];
    }
    double n = cieYIntegral();
    return {r.x / n, r.y / n, r.z / n};
}

Xyz toXyz(const DenseSpectrum& s) {
    return toXyz([&s](double nm) { return double(s.at(float(nm))); });
}

const DenseSpectrum* cieIlluminant(const std::string& name) {
    static const std::map<std::string, std::unique_ptr<DenseSpectrum>> table = [] {
        std::map<std::string, std::unique_ptr<DenseSpectrum>> m;
        for (int k = 0; k < data::kIlluminantCount; ++k) {
            const auto& t = data::kIlluminants[k];
            auto s = std::make_unique<DenseSpectrum>(DenseSpectrum::sample([&t](double nm) {
                return tabulatedAt(t.values, t.count, t.startNm, t.stepNm, nm);
            }));
            double y = toXyz(*s).y; // luminance relative to the 1 nm y-bar sum
            for (float& v : s->values) v = float(v / y);
            m.emplace(t.name, std::move(s));
        }
        return m;
    }();
    auto it = table.find(name);
    return it == table.end() ? nullptr : it->second.get();
}

DenseSpectrum daylightIlluminant(double x, double y) {
    // CIE 15: the basis weights of a daylight of chromaticity (x, y).
    double m = 0.0241 + 0.2562 * x - 0.7341 * y;
    double m1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / m;
    double m2 = (0.0300 - 31.4424 * x + 30.0717 * y) / m;
    const data::TabulatedSpectrum* b = data::kDaylightBasis;
    auto at = [&](int k, double nm) {
        return tabulatedAt(b[k].values, b[k].count, b[k].startNm, b[k].stepNm, nm);
    };
    DenseSpectrum s = DenseSpectrum::sample(
        [&](double nm) { return at(0, nm) + m1 * at(1, nm) + m2 * at(2, nm); });
    double lum = toXyz(s).y;
    for (float& v : s.values) v = float(v / lum);
    return s;
}

const DenseSpectrum& acesD60Illuminant() {
    static const DenseSpectrum s = daylightIlluminant(0.32168, 0.33767);
    return s;
}

std::vector<std::string> cieIlluminantNames() {
    std::vector<std::string> names;
    for (int k = 0; k < data::kIlluminantCount; ++k) names.push_back(data::kIlluminants[k].name);
    return names;
}

double piecewiseLinear(const std::vector<double>& pairs, double nm) {
    std::size_t n = pairs.size() / 2;
    if (n == 0 || nm < pairs[0] || nm > pairs[2 * (n - 1)]) return 0;
    if (n == 1) return pairs[1];
    // The segment [l_i, l_i+1] holding nm, by bisection over the ascending wavelengths.
    std::size_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        std::size_t mid = (lo + hi) / 2;
        (pairs[2 * mid] <= nm ? lo : hi) = mid;
    }
    double l0 = pairs[2 * lo], l1 = pairs[2 * hi];
    double t = l1 > l0 ? (nm - l0) / (l1 - l0) : 0;
    return pairs[2 * lo + 1] * (1 - t) + pairs[2 * hi + 1] * t;
}

} // namespace rayproc::spectral
