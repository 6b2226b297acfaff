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
    if (mode == "gi") {
        o << " gather=" << gi.gatherRays << " ic=" << gi.icAccuracy << " photons=" << gi.photons;
        if (gi.causticPhotons != gi.photons) o << " caustic-photons=" << gi.causticPhotons;
        if (!gi.irradianceCache) o << " no-irradiance-cache";
        if (gi.icRefineRays != GiSettings{}.icRefineRays) o << " ic-refine-rays=" << gi.icRefineRays;
        if (gi.icCorrectionRays != GiSettings{}.icCorrectionRays)
            o << " ic-correction-rays=" << gi.icCorrectionRays;
        if (!gi.icSmoothing) o << " no-ic-smoothing";
        if (!gi.precomputedIrradiance) o << " no-precomputed-irradiance";
        if (!gi.lazyIrradiance) o << " no-lazy-irradiance";
        if (!gi.gatherDirect) o << " no-gather-direct";
        if (gi.mapCorrection) o << " map-correction";
        if (gi.photonRounds != kMaxPhotonRounds) o << " photon-rounds=" << gi.photonRounds;
        if (!gi.caustics) o << " no-caustics";
        if (!gi.progressiveCaustics) o << " no-progressive-caustics";
        else if (!gi.causticPixelRadius) o << " no-caustic-pixel-radius";
        if (!gi.roughCaustics) o << " no-rough-caustics";
    }
    if ((mode == "path" && !path.roulette) || (mode == "raytrace" && !raytrace.roulette) ||
        (mode == "gi" && !gi.roulette))
        o << " no-russian-roulette";
    if (!engine.stratification) o << " no-stratification";
    if (!engine.skyCompensation && mode == "path") o << " no-sky-compensation";
    if (!engine.glossyMis && (mode == "gi" || mode == "raytrace")) o << " no-glossy-mis";
    if (!engine.lightChoice && (mode == "gi" || mode == "raytrace")) o << " no-light-choice";
    if (!engine.diffuseMis && (mode == "gi" || mode == "raytrace")) o << " no-diffuse-mis";
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
