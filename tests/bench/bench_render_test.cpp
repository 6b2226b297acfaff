// bench's settings column (RenderConfig::settingsString) takes a mode's settings in the mode's
// own words (ModeEntry::settingWords): an option set through the parser the mode registered
// reaches it without bench naming the option.
#include "test_util.h"

#include "bench/bench_render.h"
#include "modes/mode_options.h"

#include <set>

using namespace rayproc;
using namespace rayproc::bench;

namespace {

// `c` with `words` given to gi's own options, as `rayproc render` takes them.
void applyGiOptions(RenderConfig& c, const std::string& words) {
    std::unique_ptr<ModeOptions> options = findMode("gi")->options();
    CLI::App app;
    options->add(app);
    app.parse(words, false);
    options->apply(c);
}

} // namespace

TEST_CASE("bench's settings column names gi's options that bench itself never names", "[bench]") {
    auto scene = test::loadSceneAt("cornell-box", 8, 8);
    RenderConfig c = RenderConfig::forMode(*scene, "gi", 4);
    const std::string defaults = c.settingsString();
    CHECK(defaults.rfind("spp=4 gather=64 ic=0.25 photons=200000", 0) == 0);
    applyGiOptions(c, "--global-k 32 --no-ic-gradients --caustic-alpha 0.5");
    CHECK(c.settingsString() == defaults + " global-k=32 caustic-alpha=0.5 no-ic-gradients");
}

TEST_CASE("every one of gi's options, off its default, changes bench's settings column",
          "[bench]") {
    auto scene = test::loadSceneAt("cornell-box", 8, 8);
    const RenderConfig base = RenderConfig::forMode(*scene, "gi", 4);
    const std::vector<std::string> given = {
        "--photons 1000", "--photon-rounds 2", "--global-k 32", "--caustic-photons 500",
        "--gather-rays 16", "--film-gather-rays 3", "--ic-accuracy 0.5", "--ic-refine-rays 0",
        "--ic-correction-rays 7", "--no-irradiance-cache", "--no-caustics",
        "--no-progressive-caustics", "--no-caustic-pixel-radius", "--no-rough-caustics",
        "--caustic-alpha 0.5", "--caustic-radius 0.02", "--no-precomputed-irradiance",
        "--no-lazy-irradiance", "--map-correction", "--no-gather-direct", "--no-ic-smoothing",
        "--no-ic-gradients"};
    std::set<std::string> lines{base.settingsString()};
    for (const std::string& words : given) {
        INFO(words);
        RenderConfig c = base;
        applyGiOptions(c, words);
        CHECK(lines.insert(c.settingsString()).second); // a line of its own
    }
    // Every option gi registers is in the list above: a new one must say its word too.
    std::unique_ptr<ModeOptions> options = findMode("gi")->options();
    CLI::App app;
    options->add(app);
    std::size_t registered = 0;
    for (const CLI::Option* o : app.get_options())
        if (!o->check_lname("help")) ++registered;
    CHECK(registered == given.size());
}
