// Build-time generator of the RGB -> spectrum coefficient tables (Jakob & Hanika 2019; docs/
// spectral.md, "RGB upsampling"). Usage: rgb2spec_gen COLOR_SPACE RES OUT.bin
// The table covers RGB in [0, 1]^3 by the largest component l (3 blocks), its value z on RES
// nodes z_k = smoothstep(smoothstep(k / (RES - 1))) (dense near black, where Lab is), and the two
// others over z on a RES x RES grid. Each cell is fitted by spectral::RgbFitter, started from its
// neighbour along z (from z_{RES/5} upwards, then downwards), which converges in a few steps.
// File: "RPSG", int32 RES, RES floats z_k, then 3 x RES^3 x 3 floats (l, k, j, i, coefficient).
#include "spectral/rgb_fit.h"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <thread>
#include <vector>

using namespace rayproc::spectral;

namespace {

double smoothstep(double x) { return x * x * (3 - 2 * x); }

} // namespace

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: rgb2spec_gen COLOR_SPACE RES OUT.bin\n");
        return 2;
    }
    const ColorSpace* cs = colorSpaceByName(argv[1]);
    int res = std::atoi(argv[2]);
    if (!cs || res < 3 || res > 256) {
        std::fprintf(stderr, "rgb2spec_gen: unknown colour space or bad resolution\n");
        return 2;
    }
    auto start = std::chrono::steady_clock::now();
    RgbFitter fitter(*cs);
    std::vector<float> zNodes(res);
    for (int k = 0; k < res; ++k) zNodes[k] = float(smoothstep(smoothstep(double(k) / (res - 1))));
    std::vector<float> table(std::size_t(3) * res * res * res * 3);
    std::atomic<int> next{0};
    std::atomic<long> unconverged{0};
    std::vector<double> worst(std::thread::hardware_concurrency() + 1, 0.0);
    auto worker = [&](int tid) {
        for (;;) {
            int job = next++;
            if (job >= 3 * res) return;
            int l = job / res, j = job % res;
            for (int i = 0; i < res; ++i) {
                double x = double(i) / (res - 1), y = double(j) / (res - 1);
                SigmoidCoefficients startC{0, 0, 0};
                int startK = res / 5;
                auto solveAt = [&](int k, SigmoidCoefficients& c) {
                    double z = zNodes[k];
                    std::array<double, 3> rgb;
                    rgb[l] = z;
                    rgb[(l + 1) % 3] = x * z;
                    rgb[(l + 2) % 3] = y * z;
                    double r = fitter.fit(rgb, c);
                    if (r > 1e-3) ++unconverged;
                    worst[tid] = std::max(worst[tid], r);
                    float* out = &table[((((std::size_t(l) * res + k) * res + j) * res + i)) * 3];
                    for (int q = 0; q < 3; ++q) out[q] = float(c[q]);
                };
                SigmoidCoefficients c = startC;
                for (int k = startK; k < res; ++k) solveAt(k, c);
                const float* s = &table[((((std::size_t(l) * res + startK) * res + j) * res + i)) * 3];
                c = {s[0], s[1], s[2]};
                for (int k = startK - 1; k >= 0; --k) solveAt(k, c);
            }
        }
    };
    int threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back(worker, t);
    for (auto& t : pool) t.join();
    double maxResidual = 0;
    for (double w : worst) maxResidual = std::max(maxResidual, w);

    std::ofstream out(argv[3], std::ios::binary);
    out.write("RPSG", 4);
    int32_t r32 = res;
    out.write(reinterpret_cast<const char*>(&r32), 4);
    out.write(reinterpret_cast<const char*>(zNodes.data()), zNodes.size() * sizeof(float));
    out.write(reinterpret_cast<const char*>(table.data()), table.size() * sizeof(float));
    if (!out) {
        std::fprintf(stderr, "rgb2spec_gen: cannot write %s\n", argv[3]);
        return 1;
    }
    double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("rgb2spec_gen: %s at %d^3: %.1f s on %d threads, largest CIELAB residual %.3g, "
                "%ld of %ld cells above 1e-3\n",
                argv[1], res, secs, threads, maxResidual, long(unconverged),
                3L * res * res * res);
    return 0;
}
