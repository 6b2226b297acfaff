// The modes' own command-line options (modes/mode_options.h) and the options several modes share
// (ModeOverrides): parsed as the render command parses them, each reaches the setting it names,
// and what the command line does not give keeps the scene's or the default.
#include "test_util.h"

#include "modes/mode_options.h"
#include "modes/mode_registry.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

// gi's options declared in a group of `app`, as the render command does.
std::unique_ptr<ModeOptions> giOptionsOn(CLI::App& app) {
    const ModeEntry* gi = findMode("gi");
    REQUIRE(gi != nullptr);
    REQUIRE(gi->options != nullptr);
    std::unique_ptr<ModeOptions> options = gi->options();
    options->add(*app.add_option_group("gi options"));
    return options;
}

} // namespace

TEST_CASE("Every one of gi's own options reaches the GiSettings field it names", "[modes]") {
    std::unique_ptr<Scene> scene = loadScene(scenePath("cornell-box"));
    CLI::App app;
    std::unique_ptr<ModeOptions> options = giOptionsOn(app);
    app.parse("--photons 1000 --photon-rounds 2 --global-k 32 --caustic-photons 500 "
              "--gather-rays 16 --film-gather-rays 3 --ic-accuracy 0.5 --ic-refine-rays 0 "
              "--ic-correction-rays 7 --no-irradiance-cache --no-caustics "
              "--no-progressive-caustics --no-caustic-pixel-radius --no-rough-caustics "
              "--caustic-alpha 0.5 --caustic-radius 0.02 --no-precomputed-irradiance "
              "--no-lazy-irradiance --map-correction --no-gather-direct --no-ic-smoothing "
              "--no-ic-gradients",
              false);
    ModeSettings m = ModeSettings::forScene(*scene, ModeOverrides{});
    const ModeSettings before = m;
    options->apply(m);
    const GiSettings& s = m.gi;
    CHECK(s.photons == 1000);
    CHECK(s.photonRounds == 2);
    CHECK(s.globalK == 32);
    CHECK(s.causticPhotons == 500);
    CHECK(s.gatherRays == 16);
    CHECK(s.filmGatherRays == 3);
    CHECK(s.icAccuracy == 0.5f);
    CHECK(s.icRefineRays == 0);
    CHECK(s.icCorrectionRays == 7);
    CHECK_FALSE(s.irradianceCache);
    CHECK_FALSE(s.caustics);
    CHECK_FALSE(s.progressiveCaustics);
    CHECK_FALSE(s.causticPixelRadius);
    CHECK_FALSE(s.roughCaustics);
    CHECK(s.causticAlpha == 0.5f);
    CHECK(s.causticRadius == 0.02f);
    CHECK_FALSE(s.precomputedIrradiance);
    CHECK_FALSE(s.lazyIrradiance);
    CHECK(s.mapCorrection);
    CHECK_FALSE(s.gatherDirect);
    CHECK_FALSE(s.icSmoothing);
    CHECK_FALSE(s.icGradients);
    // gi's options are gi's alone: the other modes' settings are as the scene gave them.
    CHECK(m.preview.toString() == before.preview.toString());
    CHECK(m.raytrace.toString() == before.raytrace.toString());
    CHECK(m.path.toString() == before.path.toString());
}

TEST_CASE("gi's options not given keep the scene's and the default settings", "[modes]") {
    // A pbrt file's sppm block sets the caustic photons and radius, which the options override
    // only when given.
    std::unique_ptr<Scene> scene = loadScene(scenePath("cornell-box"));
    scene->render.photonsPerPass = 12345;
    scene->render.photonRadius = 0.125f;
    CLI::App app;
    std::unique_ptr<ModeOptions> options = giOptionsOn(app);
    app.parse("", false);
    ModeSettings m = ModeSettings::forScene(*scene, ModeOverrides{});
    const std::string expected = m.gi.toString();
    options->apply(m);
    CHECK(m.gi.toString() == expected);
    CHECK(m.gi.causticPhotons == 12345);
    CHECK(m.gi.causticRadius == 0.125f);
    CHECK(m.gi.photons == GiSettings{}.photons);
}

TEST_CASE("The options several modes share reach every mode that reads them", "[modes]") {
    std::unique_ptr<Scene> scene = loadScene(scenePath("cornell-box"));
    ModeOverrides shared;
    shared.roulette = false;
    shared.debugView = "ic-records";
    ModeSettings m = ModeSettings::forScene(*scene, shared);
    CHECK_FALSE(m.raytrace.roulette);
    CHECK_FALSE(m.path.roulette);
    CHECK_FALSE(m.gi.roulette);
    CHECK(m.gi.debugView == GiDebugView::IcRecords);

    // Path's noise view is the engine's: gi renders as without a view.
    shared.debugView = "noise";
    CHECK(ModeSettings::forScene(*scene, shared).gi.debugView == GiDebugView::None);
    const ModeSettings defaults = ModeSettings::forScene(*scene, ModeOverrides{});
    CHECK(defaults.raytrace.roulette);
    CHECK(defaults.path.roulette);
    CHECK(defaults.gi.roulette);
    CHECK(defaults.gi.debugView == GiDebugView::None);
}

// The render command warns that a sampling switch a mode does not read changes nothing
// (ModeEntry::engineSwitches): it must be so (a scene of area lights, glossy and diffuse
// surfaces, glass and a sky).
TEST_CASE("An engine switch a mode does not read changes none of its pixels", "[modes]") {
    std::unique_ptr<Scene> scene = loadSceneAt("materials", 16, 12);
    EmbreeScene accel(*scene);
    std::size_t count = 0;
    const EngineSwitchName* names = engineSwitchNames(count);
    for (const ModeEntry& mode : modeRegistry()) {
        ModeSettings m = ModeSettings::forScene(*scene, ModeOverrides{});
        m.setSpp(2);
        EngineSettings engine;
        engine.threads = 2;
        engine.quiet = true;
        const Image all = mode.render(*scene, accel, m, engine, RenderControl{}).image;
        for (std::size_t i = 0; i < count; ++i) {
            if (mode.engineSwitches & names[i].flag) continue;
            INFO(mode.name << " without --no-" << names[i].word);
            EngineSettings off = engine;
            off.*names[i].on = false;
            CHECK(sameBits(mode.render(*scene, accel, m, off, RenderControl{}).image, all));
        }
    }
}
