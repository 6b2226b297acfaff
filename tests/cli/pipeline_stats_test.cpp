// `rayproc render --stats` and `--stats-json` print each pipeline the render ran, in order:
// the emitter, the queue, the intersector, then every stage with the queues that feed it and
// the batches and rays each carried (engine/pipeline.h, RenderStats::pipelines).
#include "test_util.h"

#include <nlohmann/json.hpp>

#include <string>

using namespace rayproc;
using namespace rayproc::test;

namespace {

bool contains(const std::string& text, const std::string& what) {
    return text.find(what) != std::string::npos;
}

// A stage row of the --stats pipeline table: its stage, queue and query, and whether the
// queue carried rays.
bool hasRow(const std::string& table, const std::string& stage, const std::string& queue,
            const std::string& query) {
    std::istringstream in(table);
    for (std::string l; std::getline(in, l);) {
        std::istringstream row(l);
        std::string s, q, how;
        unsigned long long batches = 0, rays = 0;
        if (row >> s >> q >> how >> batches >> rays && s == stage && q == queue && how == query)
            return batches > 0 && rays >= batches;
    }
    return false;
}

RunResult renderWithStats(const TempDir& dir, const std::string& mode) {
    return runRayproc({"render", scenePath("cornell-box"), "--mode", mode, "--width", "24",
                       "--height", "24", "--spp", "2", "--threads", "2", "--quiet", "-o",
                       dir.file(mode + ".pfm"), "--stats", "--stats-json",
                       dir.file(mode + ".json")},
                      dir, 120);
}

} // namespace

TEST_CASE("The render statistics (--stats) list a path render's pipeline with its queues",
          "[cli][pipeline]") {
    TempDir dir;
    RunResult r = renderWithStats(dir, "path");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(contains(r.err, "pipeline render: camera emitter -> queue -> intersect (packets of "));
    CHECK(contains(r.err, "-> path [camera, reflection"));
    CHECK(hasRow(r.err, "path", "camera", "closest"));
    CHECK(hasRow(r.err, "path", "reflection", "closest"));
    CHECK(hasRow(r.err, "shadow", "shadow", "occlusion"));
    // The table the tests and scripts read before is still there.
    CHECK(contains(r.err, "rays traced "));
    nlohmann::json j = nlohmann::json::parse(readText(dir.file("path.json")));
    REQUIRE(j["pipelines"].size() == 1);
    const nlohmann::json& p = j["pipelines"][0];
    CHECK(p["name"] == "render");
    CHECK(p["emitter"] == "camera");
    REQUIRE(p["stages"].size() == 2);
    CHECK(p["stages"][0]["name"] == "path");
    CHECK(p["stages"][1]["name"] == "shadow");
    CHECK(p["stages"][1]["queues"][0]["query"] == "occlusion");
    CHECK(p["stages"][0]["rays"].get<std::uint64_t>() >= 24u * 24u * 2u);
    CHECK(j.contains("stages"));
    CHECK(j.contains("pipeline"));
}

TEST_CASE("The render statistics (--stats) list every pipeline of a gi render in order",
          "[cli][pipeline]") {
    TempDir dir;
    RunResult r = renderWithStats(dir, "gi");
    INFO(r.err);
    REQUIRE(r.status == 0);
    const std::size_t photons = r.err.find("pipeline photons: photon emitter -> queue");
    const std::size_t prepass = r.err.find("pipeline cache prepass: camera emitter -> queue");
    const std::size_t render = r.err.find("pipeline render: camera emitter -> queue");
    REQUIRE(photons != std::string::npos);
    REQUIRE(prepass != std::string::npos);
    REQUIRE(render != std::string::npos);
    CHECK(photons < prepass);
    CHECK(prepass < render);
    CHECK(contains(r.err, "-> surface [camera, reflection"));
    CHECK(contains(r.err, "-> gather [gather, gather-shadow: occlusion]"));
    CHECK(hasRow(r.err, "photon", "photon", "closest"));
    CHECK(hasRow(r.err, "gather", "gather", "closest"));
    nlohmann::json j = nlohmann::json::parse(readText(dir.file("gi.json")));
    std::vector<std::string> names;
    for (const nlohmann::json& p : j["pipelines"]) names.push_back(p["name"]);
    REQUIRE(names.size() >= 3);
    CHECK(names.front() == "photons");
    CHECK(names.back() == "render");
    const nlohmann::json& last = j["pipelines"].back();
    CHECK(last["stages"][0]["name"] == "surface");
    CHECK(last["stages"][0]["queues"][0]["kind"] == "camera");
    CHECK(last["stages"][0]["queues"][0]["batches"].get<std::uint64_t>() > 0);
}
