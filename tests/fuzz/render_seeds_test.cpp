// render_fuzzer's seeds (tests/fuzz/render-seeds/: light power and filter parameters near
// float's limits) under render_fuzzer's contract (render_one.h), in the ordinary test build: each
// seed is a scene rayproc accepts, renders in every mode, and gives finite images that are not
// black (each seed has a light that reaches what the camera sees).
#include "render_one.h"
#include "test_util.h"

#include <filesystem>
#include <string>

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("render_fuzzer's seeds render in every mode: finite, not black", "[fuzz]") {
    int seeds = 0;
    for (const auto& entry :
         std::filesystem::directory_iterator(sourceDir() / "tests" / "fuzz" / "render-seeds")) {
        ++seeds;
        std::string name = entry.path().filename().string();
        std::vector<Image> images = fuzz::renderEveryMode(readText(entry.path().string()));
        INFO(name);
        REQUIRE(images.size() == 4);
        CHECK(fuzz::allFinite(images));
        const char* modes[] = {"preview", "raytrace", "path", "gi"};
        for (std::size_t m = 0; m < images.size(); ++m) {
            INFO("mode " << modes[m]);
            CHECK(meanValue(images[m]) > 0);
        }
    }
    CHECK(seeds >= 14);
}
