#include "gi/progressive_caustics.h"

#include "gi/photon_pass.h"
#include "kernels/random.h"

#include <cmath>

namespace rayproc {

namespace {
// The caustic photons' random stream of pass i: the single map's tag for the first pass.
std::uint64_t passTag(int pass) {
    return pass == 0 ? 2 : kernels::hashCombine(2, std::uint64_t(pass));
}
// Photons sampled for the first radius (their k-th neighbours searched once).
constexpr int kRadiusSamples = 1024;
} // namespace

ProgressiveCaustics::ProgressiveCaustics(const Scene& scene, const EmbreeScene& accel,
                                         const LightSet& lights, GiData& gi,
                                         const EngineSettings& engine, const Cluster& cluster,
                                         PhaseLog* phases, const FocusRegion& focus, Stats& stats)
    : m_scene(scene), m_accel(accel), m_lights(lights), m_gi(gi), m_engine(engine),
      m_cluster(cluster), m_phases(phases), m_focus(focus), m_stats(stats),
      m_radius(double(gi.settings.causticAlpha)) {
    const GiSettings& s = gi.settings;
    PhotonPassSpec spec{true, std::uint32_t(s.causticPhotons), passTag(0), "gi caustic photons"};
    spec.spectral = m_gi.spectral;
    buildPhotonMap(m_map, scene, accel, lights, s, m_engine, cluster, m_phases, spec, focus, stats);
    m_passesTraced = 1;
    m_mapPhotons = std::uint64_t(s.causticPhotons);
    float median = m_map.medianNeighbourRadius(s.causticK, gi.causticRadius, kRadiusSamples);
    m_firstRadius = median > 0 ? median : gi.causticRadius;
    // Later passes trace while the render's progress bar runs: theirs would interleave.
    m_engine.quiet = true;
    m_gi.caustic = &m_map;
    m_gi.causticRadius = m_firstRadius;
    if (s.causticPixelRadius) {
        const std::size_t pixels = std::size_t(std::max(scene.camera.width, 1)) *
                                   std::size_t(std::max(scene.camera.height, 1));
        m_pixels =
            std::make_unique<CausticPixelRadius>(pixels, gi.causticRadius, double(s.causticAlpha));
        m_gi.causticPixels = m_pixels.get();
    }
}

void ProgressiveCaustics::beginPass(int pass, int samples) {
    const GiSettings& s = m_gi.settings;
    const std::uint64_t photons = progressivePassPhotons(std::uint64_t(s.causticPhotons), samples);
    if (pass != m_mapPass || photons != m_mapPhotons) {
        PhotonPassSpec spec{true, std::uint32_t(photons), passTag(pass), "gi caustic photons"};
        spec.spectral = m_gi.spectral;
        buildPhotonMap(m_map, m_scene, m_accel, m_lights, s, m_engine, m_cluster, m_phases, spec,
                       m_focus, m_stats);
        m_mapPass = pass;
        m_mapPhotons = photons;
        ++m_passesTraced;
    }
    m_gi.caustic = &m_map;
    m_gi.causticRadius = float(double(m_firstRadius) * std::sqrt(m_radius.next(samples)));
    // The pixels' radii from the last pass's photon counts (its seed after the first).
    if (m_pixels && pass > 0) m_pixels->endPass(m_lastSamples);
    m_lastSamples = samples;
}

} // namespace rayproc
