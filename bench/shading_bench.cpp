// Shading kernels the gather and shadow stages call per hit.
//
//   BM_FresnelConductor            kernels::fresnelComplex (real arithmetic), RGB, per call
//   BM_FresnelConductorStdComplex  the same reflectance through std::complex<float> (the form
//                                  the kernel replaced; kept here as the baseline)
//   BM_EnvironmentSample           Distribution2D::sample on a 512 x 512 lat-long sky, per call
//
// Fresnel inputs cycle through 4096 cosines in (0, 1] and gold's, copper's and aluminium's RGB
// indices. The sky: a blue gradient above the horizon, a sun of 1e4 times its radiance over
// about 30 pixels, the ground a hundredth of the horizon, each row weighted by sin theta as the
// environment light weights it; the sample points are 65,536 uniform pairs.
#include "kernels/fresnel.h"
#include "lighting/distribution_2d.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <complex>
#include <random>
#include <vector>

namespace rayproc::bench {
namespace {

constexpr int kInputs = 4096;

struct FresnelInputs {
    std::vector<float> cosines;
    Vec3 eta[3] = {{0.143f, 0.374f, 1.442f}, {0.200f, 0.924f, 1.102f}, {1.657f, 0.880f, 0.521f}};
    Vec3 k[3] = {{3.983f, 2.385f, 1.603f}, {3.912f, 2.452f, 2.142f}, {9.224f, 6.270f, 4.837f}};
    FresnelInputs() {
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> uni(1e-3f, 1.0f);
        cosines.resize(kInputs);
        for (float& c : cosines) c = uni(rng);
    }
};

float stdComplexFresnel(float cosI, float eta, float k) {
    using C = std::complex<float>;
    C n(eta, k);
    C cosT = std::sqrt(C(1.0f) - C(1.0f - cosI * cosI) / (n * n));
    C rPar = (n * cosI - cosT) / (n * cosI + cosT);
    C rPerp = (C(cosI) - n * cosT) / (C(cosI) + n * cosT);
    return 0.5f * (std::norm(rPar) + std::norm(rPerp));
}

template <typename F>
void runFresnel(benchmark::State& state, F fresnel) {
    static const FresnelInputs in;
    std::size_t i = 0;
    for (auto _ : state) {
        float c = in.cosines[i % kInputs];
        const Vec3 &eta = in.eta[i % 3], &k = in.k[i % 3];
        Vec3 f{fresnel(c, eta.x, k.x), fresnel(c, eta.y, k.y), fresnel(c, eta.z, k.z)};
        benchmark::DoNotOptimize(f);
        ++i;
    }
    state.SetItemsProcessed(std::int64_t(state.iterations()));
}

void BM_FresnelConductor(benchmark::State& state) {
    runFresnel(state,
               [](float c, float eta, float k) { return kernels::fresnelComplex(c, eta, k); });
}
BENCHMARK(BM_FresnelConductor);

void BM_FresnelConductorStdComplex(benchmark::State& state) {
    runFresnel(state, stdComplexFresnel);
}
BENCHMARK(BM_FresnelConductorStdComplex);

Distribution2D makeSky(int w, int h) {
    std::vector<float> weights(std::size_t(w) * std::size_t(h));
    for (int y = 0; y < h; ++y) {
        float theta = kPi * (float(y) + 0.5f) / float(h);
        for (int x = 0; x < w; ++x) {
            float sky = theta < 0.5f * kPi ? 0.3f + 0.7f * std::cos(theta) : 0.003f;
            float dx = float(x - w / 3), dy = float(y - h / 5);
            if (dx * dx + dy * dy < 10.0f) sky *= 1e4f;
            weights[std::size_t(y) * std::size_t(w) + std::size_t(x)] = sky * std::sin(theta);
        }
    }
    return Distribution2D(std::move(weights), w, h);
}

void BM_EnvironmentSample(benchmark::State& state) {
    static const Distribution2D sky = makeSky(512, 512);
    static const std::vector<Vec2> points = [] {
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> uni(0.0f, 1.0f);
        std::vector<Vec2> p(65536);
        for (Vec2& v : p) v = {uni(rng), uni(rng)};
        return p;
    }();
    std::size_t i = 0;
    for (auto _ : state) {
        float pdf;
        int x, y;
        Vec2 p = sky.sample(points[i++ & 65535], pdf, x, y);
        benchmark::DoNotOptimize(p);
        benchmark::DoNotOptimize(pdf);
    }
    state.SetItemsProcessed(std::int64_t(state.iterations()));
}
BENCHMARK(BM_EnvironmentSample);

} // namespace
} // namespace rayproc::bench
