// The page's script against the server's messages, in node with a stand-in DOM
// (tests/serve/page_script.cjs; the browser test is tests/e2e). Skipped without node.
#include "test_util.h"

#include "serve/server.h"
#include "skip.h"

#include <catch2/catch.hpp>

#include <cstdlib>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// Runs one scenario of page_script.cjs on the page the server sends; its output on failure.
int runScenario(const std::string& scenario, std::string& output) {
    TempDir dir;
    writeText(dir.file("page.html"), serve::kPage);
    std::string log = dir.file("out.txt");
    std::string command = "node '" + (sourceDir() / "tests" / "serve" / "page_script.cjs").string() +
                          "' '" + dir.file("page.html") + "' " + scenario + " > '" + log + "' 2>&1";
    int rc = std::system(command.c_str());
    output = readText(log);
    return rc;
}

bool haveNode() { return std::system("node --version > /dev/null 2>&1") == 0; }

} // namespace

TEST_CASE("serve page: a pick on a pbrt scene names the object - edits say the scene is read-only",
          "[serve]") {
    if (!haveNode()) RAYPROC_SKIP("node is not installed");
    std::string out;
    int rc = runScenario("pbrt_pick", out);
    INFO(out);
    CHECK(rc == 0);
}

TEST_CASE("serve page: light and emission fields keep all three channels", "[serve]") {
    if (!haveNode()) RAYPROC_SKIP("node is not installed");
    std::string out;
    int rc = runScenario("rgb_emission", out);
    INFO(out);
    CHECK(rc == 0);
}

TEST_CASE("serve page: a move step outside [-1000, 1000] is refused with the range named", "[serve]") {
    if (!haveNode()) RAYPROC_SKIP("node is not installed");
    std::string out;
    int rc = runScenario("move_step", out);
    INFO(out);
    CHECK(rc == 0);
}

TEST_CASE("serve page: a drag keeps one camera message in flight and sends the latest view",
          "[serve]") {
    if (!haveNode()) RAYPROC_SKIP("node is not installed");
    std::string out;
    int rc = runScenario("camera_throttle", out);
    INFO(out);
    CHECK(rc == 0);
}

TEST_CASE("serve page: fly, zoom and the orbit's pivot scale with the scene - zoom passes the pivot",
          "[serve]") {
    if (!haveNode()) RAYPROC_SKIP("node is not installed");
    std::string out;
    int rc = runScenario("scene_scaled_navigation", out);
    INFO(out);
    CHECK(rc == 0);
}

TEST_CASE("serve page: a 150-pixel orbit stays within a field of view - a gesture is one undo step",
          "[serve]") {
    if (!haveNode()) RAYPROC_SKIP("node is not installed");
    std::string out;
    int rc = runScenario("orbit_speed", out);
    INFO(out);
    CHECK(rc == 0);
}

TEST_CASE("serve page: refinement progress, exposure, resolution, statistics, reconnect",
          "[serve]") {
    if (!haveNode()) RAYPROC_SKIP("node is not installed");
    std::string out;
    int rc = runScenario("viewer_controls", out);
    INFO(out);
    CHECK(rc == 0);
}
