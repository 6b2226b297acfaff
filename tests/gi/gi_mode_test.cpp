// gi mode as a whole: its debug views show what they claim, the error log's clock counts the
// photon pass, precomputation and cache prepass, and --time-limit stops after the first pass
// past the budget.
#include "../analytic/analytic.h"
#include "image/metrics.h"

#include <fstream>

using namespace rayproc;
using namespace rayproc::test;

namespace {

bool isMarker(const Image& img, int x, int y) {
    const float* p = img.at(x, y);
    return p[0] == kIcRecordMarker.x && p[1] == kIcRecordMarker.y && p[2] == kIcRecordMarker.z;
}

} // namespace

TEST_CASE("gi debug view ic-records: the render at a quarter, one marker per record pixel", "[gi]") {
    auto scene = loadSceneAt("cornell-box", 48, 48);
    EmbreeScene accel(*scene);
    RenderResult normal = renderGiMode(*scene, accel, 1);
    RenderResult view = renderGiMode(*scene, accel, 1, 1, GiDebugView::IcRecords);
    const double records = extraStat(view, "gi/cache_records");
    REQUIRE(records > 20);
    std::size_t marked = 0, dimmed = 0, other = 0;
    for (int y = 0; y < view.image.height; ++y)
        for (int x = 0; x < view.image.width; ++x) {
            if (isMarker(view.image, x, y)) {
                ++marked;
                continue;
            }
            const float *v = view.image.at(x, y), *n = normal.image.at(x, y);
            // Multiplying by 0.25 is exact in floating point: the rest of the image is
            // bit for bit the normal render (same seed, same cache) dimmed.
            if (v[0] == 0.25f * n[0] && v[1] == 0.25f * n[1] && v[2] == 0.25f * n[2]) ++dimmed;
            else ++other;
        }
    INFO(records << " records, " << marked << " marked pixels, " << dimmed << " dimmed, " << other
                 << " other");
    CHECK(other == 0);
    CHECK(double(marked) == extraStat(view, "gi/ic_marked_pixels"));
    // Every record lies where a camera ray met a diffuse surface, so it projects into the
    // image; several may share a pixel (the fine levels of the prepass are at full resolution).
    CHECK(double(marked) <= records);
    CHECK(double(marked) >= 0.5 * records);
    CHECK(!isMarker(normal.image, 0, 0));
}

TEST_CASE("gi debug views photons, caustics and indirect differ from the render as they claim",
          "[gi]") {
    auto scene = loadSceneAt("cornell-spheres", 32, 32);
    EmbreeScene accel(*scene);
    Image normal = renderGiMode(*scene, accel, 1).image;
    Image caustics = renderGiMode(*scene, accel, 1, 1, GiDebugView::Caustics).image;
    Image indirect = renderGiMode(*scene, accel, 1, 1, GiDebugView::Indirect).image;
    Image photons = renderGiMode(*scene, accel, 1, 1, GiDebugView::Photons).image;
    // No direct light and no emission in any view: the render's brightest pixel (the light)
    // is dark in the views.
    int lx = 0, ly = 0;
    for (int y = 0; y < normal.height; ++y)
        for (int x = 0; x < normal.width; ++x)
            if (normal.at(x, y)[0] > normal.at(lx, ly)[0]) lx = x, ly = y;
    double lightPixel = normal.at(lx, ly)[0];
    INFO("brightest pixel (" << lx << ", " << ly << "): " << lightPixel);
    REQUIRE(lightPixel > 1.0);
    CHECK(caustics.at(lx, ly)[0] < 0.1 * lightPixel);
    CHECK(photons.at(lx, ly)[0] < 0.1 * lightPixel);
    CHECK(indirect.at(lx, ly)[0] < 0.1 * lightPixel);
    // Caustics only: not black here (the spheres focus and reflect light onto the walls and
    // the floor), and all black in the Cornell box, which has no specular surface.
    CHECK(meanValue(caustics) > 0);
    {
        auto box = loadSceneAt("cornell-box", 16, 16);
        EmbreeScene boxAccel(*box);
        Image boxCaustics = renderGiMode(*box, boxAccel, 1, 1, GiDebugView::Caustics).image;
        CHECK(meanValue(boxCaustics) == 0);
    }
    // Indirect and caustic light are parts of the render: each mean is below the render's.
    CHECK(meanValue(indirect) > 0.05 * meanValue(normal));
    CHECK(meanValue(indirect) < meanValue(normal));
    CHECK(meanValue(caustics) < meanValue(indirect));
    // The photons view is the maps' estimate of all reflected light: of the order of the
    // render's diffuse light (no emission), unlike the indirect view.
    CHECK(meanValue(photons) > meanValue(indirect));
}

TEST_CASE("The gi error log counts the pre-passes and --time-limit stops after the first pass "
          "past the budget",
          "[gi]") {
    auto scene = loadSceneAt("cornell-box", 32, 32);
    EmbreeScene accel(*scene);
    TempDir dir;
    Image reference = renderGiMode(*scene, accel, 2, 5).image;
    const std::string log = (dir.path / "gi.csv").string();

    EngineSettings engine;
    engine.threads = 2;
    engine.seed = 1;
    engine.quiet = true;
    RenderControl control;
    control.reference = &reference;
    control.errorLogPath = log;
    GiSettings s = giSettings(*scene, ModeOverrides{4, 0, 0});
    RenderResult r = renderGi(*scene, accel, s, engine, control);
    const double prePasses = extraStat(r, "gi/photon_seconds") + extraStat(r, "gi/precompute_seconds") +
                             extraStat(r, "gi/cache_seconds");
    std::ifstream in(log);
    std::string header, first;
    std::getline(in, header);
    std::getline(in, first);
    REQUIRE(header == "spp,seconds,relmse,rmse,relmse_estimate");
    double firstSeconds = std::stod(first.substr(first.find(',') + 1));
    INFO("first pass logged at " << firstSeconds << " s; pre-passes " << prePasses << " s; wall "
                                 << r.stats.wallSeconds);
    CHECK(firstSeconds >= prePasses);
    CHECK(r.stats.wallSeconds >= firstSeconds);
    CHECK(r.samplesDone == 4);
    CHECK(!r.timeLimitReached);

    // A budget shorter than the pre-passes: exactly one pass (1 spp) is rendered.
    EngineSettings limited;
    limited.threads = 2;
    limited.quiet = true;
    RenderControl budget;
    budget.timeLimitSeconds = 1e-6;
    GiSettings many = giSettings(*scene, ModeOverrides{1000, 0, 0});
    RenderResult cut = renderGi(*scene, accel, many, limited, budget);
    CHECK(cut.timeLimitReached);
    CHECK(cut.samplesDone == 1);
    CHECK(cut.passesDone == 1);
    CHECK(allFinite(cut.image));
    CHECK(meanValue(cut.image) > 0.01);

    // Path mode under a budget: at least one pass, fewer samples than asked.
    EngineSettings pathEngine;
    pathEngine.threads = 2;
    pathEngine.quiet = true;
    RenderControl pathBudget;
    pathBudget.timeLimitSeconds = 0.05;
    RenderResult p = renderPath(*scene, accel, pathSettings(scene->render, ModeOverrides{100000, 0, 0}),
                                pathEngine, pathBudget);
    INFO("path: " << p.samplesDone << " spp in " << p.stats.wallSeconds << " s");
    CHECK(p.timeLimitReached);
    CHECK(p.samplesDone >= 1);
    CHECK(p.samplesDone < 100000);
    CHECK(p.stats.wallSeconds >= 0.05);
}

TEST_CASE("The error-log row is handed to RenderControl::onPassError, with or without the log "
          "file",
          "[gi][bench]") {
    auto scene = loadSceneAt("cornell-box", 16, 16);
    EmbreeScene accel(*scene);
    TempDir dir;
    Image reference = renderGiMode(*scene, accel, 2, 5).image;
    for (bool withFile : {true, false}) {
        const std::string log = (dir.path / "gi.csv").string();
        std::vector<RenderControl::PassError> rows;
        EngineSettings engine;
        engine.threads = 2;
        engine.quiet = true;
        RenderControl control;
        control.reference = &reference;
        if (withFile) control.errorLogPath = log;
        control.onPassError = [&](const RenderControl::PassError& e) { rows.push_back(e); };
        GiSettings s = giSettings(*scene, ModeOverrides{3, 0, 0});
        RenderResult r = renderGi(*scene, accel, s, engine, control);
        INFO("with the log file: " << withFile);
        REQUIRE(rows.size() == std::size_t(r.passesDone));
        REQUIRE(rows.size() >= 2);
        for (std::size_t i = 0; i < rows.size(); ++i) {
            CHECK(rows[i].spp == int(i) + 1); // passes of 1 spp (3 spp asked)
            CHECK(rows[i].relmse > 0);
            CHECK(rows[i].rays > 0);
            if (i > 0) {
                CHECK(rows[i].seconds >= rows[i - 1].seconds);
                CHECK(rows[i].rays > rows[i - 1].rays);
            }
        }
        // The last pass's error is the finished image's.
        CHECK(rows.back().relmse == Approx(compareImages(r.image, reference).relmse).epsilon(1e-9));
        if (!withFile) continue;
        std::ifstream in(log);
        std::string line;
        std::getline(in, line);
        for (const RenderControl::PassError& e : rows) {
            REQUIRE(std::getline(in, line));
            CHECK(std::stoi(line) == e.spp);
            std::size_t c = line.find(',');
            c = line.find(',', c + 1); // past seconds
            CHECK(std::stod(line.substr(c + 1)) == Approx(e.relmse).epsilon(1e-7));
        }
        CHECK(!std::getline(in, line));
    }
}

TEST_CASE("Lazy precomputed irradiance renders the eager image bit for bit with fewer estimates",
          "[gi]") {
    // The image must not change; how many estimates are saved is the scene's business (in the
    // classroom of docs/photon-map.md 7% of them are made; here most photons are in view).
    auto scene = loadSceneAt("cornell-box", 24, 24);
    EmbreeScene accel(*scene);
    EngineSettings engine;
    engine.threads = 2;
    engine.quiet = true;
    GiSettings s = giSettings(*scene, ModeOverrides{2, 0, 0});
    s.photons = 20000;
    RenderResult lazy = renderGi(*scene, accel, s, engine);
    s.lazyIrradiance = false;
    RenderResult eager = renderGi(*scene, accel, s, engine);
    REQUIRE(lazy.image.pixels.size() == eager.image.pixels.size());
    CHECK(std::memcmp(lazy.image.pixels.data(), eager.image.pixels.data(),
                      lazy.image.pixels.size() * sizeof(lazy.image.pixels[0])) == 0);
    const double made = extraStat(lazy, "gi/precomputed_estimates");
    const double all = extraStat(lazy, "gi/precomputed_photons");
    INFO(made << " of " << all << " estimates made");
    CHECK(all > 1000);
    CHECK(made > 0);
    CHECK(made <= all);
    CHECK(extraStat(eager, "gi/precomputed_estimates") == all);
}
