// gi's own command-line options (render --help's "gi options"): the photon maps' counts, the
// final gather's and the irradiance cache's, and the switches of each of gi's techniques. Every
// option sets a GiSettings field (gi/gi_context.h) that no other mode reads; the options that
// gi shares with other modes (--spp, --max-depth, --light-samples, --no-russian-roulette,
// --debug-view) reach GiSettings through ModeOverrides (giSettings() in modes/gi.cpp).
#include "core/option_checks.h"
#include "modes/mode_options.h"
#include "modes/mode_registry.h"

#include <sstream>

namespace rayproc {

namespace {

class GiOptions final : public ModeOptions {
public:
    void add(CLI::App& group) override {
        addCounts(group);
        addSwitches(group);
        addCacheSwitches(group);
    }
    void apply(ModeSettings& settings) const override;

private:
    // -1 or 0 (as each option's range allows): not given, the setting keeps its value.
    int m_photons = -1, m_causticPhotons = -1, m_gatherRays = 0, m_photonRounds = 0;
    int m_globalK = 0, m_filmGatherRays = 0, m_icRefineRays = -1, m_icCorrectionRays = -1;
    float m_icAccuracy = 0, m_causticAlpha = 0, m_causticRadius = 0;
    bool m_noCache = false, m_noCaustics = false, m_noPrecomputed = false;
    bool m_noIcGradients = false, m_noIcSmoothing = false;
    bool m_noProgressiveCaustics = false, m_noCausticPixelRadius = false;
    bool m_noGatherDirect = false, m_noLazyIrradiance = false, m_mapCorrection = false;
    bool m_noRoughCaustics = false;

    void addCounts(CLI::App& group);
    void addSwitches(CLI::App& group);
    void addCacheSwitches(CLI::App& group);
};

// The photon, gather and cache counts.
void GiOptions::addCounts(CLI::App& group) {
    group.add_option("--photons", m_photons,
                     "gi: photons emitted for the global map per round (default 200000); rounds "
                     "repeat until a quarter of this many of the photons the final gather reads "
                     "have landed in view (see --photon-rounds)")
        ->check(CLI::Range(0, 100000000));
    group.add_option("--photon-rounds", m_photonRounds,
                     "gi: at most this many rounds of --photons for the global map (default 8; "
                     "1 = exactly --photons). A room lit through its windows keeps few of the "
                     "photons aimed at it (the classroom: 4% in view)")
        ->check(CLI::Range(1, 64));
    group.add_option("--global-k", m_globalK,
                     "gi: photons per density estimate of the global map (default 64; Jensen's k). "
                     "Fewer: smaller discs, less of the darkening where a disc reaches past a "
                     "surface's edge, more noise; more: the reverse")
        ->check(CLI::Range(1, 1024));
    group.add_option("--caustic-photons", m_causticPhotons,
                     "gi: photons emitted for the caustic map, each pass's with progressive "
                     "caustics (default: one per pixel, at least 50000 and at most 1000000; only "
                     "light -> specular+ -> diffuse paths are stored)")
        ->check(CLI::Range(0, 100000000));
    group.add_option("--gather-rays", m_gatherRays,
                     "gi: stratified cosine-weighted rays per final gather of an irradiance-cache "
                     "record (default 64)")
        ->check(CLI::Range(1, 65536));
    group.add_option("--film-gather-rays", m_filmGatherRays,
                     "gi: rays of a final gather made for the image where a render pass finds no "
                     "usable cache record (or without the cache); default --gather-rays / --spp, "
                     "at least 1: about a record's rays per pixel over the render, one per pass "
                     "under --time-limit with a large --spp")
        ->check(CLI::Range(1, 65536));
    group.add_option("--ic-accuracy", m_icAccuracy,
                     "gi: Ward's accuracy a of the irradiance cache; smaller = more records "
                     "(default 0.25)")
        ->check(finiteFloat())
        ->check(CLI::Range(0.001, 10.0));
    group.add_option("--ic-refine-rays", m_icRefineRays,
                     "gi: gather rays every cache record adds before each render pass, so the "
                     "records' noise falls as passes accumulate instead of staying in the image "
                     "(default 1; 0: off)")
        ->check(CLI::Range(0, 65536));
    group.add_option("--ic-correction-rays", m_icCorrectionRays,
                     "gi: path-traced correction rays every cache record adds before each render "
                     "pass: the global photon map's bias leaves the records as passes accumulate "
                     "(a control variate: the records converge to the exact final gather's "
                     "irradiance, not the map's; default 4; 0: off, the records keep the map's "
                     "bias)")
        ->check(CLI::Range(0, 65536));
}

// The switches of the photon maps and the caustic estimate's radius.
void GiOptions::addSwitches(CLI::App& group) {
    group.add_flag("--no-irradiance-cache", m_noCache,
                   "gi: final gather at every diffuse hit instead of interpolating cached records");
    group.add_flag("--no-caustics", m_noCaustics, "gi: no caustic photon map");
    group.add_flag("--no-progressive-caustics", m_noProgressiveCaustics,
                   "gi: one caustic map for the whole render with k-nearest estimates, instead of "
                   "a new map of --caustic-photons every pass with a shrinking radius (progressive "
                   "photon mapping: caustics converge as passes accumulate)");
    group.add_flag("--no-caustic-pixel-radius", m_noCausticPixelRadius,
                   "gi: progressive caustics with one radius sequence for the whole image instead "
                   "of a radius per pixel shrunk by the photons the pixel receives (SPPM's "
                   "statistics; docs/photon-map.md)");
    group.add_flag("--no-rough-caustics", m_noRoughCaustics,
                   "gi: caustic photons end at rough glass and rough water instead of going on "
                   "through them as through smooth glass; the light through such surfaces then "
                   "reaches the image through final gathers and the global map (blurred, not "
                   "progressive; docs/caustics.md)");
    group.add_option("--caustic-alpha", m_causticAlpha,
                     "gi: progressive caustics' radius reduction alpha: each pass's squared radius "
                     "is the last one's times (i + alpha) / (i + 1) (default 0.667; smaller "
                     "shrinks faster: less bias, more noise)")
        ->check(finiteFloat())
        ->check(CLI::Range(0.01, 1.0));
    group.add_option("--caustic-radius", m_causticRadius,
                     "gi: the caustic estimate's largest radius, in scene units: progressive "
                     "caustics start from the first map's 64th-neighbour distance or this, "
                     "whichever is smaller (default: 2% of the diagonal of what the camera sees; "
                     "a pbrt file's sppm \"radius\" sets it)")
        ->check(finiteFloat())
        ->check(CLI::PositiveNumber);
    group.add_flag("--no-precomputed-irradiance", m_noPrecomputed,
                   "gi: gather rays estimate the global map's irradiance from scratch instead of "
                   "Christensen's precomputed values");
    group.add_flag("--no-lazy-irradiance", m_noLazyIrradiance,
                   "gi: precompute the irradiance at every fourth photon before rendering instead "
                   "of each the first time a lookup needs it (the same image; the lazy way skips "
                   "photons no lookup reaches)");
    group.add_flag("--map-correction", m_mapCorrection,
                   "gi: every pass, take the global photon map's estimate away again wherever it "
                   "went into the image and add a traced path in its place (one ray from each "
                   "first diffuse hit for its final gather): the map's bias fades as passes add "
                   "up and gi converges to path mode's image, at path tracing's noise (off by "
                   "default)");
    group.add_flag("--no-gather-direct", m_noGatherDirect,
                   "gi: where a final-gather ray lands on a diffuse surface, take the global map's "
                   "estimate of all the light there instead of sampling the sun (delta lights) "
                   "and the sky there with one shadow ray each and taking the rest from the map "
                   "(the map blurs sharp shadows and sunlit patches: biased, but no shadow rays)");
}

// The switches of the irradiance cache's interpolation and corrections.
void GiOptions::addCacheSwitches(CLI::App& group) {
    group.add_flag("--no-ic-smoothing", m_noIcSmoothing,
                   "gi: apply each cache record's own corrections (--ic-correction-rays) instead "
                   "of their average over its nearest records of the same facing, whose number "
                   "Stein's unbiased risk estimate chooses before each pass");
    group.add_flag("--no-ic-gradients", m_noIcGradients,
                   "gi: interpolate cached irradiance without Ward & Heckbert's rotational and "
                   "translational gradients");
}

void GiOptions::apply(ModeSettings& settings) const {
    GiSettings& s = settings.gi;
    if (m_photons >= 0) s.photons = m_photons;
    if (m_photonRounds > 0) s.photonRounds = m_photonRounds;
    if (m_globalK > 0) s.globalK = m_globalK;
    if (m_causticPhotons >= 0) s.causticPhotons = m_causticPhotons;
    if (m_gatherRays > 0) s.gatherRays = m_gatherRays;
    if (m_filmGatherRays > 0) s.filmGatherRays = m_filmGatherRays;
    if (m_icAccuracy > 0) s.icAccuracy = m_icAccuracy;
    if (m_icRefineRays >= 0) s.icRefineRays = m_icRefineRays;
    if (m_icCorrectionRays >= 0) s.icCorrectionRays = m_icCorrectionRays;
    s.irradianceCache = !m_noCache;
    s.caustics = !m_noCaustics;
    s.progressiveCaustics = !m_noProgressiveCaustics;
    s.causticPixelRadius = !m_noCausticPixelRadius;
    s.roughCaustics = !m_noRoughCaustics;
    if (m_causticAlpha > 0) s.causticAlpha = m_causticAlpha;
    if (m_causticRadius > 0) s.causticRadius = m_causticRadius;
    s.precomputedIrradiance = !m_noPrecomputed;
    s.lazyIrradiance = !m_noLazyIrradiance;
    s.gatherDirect = !m_noGatherDirect;
    s.mapCorrection = m_mapCorrection;
    s.icGradients = !m_noIcGradients;
    s.icSmoothing = !m_noIcSmoothing;
}

} // namespace

std::unique_ptr<ModeOptions> giOptions() { return std::make_unique<GiOptions>(); }

// The words follow the options above; one added there adds its word here. The counts bench
// sweeps come first and always; the caustic photons where they differ from the global map's
// (their default follows the image size).
std::string giSettingWords(const ModeSettings& settings) {
    const GiSettings& s = settings.gi;
    const GiSettings d;
    std::ostringstream o;
    o << "gather=" << s.gatherRays << " ic=" << s.icAccuracy << " photons=" << s.photons;
    if (s.causticPhotons != s.photons) o << " caustic-photons=" << s.causticPhotons;
    if (!s.irradianceCache) o << " no-irradiance-cache";
    if (s.icRefineRays != d.icRefineRays) o << " ic-refine-rays=" << s.icRefineRays;
    if (s.icCorrectionRays != d.icCorrectionRays) o << " ic-correction-rays=" << s.icCorrectionRays;
    if (!s.icSmoothing) o << " no-ic-smoothing";
    if (!s.precomputedIrradiance) o << " no-precomputed-irradiance";
    if (!s.lazyIrradiance) o << " no-lazy-irradiance";
    if (!s.gatherDirect) o << " no-gather-direct";
    if (s.mapCorrection) o << " map-correction";
    if (s.photonRounds != d.photonRounds) o << " photon-rounds=" << s.photonRounds;
    if (!s.caustics) o << " no-caustics";
    if (!s.progressiveCaustics) o << " no-progressive-caustics";
    else if (!s.causticPixelRadius) o << " no-caustic-pixel-radius";
    if (!s.roughCaustics) o << " no-rough-caustics";
    if (s.globalK != d.globalK) o << " global-k=" << s.globalK;
    if (s.filmGatherRays != d.filmGatherRays) o << " film-gather-rays=" << s.filmGatherRays;
    if (s.causticAlpha != d.causticAlpha) o << " caustic-alpha=" << s.causticAlpha;
    if (s.causticRadius != d.causticRadius) o << " caustic-radius=" << s.causticRadius;
    if (!s.icGradients) o << " no-ic-gradients";
    const std::string roulette = rouletteWord(s.roulette);
    if (!roulette.empty()) o << " " << roulette;
    return o.str();
}

} // namespace rayproc
