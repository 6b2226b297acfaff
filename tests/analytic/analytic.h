// Shared by the analytic tests (tests/analytic/, tag [analytic]): scenes whose radiance is known
// in closed form, rendered by every mode where the physics applies, and a check of the mean
// image radiance against the closed form that states the measured value and its standard error.
// docs/testing.md lists the cases, the tolerances and where they come from.
#pragma once

#include "test_util.h"

#include <cmath>
#include <sstream>
#include <string>

namespace rayproc::test {

inline std::string jsonVec(const Vec3& v) {
    std::ostringstream o;
    o.precision(9);
    o << "[" << v.x << ", " << v.y << ", " << v.z << "]";
    return o.str();
}

// Renders `scene` with `mode` at `spp` (seed fixed), quietly.
inline Image renderMode(const Scene& scene, const EmbreeScene& accel, const std::string& mode,
                        int spp, std::uint64_t seed = 1, int maxDepth = 0) {
    RenderOptions o;
    o.mode = mode;
    o.spp = spp;
    o.seed = seed;
    o.maxDepth = maxDepth;
    return render(scene, accel, o).image;
}

// A point light inside a closed diffuse sphere of radius 2 around the camera: every ray from
// the centre hits the wall (the processor's and the pipeline's tests).
inline const char* const kClosedSphere =
    R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov": 70, "resolution": [8, 8]},
        "materials": {"wall": {"type": "diffuse", "color": [0.8, 0.8, 0.8]}},
        "lights": [{"type": "point", "position": [0.3, -0.2, 0.1], "intensity": [1, 1, 1]}],
        "nodes": [{"type": "sphere", "material": "wall", "radius": 2}]})";

// gi mode at its defaults (photon counts, gather rays, cache) with `spp` and a fixed seed.
inline RenderResult renderGiMode(const Scene& scene, const EmbreeScene& accel, int spp,
                                 std::uint64_t seed = 1,
                                 GiDebugView view = GiDebugView::None) {
    EngineSettings engine;
    engine.threads = 2;
    engine.seed = seed;
    engine.quiet = true;
    GiSettings s = giSettings(scene, ModeOverrides{spp, 0, 0});
    s.debugView = view;
    return renderGi(scene, accel, s, engine);
}

// Checks, per channel, that gi mode at its defaults (giSpp) gives the image mean of path mode
// (pathSpp) within relTol.
inline void checkGiMeanMatchesPath(const Scene& scene, const EmbreeScene& accel, int giSpp,
                                   int pathSpp, double relTol, const std::string& label) {
    RenderOptions o;
    o.mode = "path";
    o.spp = pathSpp;
    Vec3 path = imageMean(render(scene, accel, o).image);
    Vec3 gi = imageMean(renderGiMode(scene, accel, giSpp).image);
    for (int c = 0; c < 3; ++c) {
        INFO(label << " channel " << c << ": gi " << gi[c] << " path " << path[c]);
        CHECK(gi[c] == Approx(path[c]).epsilon(relTol));
    }
}

// gi's tolerance in the analytic tests: photon density estimation is biased (the disc's
// curvature, the cone filter's O(1/k), RGBE rounding, the cache's interpolation); measured
// figures are in docs/testing.md.
constexpr double kGiTolerance = 0.02;

// Checks, per channel, that the mean radiance over the image (or the pixel rectangle) is within
// `relTol` of `expected`, and that the check is meaningful: the standard error of the mean
// (from the per-pixel spread) is below a quarter of the tolerance, so a 1% bias cannot hide
// in the noise and the noise alone fails with probability < 1e-4 (4 sigma).
inline void checkMeanRadiance(const Image& img, const Vec3& expected, double relTol,
                              const std::string& label, int x0 = 0, int y0 = 0, int x1 = 0,
                              int y1 = 0) {
    for (int c = 0; c < 3; ++c) {
        double e = expected[c];
        PixelStats st = pixelStats(img, c, x0, y0, x1, y1);
        double rel = e != 0 ? (st.mean - e) / e : st.mean;
        INFO(label << " channel " << c << ": mean " << st.mean << " expected " << e
                   << " relative error " << rel << " standard error " << st.stdError << " ("
                   << (e != 0 ? st.stdError / e : st.stdError) << " relative) over " << st.count
                   << " pixels");
        CHECK(std::abs(rel) <= relTol);
        CHECK(st.stdError <= 0.25 * relTol * std::max(std::abs(e), 1e-6));
    }
}

} // namespace rayproc::test
