// The rayproc command line, run as a real process: help texts, errors and exit statuses,
// statistics as JSON, progress when stderr is a file, Ctrl-C that writes the partial image,
// and the figures of `rayproc info`.
#include "test_util.h"

#include "modes/mode_options.h"
#include "modes/mode_registry.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <regex>

using namespace rayproc;
using namespace rayproc::test;

namespace {

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

// Lines like "raytrace:  42.0% elapsed 00:01 ETA 00:02 2.80 Mrays/s".
std::size_t progressLines(const std::string& err, const std::string& label) {
    std::regex re("^" + label + ": +[0-9]+\\.[0-9]% elapsed .* ETA .*Mrays/s$");
    std::size_t n = 0;
    for (const std::string& l : lines(err)) n += std::regex_match(l, re);
    return n;
}

bool contains(const std::string& text, const std::string& what) {
    return text.find(what) != std::string::npos;
}

} // namespace

TEST_CASE("Help texts exit 0 and name every command and option", "[cli]") {
    TempDir dir;
    RunResult top = runRayproc({"--help"}, dir);
    CHECK(top.status == 0);
    INFO(top.out);
    // The top level lists the subcommands; their options are in their own help.
    CHECK(contains(top.out, "render"));
    CHECK(contains(top.out, "info"));
    CHECK(contains(top.out, "--help"));
    CHECK(contains(top.out, "--version"));

    RunResult render = runRayproc({"render", "--help"}, dir);
    CHECK(render.status == 0);
    INFO(render.out);
    for (const char* option :
         {"--mode", "--spp", "--threads", "--seed", "--width", "--height", "--quiet", "--stats",
          "--stats-json", "--packet-width", "--progressive-output", "--output", "--max-depth",
          "--light-samples"}) {
        INFO("option " << option);
        // Followed by a space: "--stats" must not count as found inside "--stats-json".
        CHECK(contains(render.out, std::string(option) + " "));
    }
    CHECK(contains(render.out, "preview"));
    CHECK(contains(render.out, "raytrace"));

    RunResult info = runRayproc({"info", "--help"}, dir);
    CHECK(info.status == 0);
    CHECK(contains(info.out, "--json"));
}

TEST_CASE("An empty argument is refused as an unexpected one, not parsed forever", "[cli]") {
    // CLI11 2.1.2 took "" for one of the nameless subcommands an option group is and looped
    // (the CLI fuzzer's finding); the render command's mode options are headings instead.
    TempDir dir;
    RunResult render = runRayproc({"render", scenePath("cornell-box"), ""}, dir);
    CHECK(render.status == 1);
    CHECK(contains(render.err, "not expected"));
}

TEST_CASE("render --help lists each mode's own options in the mode's group", "[cli]") {
    TempDir dir;
    RunResult render = runRayproc({"render", "--help"}, dir);
    REQUIRE(render.status == 0);
    INFO(render.out);
    int modesWithOptions = 0;
    for (const ModeEntry& mode : modeRegistry()) {
        if (!mode.options) continue;
        ++modesWithOptions;
        // The mode's option names, as it declares them.
        CLI::App probe;
        CLI::App* declared = probe.add_option_group("probe");
        std::unique_ptr<ModeOptions> options = mode.options();
        options->add(*declared);
        // The group: from its heading to the next line that is not indented.
        const std::string heading = std::string(mode.name) + " options";
        const std::size_t start = render.out.find(heading);
        INFO("group " << heading);
        REQUIRE(start != std::string::npos);
        std::size_t end = render.out.find('\n', start);
        while (end != std::string::npos && end + 1 < render.out.size() &&
               render.out[end + 1] == ' ')
            end = render.out.find('\n', end + 1);
        const std::string group = render.out.substr(start, end - start);
        const std::string before = render.out.substr(0, start);
        std::size_t names = 0;
        for (const CLI::Option* option : declared->get_options()) {
            // The group's own --help, which CLI11 gives every group and never lists.
            if (option == declared->get_help_ptr()) continue;
            const std::string name = option->get_name();
            ++names;
            INFO("option " << name);
            // Declared at a line's start, followed by a space or the line's end: "--no-caustics"
            // must not count as found inside another name, nor in another option's help.
            const std::regex declaredHere("(^|\n) +" + name + "( |\n)");
            CHECK(std::regex_search(group, declaredHere));
            CHECK_FALSE(std::regex_search(before, declaredHere));
        }
        CHECK(names > 0);
    }
    CHECK(modesWithOptions > 0);
}

TEST_CASE("gi's own options and the shared ones reach gi's settings, as the render log shows",
          "[cli]") {
    TempDir dir;
    RunResult r = runRayproc({"render", scenePath("cornell-box"), "--mode", "gi", "--width", "16",
                              "--height", "16", "--spp", "1", "--ic-accuracy", "0.3", "--photons",
                              "1000", "--no-caustics", "--no-russian-roulette", "--debug-view",
                              "indirect", "-o", dir.file("img.pfm")},
                             dir, 600);
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(contains(r.err, " ic_accuracy=0.3 "));
    CHECK(contains(r.err, " photons=1000 "));
    CHECK(contains(r.err, " caustics=off "));
    CHECK(contains(r.err, " roulette=off "));
    CHECK(contains(r.err, " debug_view=indirect"));
}

TEST_CASE("An unknown mode fails and lists the known ones", "[cli]") {
    TempDir dir;
    std::string out = dir.file("x.pfm");
    RunResult r = runRayproc({"render", scenePath("cornell-box"), "--mode", "pathtrace", "-o", out,
                              "--width", "16", "--height", "16"},
                             dir);
    INFO(r.err);
    CHECK(r.status != 0);
    CHECK(contains(r.err, "pathtrace"));
    CHECK(contains(r.err, "preview"));
    CHECK(contains(r.err, "raytrace"));
    CHECK_FALSE(std::filesystem::exists(out));
}

TEST_CASE("A malformed scene fails with status 1 and names the file", "[cli]") {
    TempDir dir;
    std::string out = dir.file("x.pfm");
    SECTION("JSON syntax error") {
        std::string scene = dir.file("broken-syntax.json");
        writeText(scene, "{\n  \"nodes\": [\n    {\"type\": \"sphere\", \"radius\": 1,}\n");
        RunResult r = runRayproc({"render", scene, "-o", out}, dir);
        INFO(r.err);
        CHECK(r.status == 1);
        CHECK(contains(r.err, scene));
        CHECK(contains(r.err, "line 3"));
        CHECK_FALSE(std::filesystem::exists(out));
    }
    SECTION("unknown material") {
        std::string scene = dir.file("unknown-material.json");
        writeText(scene, R"({"nodes": [{"type": "sphere", "radius": 1, "material": "gold"}]})");
        RunResult r = runRayproc({"render", scene, "-o", out}, dir);
        INFO(r.err);
        CHECK(r.status == 1);
        CHECK(contains(r.err, scene));
        CHECK(contains(r.err, "gold"));
        CHECK_FALSE(std::filesystem::exists(out));
    }
    SECTION("info on the same file") {
        std::string scene = dir.file("broken.json");
        writeText(scene, "[1, 2");
        RunResult r = runRayproc({"info", scene}, dir);
        INFO(r.err);
        CHECK(r.status == 1);
        CHECK(contains(r.err, scene));
    }
}

TEST_CASE("A missing output directory fails before rendering", "[cli]") {
    TempDir dir;
    // A render that would take minutes: no progress line (not even the final one a finished or
    // interrupted render prints) proves the check comes first; the 30 s limit only catches a
    // hang.
    std::vector<std::string> slow = {
        "render", scenePath("cornell-box"), "--spp", "100000", "--width", "256", "--height", "256"};
    SECTION("image") {
        std::string out = dir.file("no-such-dir/out.png");
        auto args = slow;
        args.insert(args.end(), {"-o", out});
        RunResult r = runRayproc(args, dir, 30);
        INFO(r.err);
        CHECK(r.status == 1);
        CHECK(contains(r.err, dir.file("no-such-dir")));
        CHECK(progressLines(r.err, "raytrace") == 0);
    }
    SECTION("statistics") {
        std::string out = dir.file("out.png");
        auto args = slow;
        args.insert(args.end(), {"-o", out, "--stats-json", dir.file("missing/stats.json")});
        RunResult r = runRayproc(args, dir, 30);
        INFO(r.err);
        CHECK(r.status == 1);
        CHECK(contains(r.err, dir.file("missing")));
        CHECK(progressLines(r.err, "raytrace") == 0);
        CHECK_FALSE(std::filesystem::exists(out));
    }
}

TEST_CASE("Statistics as JSON with --stats-json", "[cli]") {
    TempDir dir;
    std::string out = dir.file("img.pfm"), stats = dir.file("stats.json");
    RunResult r = runRayproc({"render", scenePath("cornell-box"), "--width", "32", "--height", "32",
                              "--spp", "2", "--quiet", "-o", out, "--stats-json", stats},
                             dir);
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.empty());
    CHECK(contains(r.out, out));
    REQUIRE(std::filesystem::exists(stats));
    nlohmann::json j = nlohmann::json::parse(readText(stats));
    for (const char* key : {"wall_seconds", "rays", "invalid_samples", "stages"}) {
        INFO("key " << key);
        CHECK(j.contains(key));
    }
    CHECK(j["wall_seconds"].get<double>() > 0);
    CHECK(j["invalid_samples"].get<long long>() == 0);
    REQUIRE(j["stages"].is_object());
    CHECK(j["stages"].size() >= 4);
    std::uint64_t traced = 0;
    for (auto& [name, stage] : j["stages"].items()) {
        INFO("stage " << name);
        REQUIRE(stage.contains("rays"));
        REQUIRE(stage.contains("seconds"));
        CHECK(stage["rays"].is_number_unsigned());
        CHECK(stage["seconds"].get<double>() >= 0);
    }
    for (const char* name : {"camera", "intersect", "occlude", "surface", "shadow"}) {
        INFO("stage " << name);
        CHECK(j["stages"].contains(name));
    }
    traced = j["stages"]["intersect"]["rays"].get<std::uint64_t>() +
             j["stages"]["occlude"]["rays"].get<std::uint64_t>();
    CHECK(j["rays"].get<std::uint64_t>() == traced);
    CHECK(j["stages"]["intersect"]["rays"].get<std::uint64_t>() >= 32u * 32u * 2u);
    // The stages in pipeline order: the camera first, traversal next, the film's stages after.
    REQUIRE(j["pipeline"].is_array());
    CHECK(j["pipeline"].size() == j["stages"].size());
    CHECK(j["pipeline"][0] == "camera");
    // Phases: every part of the command's wall time, once, with how it ran.
    REQUIRE(j["phases"].is_array());
    double phaseSum = 0;
    std::vector<std::string> names;
    for (const nlohmann::json& p : j["phases"]) {
        INFO("phase " << p.dump());
        for (const char* key : {"name", "kind", "seconds", "threads", "count", "busy_fraction"})
            REQUIRE(p.contains(key));
        const std::string kind = p["kind"].get<std::string>();
        CHECK((kind == "serial" || kind == "parallel" || kind == "workers"));
        CHECK(p["seconds"].get<double>() >= 0);
        CHECK(p["busy_fraction"].is_null() == (kind != "workers"));
        phaseSum += p["seconds"].get<double>();
        names.push_back(p["name"].get<std::string>());
    }
    for (const char* name : {"scene_load", "bvh_build", "light_set", "render_passes",
                             "film_commit", "between_passes", "film_resolve", "image_write", "other"}) {
        INFO("phase " << name);
        CHECK(std::count(names.begin(), names.end(), name) == 1);
    }
    CHECK(phaseSum == Approx(j["process_seconds"].get<double>()).epsilon(1e-6));
    CHECK(j["process_seconds"].get<double>() >= j["wall_seconds"].get<double>());
    CHECK(j["serial_fraction"].get<double>() >= 0);
    CHECK(j["serial_fraction"].get<double>() <= 1);
    CHECK(j["workers_busy_fraction"].get<double>() > 0);
    Image img = readImage(out);
    CHECK(img.width == 32);
    CHECK(img.height == 32);
}

TEST_CASE("gi's --global-k sets the photons per estimate, and the render log says so", "[cli]") {
    TempDir dir;
    RunResult r = runRayproc({"render", scenePath("cornell-box"), "--mode", "gi", "--width", "16",
                              "--height", "16", "--spp", "1", "--photons", "5000", "--global-k",
                              "32", "-o", dir.file("img.pfm")},
                             dir, 600);
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(contains(r.err, "global_k=32"));
}

TEST_CASE("gi's --caustic-radius caps the caustic radius, and the render log says so", "[cli]") {
    TempDir dir;
    RunResult r = runRayproc({"render", scenePath("caustic-pool"), "--mode", "gi", "--width",
                              "16", "--height", "16", "--spp", "2", "--caustic-photons", "5000",
                              "--caustic-radius", "0.03", "--stats-json", dir.file("s.json"),
                              "-o", dir.file("img.pfm")},
                             dir, 600);
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(contains(r.err, "caustic_radius=0.03"));
    // The first map's 64th-neighbour radius is larger here (about 0.1): the cap decides.
    std::ifstream in(dir.file("s.json"));
    nlohmann::json stats = nlohmann::json::parse(in);
    CHECK(stats["gi"]["caustic_first_radius"].get<double>() == Approx(0.03).epsilon(1e-6));
}

TEST_CASE("Progress is printed as plain lines when stderr is not a terminal", "[cli]") {
    TempDir dir;
    std::string out = dir.file("img.pfm");
    SECTION("without --quiet") {
        // A plain line every 0.05 s (RAYPROC_PROGRESS_INTERVAL; 5 s by default) during a render
        // of about a second (15 s under AddressSanitizer): periodic lines, then the final one.
        ::setenv("RAYPROC_PROGRESS_INTERVAL", "0.05", 1);
        RunResult r =
            runRayproc({"render", scenePath("cornell-box"), "--mode", "raytrace", "--width", "128",
                        "--height", "128", "--spp", "64", "--threads", "2", "-o", out},
                       dir, 600);
        ::unsetenv("RAYPROC_PROGRESS_INTERVAL");
        INFO(r.err);
        REQUIRE(r.status == 0);
        CHECK_FALSE(contains(r.err, "\r")); // no bar redrawing into a file
        std::size_t n = progressLines(r.err, "raytrace");
        CHECK(n >= 2); // a periodic line, then the final one
        CHECK(std::regex_search(r.err, std::regex("(^|\n)raytrace: +[0-9]?[0-9]\\.[0-9]% ")));
        std::vector<std::string> ls = lines(r.err);
        REQUIRE_FALSE(ls.empty());
        CHECK(std::regex_match(ls.back(), std::regex("^raytrace: 100\\.0% .*")));
        // The render log line names the settings, so the image is reproducible from it.
        CHECK(contains(r.err, "mode=raytrace spp=64"));
        CHECK(contains(r.err, "seed=1"));
    }
    SECTION("preview labels its lines") {
        RunResult r = runRayproc({"render", scenePath("cornell-box"), "--mode", "preview",
                                  "--width", "32", "--height", "32", "-o", out},
                                 dir);
        INFO(r.err);
        REQUIRE(r.status == 0);
        CHECK(progressLines(r.err, "preview") >= 1);
    }
    SECTION("with --quiet nothing but errors") {
        RunResult r = runRayproc({"render", scenePath("cornell-box"), "--width", "64", "--height",
                                  "64", "--spp", "4", "--quiet", "-o", out},
                                 dir);
        CHECK(r.status == 0);
        CHECK(r.err.empty());
        CHECK(r.out == out + "\n");
        RunResult bad = runRayproc(
            {"render", scenePath("cornell-box"), "--quiet", "--mode", "nope", "-o", out}, dir);
        CHECK(bad.status != 0);
        CHECK_FALSE(bad.err.empty());
    }
}

// SIGTERM (batch schedulers, kill) and SIGHUP (a closed terminal) keep the work like Ctrl-C;
// the status is the shell's 128 + the signal's number.
TEST_CASE("SIGINT, SIGTERM and SIGHUP stop a render, write the partial image, exit 128 + signal",
          "[cli]") {
    int sig = GENERATE(SIGINT, SIGTERM, SIGHUP);
    INFO("signal " << sig);
    TempDir dir;
    std::string out = dir.file("partial.pfm");
    Child child({"render", scenePath("cornell-box"), "--mode", "raytrace", "--spp", "100000",
                 "--width", "128", "--height", "128", "--threads", "2", "-o", out},
                dir.file("stdout.txt"), dir.file("stderr.txt"));
    REQUIRE(child.started());
    REQUIRE(child.waitForErr("mode=raytrace", 30.0));
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    child.signal(sig);
    bool finished = child.wait(20.0); // kills the child on timeout
    INFO(child.err());
    REQUIRE(finished);
    CHECK(child.status() == 128 + sig);
    CHECK(contains(child.err(), "interrupted"));
    // The last progress line says where the render stopped, not 100%.
    std::vector<std::string> ls = lines(child.err());
    std::size_t n = progressLines(child.err(), "raytrace");
    CHECK(n >= 1);
    for (const std::string& l : ls)
        if (std::regex_match(l, std::regex("^raytrace: .*"))) CHECK_FALSE(contains(l, "100.0%"));

    REQUIRE(std::filesystem::exists(out));
    Image img = readImage(out);
    CHECK(img.width == 128);
    CHECK(img.height == 128);
    CHECK(allFinite(img));
    CHECK(meanValue(img) > 0.01);
    // No temporary file left behind by the atomic write.
    std::size_t files = 0;
    for (auto& e : std::filesystem::directory_iterator(dir.path))
        files += e.path().filename().string().rfind("partial", 0) == 0;
    CHECK(files == 1);
}

// Interrupted before any pixel had a sample, a render has nothing to write: the old image stays
// (it used to be replaced by a black one, "wrote the partial image (1024 pixels had no sample)").
TEST_CASE("Ctrl-C during gi's photon pass stops it before its end, says where and writes nothing",
          "[cli]") {
    TempDir dir;
    std::string out = dir.file("partial.pfm");
    Image old(32, 32);
    std::fill(old.pixels.begin(), old.pixels.end(), 0.5f);
    writeImage(out, old);
    const std::string before = readText(out);
    // 20M photons take tens of seconds; the interrupt arrives while they are traced.
    Child child({"render", scenePath("cornell-box"), "--mode", "gi", "--photons", "20000000",
                 "--spp", "1", "--width", "32", "--height", "32", "--threads", "2", "-o", out},
                dir.file("stdout.txt"), dir.file("stderr.txt"));
    REQUIRE(child.started());
    // The settings line comes right before the photon pass.
    REQUIRE(child.waitForErr("mode=gi", 30.0));
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    child.signal(SIGINT);
    bool finished = child.wait(60.0); // a bound on a hang, not a speed claim
    INFO(child.err());
    REQUIRE(finished);
    CHECK(child.status() == 128 + SIGINT);
    // The photon pass reported its progress, and where it stopped: before its end (it used to
    // run to its end, about 25 s here, before the interrupt was seen).
    CHECK(progressLines(child.err(), "gi photons") >= 1);
    for (const std::string& l : lines(child.err()))
        if (std::regex_match(l, std::regex("^gi photons: .*"))) CHECK_FALSE(contains(l, "100.0%"));
    CHECK(contains(child.err(), "interrupted before any pixel had a sample: nothing was written"));
    CHECK_FALSE(contains(child.err(), "wrote the partial image"));
    CHECK(readText(out) == before);
    CHECK(child.out().empty()); // stdout names a written image only
}

TEST_CASE("rayproc info --json gives the exact figures of the Cornell box", "[cli]") {
    TempDir dir;
    RunResult r = runRayproc({"info", scenePath("cornell-box"), "--json"}, dir);
    INFO(r.err);
    REQUIRE(r.status == 0);
    nlohmann::json j = nlohmann::json::parse(r.out);
    CHECK(j["geometry"]["triangles_unique"].get<int>() == 36);
    CHECK(j["geometry"]["triangles_placed"].get<int>() == 36);
    CHECK(j["geometry"]["spheres"].get<int>() == 0);
    CHECK(j["geometry"]["disks"].get<int>() == 0);
    CHECK(j["lights"]["area"].get<int>() == 1);
    for (const char* kind : {"point", "spot", "directional", "environment"}) {
        INFO("light kind " << kind);
        CHECK(j["lights"][kind].get<int>() == 0);
    }

    // Materials by type, as the scene file declares them.
    nlohmann::json file = nlohmann::json::parse(readText(scenePath("cornell-box")));
    std::map<std::string, int> byType{
        {"diffuse", 0}, {"mirror", 0}, {"dielectric", 0}, {"glossy", 0}};
    for (auto& [name, m] : file["materials"].items()) ++byType[m["type"].get<std::string>()];
    CHECK(byType["diffuse"] == 8);
    for (auto& [type, count] : byType) {
        INFO("material type " << type);
        CHECK(j["materials"][type].get<int>() == count);
    }

    const auto& lo = j["bounds"]["min"];
    const auto& hi = j["bounds"]["max"];
    CHECK(lo[0].get<double>() == Approx(-1).margin(1e-6));
    CHECK(lo[1].get<double>() == Approx(0).margin(1e-6));
    CHECK(lo[2].get<double>() == Approx(-1).margin(1e-6));
    CHECK(hi[0].get<double>() == Approx(1).margin(1e-6));
    CHECK(hi[1].get<double>() == Approx(2).margin(1e-6));
    CHECK(hi[2].get<double>() == Approx(1).margin(1e-6));
}

TEST_CASE("render --coat-model sets how every coateddiffuse is evaluated", "[cli]") {
    TempDir dir;
    // The Cornell box with its tall box an orange coated plastic (no medium: auto is the
    // closed form).
    std::string scene = readText((sourceDir() / "scenes" / "cornell-box.json").string());
    const std::string tall = R"("TallBox":   {"type": "diffuse", "color": [0.725, 0.71, 0.68]})";
    REQUIRE(scene.find(tall) != std::string::npos);
    scene.replace(scene.find(tall), tall.size(),
                  R"("TallBox": {"type": "coateddiffuse", "color": [1, 0.38, 0.013], "roughness": 0.1})");
    writeText(dir.file("coated.json"), scene);
    auto render = [&](const std::string& model) {
        std::vector<std::string> args = {"render", dir.file("coated.json"), "--mode", "path",
                                         "--spp", "4", "--width", "32", "--height", "32",
                                         "--threads", "2", "-q", "-o",
                                         dir.file("img-" + model + ".pfm")};
        if (!model.empty()) args.insert(args.end(), {"--coat-model", model});
        RunResult r = runRayproc(args, dir);
        INFO(r.err);
        REQUIRE(r.status == 0);
        return readText(dir.file("img-" + model + ".pfm"));
    };
    const std::string own = render(""), automatic = render("auto");
    const std::string analytic = render("analytic"), walk = render("random-walk");
    CHECK(automatic == own);
    CHECK(analytic == own);
    CHECK(walk != own);
    RunResult bad = runRayproc({"render", dir.file("coated.json"), "--coat-model", "walk", "-o",
                                dir.file("bad.pfm")},
                               dir);
    CHECK(bad.status != 0);
    CHECK(bad.err.find("random-walk") != std::string::npos);
    CHECK(!std::filesystem::exists(dir.file("bad.pfm")));
}

TEST_CASE("A sampling switch the mode does not read is warned of and changes nothing", "[cli]") {
    TempDir dir;
    const std::string out = dir.file("out.pfm");
    auto render = [&](const std::string& mode, const std::string& option) {
        std::vector<std::string> args = {"render", scenePath("cornell-box"), "--mode", mode,
                                         "--width", "16", "--height", "12", "--spp", "2",
                                         "-o", out};
        if (!option.empty()) args.push_back(option);
        return runRayproc(args, dir);
    };
    RunResult path = render("path", "--no-glossy-mis");
    INFO(path.err);
    CHECK(path.status == 0);
    CHECK(contains(path.err, "warning: --no-glossy-mis changes nothing in path mode (raytrace, gi "
                             "read it)"));
    RunResult raytrace = render("raytrace", "--no-glossy-mis");
    CHECK(raytrace.status == 0);
    CHECK_FALSE(contains(raytrace.err, "changes nothing"));
    RunResult gi = render("gi", "--no-sky-compensation");
    CHECK(contains(gi.err, "warning: --no-sky-compensation changes nothing in gi mode (path read "
                           "it)"));
}

