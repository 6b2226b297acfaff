// The OpenImageIO module: rayproc does not link OpenImageIO (its ~260 libraries cost every
// process ~0.17 s to load); the texture loader dlopen()s librayproc_oiio.so on first use.
#include "test_util.h"

#include "image/image.h"
#include "texture/oiio_module.h"
#include "texture/texture_image.h"

#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("the rayproc binary does not link OpenImageIO", "[texture][oiio]") {
    TempDir dir;
    std::string out = (dir.path / "ldd.out").string(), err = (dir.path / "ldd.err").string();
    Child ldd({rayprocBinary()}, out, err, "/usr/bin/ldd");
    REQUIRE(ldd.started());
    REQUIRE(ldd.wait(60));
    REQUIRE(ldd.status() == 0);
    std::ifstream in(out);
    std::stringstream text;
    text << in.rdbuf();
    INFO(text.str());
    CHECK(text.str().find("libembree3") != std::string::npos); // ldd did list the libraries
    CHECK(text.str().find("libOpenImageIO") == std::string::npos);
}

TEST_CASE("the image module loads and reports a file it cannot read", "[texture][oiio]") {
    const OiioModule& m = OiioModule::get();
    CHECK(m.path.find("librayproc_oiio.so") != std::string::npos);
    REQUIRE(m.open);
    REQUIRE(m.read);
    REQUIRE(m.close);
    CHECK(&OiioModule::get() == &m); // loaded once

    TempDir dir;
    char error[256] = "";
    RayprocOiioInfo info{};
    std::string missing = (dir.path / "missing.tga").string();
    CHECK(m.open(missing.c_str(), &info, error, sizeof error) == nullptr);
    CHECK(std::string(error).size() > 0);

    // A 3x2 linear PFM read back through the module: its size, channels and float samples.
    Image img(3, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y)[c] = float(10 * y + x) + 0.25f * float(c);
    std::string path = (dir.path / "ramp.pfm").string();
    writeImage(path, img);
    void* h = m.open(path.c_str(), &info, error, sizeof error);
    REQUIRE(h != nullptr);
    CHECK(info.width == 3);
    CHECK(info.height == 2);
    CHECK(info.channels == 3);
    CHECK(info.isFloat == 1);
    std::vector<float> px(3 * 2 * 3);
    CHECK(m.read(h, px.data(), error, sizeof error) == 1);
    m.close(h);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x)
            for (int c = 0; c < 3; ++c)
                CHECK(px[std::size_t(3 * (3 * y + x) + c)] == img.at(x, y)[c]);
}
