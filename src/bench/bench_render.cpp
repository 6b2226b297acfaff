#include "bench/bench_render.h"

#include "bench/suite.h"
#include "core/error.h"

#include <chrono>
#include <sstream>

namespace rayproc::bench {

RenderConfig RenderConfig::forMode(const Scene& scene, const std::string& mode, int spp) {
    RenderConfig c;
    c.mode = mode;
    static_cast<ModeSettings&>(c) = ModeSettings::forScene(scene, ModeOverrides{});
    c.engine.quiet = true;
    c.setSpp(spp);
    return c;
}

int RenderConfig::spp() const {
    const ModeEntry* entry = findMode(mode);
    return entry ? entry->spp(*this) : path.spp;
}

void applyGiVariant(RenderConfig& c, const GiVariant& variant) {
    c.gi.gatherRays = variant.gatherRays;
    c.gi.icAccuracy = variant.icAccuracy;
    c.gi.photons = variant.photons;
}

std::string RenderConfig::settingsString() const {
    std::ostringstream o;
    o << "spp=" << spp();
    // The mode's own settings in its own words (ModeEntry::settingWords), then the engine's
    // switches that the mode reads.
    const ModeEntry* entry = findMode(mode);
    const std::string words = entry ? entry->settingWords(*this) : std::string();
    if (!words.empty()) o << " " << words;
    std::size_t count = 0;
    const EngineSwitchName* names = engineSwitchNames(count);
    for (std::size_t i = 0; i < count && entry; ++i)
        if ((entry->engineSwitches & names[i].flag) && !(engine.*names[i].on))
            o << " no-" << names[i].word;
    if (engine.packetWidth != 16) o << " packets=" << engine.packetWidth;
    if (engine.seed != 1) o << " seed=" << engine.seed;
    if (engine.spectral) o << " spectral";
    return o.str();
}

TimedRender renderTimed(const Scene& scene, const EmbreeScene& accel, const RenderConfig& c) {
    using Clock = std::chrono::steady_clock;
    Clock::time_point start = Clock::now();
    const ModeEntry* entry = findMode(c.mode);
    if (!entry) throw InputError("unknown mode '" + c.mode + "'");
    RenderResult r = entry->render(scene, accel, c, c.engine, c.control);
    TimedRender t;
    t.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    t.image = std::move(r.image);
    t.rays = r.stats.totals.raysTraced;
    t.cancelled = r.cancelled;
    return t;
}

} // namespace rayproc::bench
