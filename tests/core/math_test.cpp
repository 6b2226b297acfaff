#include "core/math.h"

#include <catch2/catch.hpp>

using namespace rayproc;

TEST_CASE("Affine inverse undoes the transform", "[core][math]") {
    Affine a = Affine::translate({1, 2, 3}) * Affine::rotate(37, {1, 1, 0}) *
               Affine::scale({2, 0.5f, 3});
    Affine inv = a.inverse();
    Vec3 p{0.3f, -1.2f, 4.0f};
    Vec3 q = inv.point(a.point(p));
    CHECK(q.x == Approx(p.x).margin(1e-5));
    CHECK(q.y == Approx(p.y).margin(1e-5));
    CHECK(q.z == Approx(p.z).margin(1e-5));
}

TEST_CASE("Normals stay perpendicular under non-uniform scale", "[core][math]") {
    Affine a = Affine::rotate(30, {0, 0, 1}) * Affine::scale({4, 1, 1});
    Vec3 t{1, 1, 0}; // a tangent of the plane x + -y = 0 ... with normal n
    Vec3 n{1, -1, 0};
    Vec3 tw = a.vector(t);
    Vec3 nw = a.inverse().normalByInverse(n);
    CHECK(dot(tw, nw) == Approx(0).margin(1e-5));
}

TEST_CASE("lookAt builds a right-handed camera frame", "[core][math]") {
    Affine c = Affine::lookAt({0, 1, 6.8f}, {0, 1, 0}, {0, 1, 0});
    Vec3 fwd = c.vector({0, 0, -1});
    Vec3 right = c.vector({1, 0, 0});
    CHECK(fwd.z == Approx(-1));
    CHECK(right.x == Approx(1)); // world +x is image right
    CHECK(c.point({0, 0, 0}).z == Approx(6.8f));
}
