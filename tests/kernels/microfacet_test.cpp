// The Trowbridge-Reitz distribution's identities, by quadrature over the hemisphere of normals:
// the projected microfacet area is the macro surface's (int D(m) cos theta_m dm = 1), the
// visible normals of any direction form a distribution (int D_w(m) dm = 1, which ties Lambda to
// D), Smith's G1 is Lambda's, the height-correlated G is symmetric and between the separable
// G1 G1 and min(G1, G1). Also the shading frame: Gram-Schmidt on the tangent, and isotropic roughness
// unaffected by the tangent.
#include "kernels/bsdf_sampling.h"
#include "kernels/microfacet.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace rayproc;
using namespace rayproc::kernels;

namespace {

// int over the upper hemisphere of g(m) dm on an n x m grid in (cos theta, phi); the grid is
// refined towards cos = 1, where narrow distributions put their mass (cos = 1 - t^2).
template <class F> double hemisphere(F g, int n = 1500, int m = 400) {
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        double t = (i + 0.5) / n, c = 1.0 - t * t, dc = 2.0 * t / n;
        double s = std::sqrt(std::max(0.0, 1.0 - c * c));
        for (int j = 0; j < m; ++j) {
            double phi = 2 * kPi * (j + 0.5) / m;
            Vec3 h(float(s * std::cos(phi)), float(s * std::sin(phi)), float(c));
            sum += g(h) * dc * (2 * kPi / m);
        }
    }
    return sum;
}

Vec3 dir(float thetaDeg, float phiDeg) {
    float t = thetaDeg * kPi / 180, p = phiDeg * kPi / 180;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

} // namespace

TEST_CASE("Trowbridge-Reitz: D and the visible normals are normalised", "[bsdf][microfacet]") {
    const TrowbridgeReitz dists[] = {{0.05f, 0.05f}, {0.3f, 0.3f}, {0.9f, 0.9f}, {0.1f, 0.5f}};
    for (const TrowbridgeReitz& mf : dists) {
        std::string label = "alphas " + std::to_string(mf.alphaX) + ", " +
                            std::to_string(mf.alphaY);
        double projected = hemisphere([&](const Vec3& m) { return mf.d(m) * m.z; });
        INFO(label << ": int D cos = " << projected);
        CHECK(std::abs(projected - 1.0) < 2e-3);
        for (float theta : {0.0f, 40.0f, 80.0f}) {
            Vec3 w = dir(theta, 20.0f);
            // Only front-facing normals are visible; dVisible (|w.m|, as pbrt-v4) is only ever
            // asked about those.
            double visible = hemisphere(
                [&](const Vec3& m) { return dot(w, m) > 0 ? mf.dVisible(w, m) : 0.0f; });
            INFO(label << ", theta " << theta << ": int D_w = " << visible);
            CHECK(std::abs(visible - 1.0) < 3e-3);
        }
    }
    // The check can fail: with Lambda of twice the alpha, D_w no longer integrates to 1.
    TrowbridgeReitz mf{0.4f, 0.4f}, wider{0.8f, 0.8f};
    Vec3 w = dir(70.0f, 0.0f);
    double wrong = hemisphere([&](const Vec3& m) {
        return wider.g1(w) / w.z * mf.d(m) * std::max(0.0f, dot(w, m));
    });
    CHECK(std::abs(wrong - 1.0) > 0.05);
}

TEST_CASE("Trowbridge-Reitz: masking-shadowing", "[bsdf][microfacet]") {
    TrowbridgeReitz mf{0.2f, 0.6f};
    for (float a : {0.0f, 30.0f, 60.0f, 85.0f})
        for (float b : {10.0f, 45.0f, 89.0f}) {
            Vec3 wo = dir(a, 10.0f), wi = dir(b, 200.0f);
            INFO("theta_o " << a << ", theta_i " << b);
            CHECK(mf.g(wo, wi) == Approx(mf.g(wi, wo)));
            // 1 + Lo + Li <= (1 + Lo)(1 + Li): correlation masks less than independence.
            CHECK(mf.g(wo, wi) >= mf.g1(wo) * mf.g1(wi) * 0.999999f);
            CHECK(mf.g(wo, wi) <= std::min(mf.g1(wo), mf.g1(wi)) * 1.000001f);
            CHECK(mf.g1(wo) == Approx(1.0f / (1.0f + mf.lambda(wo))));
        }
    CHECK(mf.g1(Vec3(0, 0, 1)) == 1.0f);
    // Isotropic Lambda in closed form: (sqrt(1 + alpha^2 tan^2) - 1) / 2.
    TrowbridgeReitz iso{0.5f, 0.5f};
    Vec3 w = dir(60.0f, 77.0f);
    float tan2 = 3.0f; // tan^2(60 degrees)
    CHECK(iso.lambda(w) == Approx(0.5f * (std::sqrt(1.0f + 0.25f * tan2) - 1.0f)).epsilon(1e-4));
}

TEST_CASE("Shading frame: Gram-Schmidt tangent, any axis when degenerate", "[bsdf][microfacet]") {
    Vec3 n = normalize(Vec3(0.2f, -0.3f, 0.9f));
    for (Vec3 t : {Vec3(1, 0, 0), Vec3(0.3f, 0.9f, 0.5f), Vec3(0, 0, 0), n * 2.0f}) {
        ShadingFrame f(n, t);
        CHECK(std::abs(dot(f.x, f.n)) < 1e-6f);
        CHECK(std::abs(dot(f.y, f.n)) < 1e-6f);
        CHECK(std::abs(dot(f.x, f.y)) < 1e-6f);
        CHECK(std::abs(length(f.x) - 1) < 1e-6f);
        CHECK(length(cross(f.x, f.y) - f.n) < 1e-5f); // right-handed
        Vec3 w = normalize(Vec3(0.5f, 0.1f, 0.7f));
        CHECK(length(f.toWorld(f.toLocal(w)) - w) < 1e-6f);
    }
    // The tangent's in-plane part is the x axis.
    ShadingFrame f(Vec3(0, 0, 1), Vec3(1, 1, 3));
    CHECK(length(f.x - normalize(Vec3(1, 1, 0))) < 1e-6f);

    // Isotropic roughness: the tangent changes nothing (up to rounding).
    BsdfParams a, b;
    a.kind = b.kind = BsdfKind::Conductor;
    a.eta = b.eta = Vec3(0.2f, 0.9f, 1.1f);
    a.k = b.k = Vec3(3.9f, 2.4f, 2.2f);
    a.alphaX = a.alphaY = b.alphaX = b.alphaY = 0.3f;
    b.tangent = Vec3(0.6f, -0.8f, 0.0f);
    Vec3 up(0, 0, 1), wo = dir(40.0f, 30.0f), wi = dir(55.0f, 190.0f);
    float pa, pb;
    Vec3 fa = evalBsdf(a, wo, wi, up, up, pa), fb = evalBsdf(b, wo, wi, up, up, pb);
    CHECK(pa == Approx(pb).epsilon(1e-5));
    CHECK(fa.x == Approx(fb.x).epsilon(1e-5));
    // Anisotropic: rotating the tangent by 90 degrees swaps the alphas.
    BsdfParams c = a, d = a;
    c.alphaX = 0.1f;
    c.alphaY = 0.5f;
    c.tangent = Vec3(1, 0, 0);
    d.alphaX = 0.5f;
    d.alphaY = 0.1f;
    d.tangent = Vec3(0, 1, 0);
    Vec3 fc = evalBsdf(c, wo, wi, up, up, pa), fd = evalBsdf(d, wo, wi, up, up, pb);
    CHECK(pa == Approx(pb).epsilon(1e-4));
    CHECK(fc.y == Approx(fd.y).epsilon(1e-4));
    Vec3 fa2 = evalBsdf(a, wo, wi, up, up, pa);
    CHECK(std::abs(fc.y - fa2.y) > 1e-3f * fa2.y); // and anisotropy does change the value
}
