// What the gi passes share: the photon maps, the irradiance cache, the settings of gi mode; and
// the requests (IcRequests) the cache's prepass and refinement gather records into, which they
// hand to their own gather stage. GiData is read-only while a pass runs.
#pragma once

#include "core/math.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rayproc {

class PhotonMap;
class IrradianceCache;
class SpectralRender;

// Diagnostic images (the paper: "output can often be misleading").
//  photons:    at the first diffuse hit, the global (plus caustic) map's radiance estimate
//              only: the maps themselves, no direct light, no final gather;
//  ic-records: the normal image at a quarter of its radiance, with the pixel of every cache
//              record's projected position set to kIcRecordMarker;
//  caustics:   the caustic map's estimate only;  indirect: the cache / final gather only.
enum class GiDebugView { None, Photons, IcRecords, Caustics, Indirect };
inline const Vec3 kIcRecordMarker(4.0f, 0.0f, 4.0f); // bright magenta

// The global map's default photon count. Its detail is the scene's, not the image's: the sunlit
// classroom at 160x90 and 128 spp kept a bias of mean 6.4% / block 11% with 50,000 photons,
// 3.5% / 8.7% with 200,000 and 4.4% / 5.1% with 800,000 (docs/photon-map.md, "How many
// photons"); 200,000 costs about 0.4 s here.
constexpr int kGlobalPhotons = 200000;
constexpr int kMaxPhotonRounds = 8;
// The caustic map's default photon count, each pass's with progressive caustics: one per pixel
// (pbrt-v4's SPPM also emits one photon per pixel per iteration by default), so caustic photons
// and camera samples grow together; between kMinDefaultPhotons and kMaxDefaultPhotons.
constexpr int kMinDefaultPhotons = 50000;
constexpr int kMaxDefaultPhotons = 1000000;
inline int defaultCausticPhotons(int width, int height) {
    double pixels = double(std::max(width, 1)) * double(std::max(height, 1));
    return int(std::clamp(pixels, double(kMinDefaultPhotons), double(kMaxDefaultPhotons)));
}

struct GiSettings {
    int spp = 16;
    int maxDepth = 8;
    // 2, not raytrace's 4: gi's passes are cheaper and reach a given error sooner on the public
    // scenes (docs/performance.md, "Light samples in gi").
    int lightSamples = 2;
    // Photons emitted for the global map, and for the caustic map (each pass's with
    // progressive caustics; only L S+ D paths are kept). giSettings() sets the caustic count
    // from the image: defaultCausticPhotons().
    int photons = kGlobalPhotons;
    int causticPhotons = kMinDefaultPhotons;
    // The global map is traced in rounds of `photons` until at least a quarter of `photons`
    // of the photons its gather estimate reads have landed in view (the camera's focus region),
    // at most this many rounds: the sunlit classroom keeps 4% of them in view, the Cornell box
    // all (docs/photon-map.md, "How many photons"). 1: exactly `photons`.
    int photonRounds = kMaxPhotonRounds;
    // A cap only: Russian roulette ends paths. 16 cut off a^16 of the light, 2.8% of the
    // furnace test's albedo-0.8 channel (measured -2.3% in the photons view).
    int maxPhotonDepth = 64;
    int globalK = 64;            // photons per global estimate
    int causticK = 64;
    float globalRadius = 0.0f;   // 0: a fraction of the scene's diagonal
    float causticRadius = 0.0f;
    int gatherRays = 64;         // final-gather rays per new estimate
    // Rays of a final gather made straight for the film, where a render pass finds no usable
    // cache record (or without the cache); 0: gatherRays / spp, at least 1, so such a pixel
    // gets about a record's rays over the whole render, and a time-limited render (a large
    // spp) one ray per pass: the passes average them (docs/irradiance-cache.md, "Film
    // gathers").
    int filmGatherRays = 0;
    float icAccuracy = 0.25f;    // Ward's a
    // Gather rays each cache record adds before every render pass after the first, so the
    // records' noise falls with the passes instead of staying in the image
    // (gi/cache_refinement.h; the classroom at 90 s: relMSE 0.0187 -> 0.0160); 0: the
    // prepass's gather only.
    int icRefineRays = 1;
    // Correction paths each cache record traces before every render pass after the first: a
    // control variate on the global map at the records (gi/cache_refinement.h), so the
    // records converge to the exact gather, not to the map's biased one. Applied with a
    // cache-wide weight that grows as they prove larger than their noise (the classroom at
    // 90 s: mean 8% dark -> 3%, relMSE 0.016 -> 0.009; where the map is already right they
    // cost 3-9% of the time to relMSE 0.01: docs/irradiance-cache.md); 0: off.
    int icCorrectionRays = 4;
    // Each record's correction averaged over its nearest records of the same facing, as many
    // as Stein's unbiased risk estimate says before each pass (gi/correction_smoothing.h).
    bool icSmoothing = true;
    bool irradianceCache = true;
    bool icGradients = true;     // Ward & Heckbert's gradients in the cache's interpolation
    bool caustics = true;
    // The caustic map traced anew every render pass with a shrinking radius, so caustics
    // converge (gi/progressive_caustics.h); off: one map, k-nearest estimates.
    bool progressiveCaustics = true;
    float causticAlpha = 2.0f / 3.0f; // the radius reduction (Hachisuka & Jensen's alpha)
    // Progressive caustics with a radius per pixel, shrunk by the photons each pixel receives
    // (SPPM's statistics, gi/caustic_pixel_radius.h); off: one radius sequence for all.
    bool causticPixelRadius = true;
    // Caustic photons go on through rough dielectric interfaces (rough water, frosted glass) as
    // through smooth ones, so the light they carry onto diffuse surfaces converges with the
    // progressive radius; gathers then leave the emitters and sky they find past a rough
    // interface to the caustic map. Off: those photons end at the rough interface, the light
    // reaches the visible points through the gathers' continuations and the global map.
    bool roughCaustics = true;
    bool precomputedIrradiance = true;
    // Each precomputed estimate made when a gather lookup first lands on its photon instead of
    // all of them before the render (PhotonMap::deferIrradiance): the same image, and no work
    // for photons no lookup reaches (a sunlit room's map outside the room).
    bool lazyIrradiance = true;
    // Where a gather ray lands on a diffuse surface, the direct light of delta lights and of
    // the sky comes from light samples there (shadow rays, like the first hit's) and the global
    // map gives the rest (it leaves out those lights' first-landing photons); off: the map
    // gives all. Its estimate of sunlight blurs sharp shadows and sunlit patches into their
    // surroundings, and the gather carries that bias to every surface they light
    // (docs/photon-map.md, "Direct light at gather hits").
    bool gatherDirect = true;
    // Every render pass, wherever the global map's estimate goes into the image (one ray from
    // each first diffuse hit standing for its gather), that estimate is taken away again and
    // a traced path added in its place, so the map's bias leaves the image as passes add up:
    // a consistent gi, at path tracing's noise (gi/correction_stage.h, docs/photon-map.md
    // "Correcting the map"). Off by default: on the public scenes the noise costs more time
    // to a given error than the bias does.
    bool mapCorrection = false;
    bool roulette = true;        // Russian roulette of photons and of specular paths
    GiDebugView debugView = GiDebugView::None;
    std::string toString() const;
};

// A record the irradiance cache's prepass is computing: where it is, and the fixed-point sums
// its gather rays add (deterministic whatever their order).
struct IcRequest {
    std::uint64_t key = 0; // (pixel, branch) for a fixed insertion order
    Vec3 position, normal;
    // Where the gather rays start (position offset off the surface) and the geometric normal
    // they must stay above: what refining the record later needs (gi/cache_refinement.h).
    Vec3 origin, geometricNormal;
    std::atomic<std::int64_t> radiance[3] = {0, 0, 0};
    std::atomic<std::int64_t> inverseDistance{0};
    std::atomic<std::int32_t> rays{0};
    // With gradients: the gather's frame (u, v, normal) and per stratum (j, k) at [j N + k]
    // the incident radiance, fixed-point like `radiance`, and the first hit's distance
    // (GatherStrata's layout; written once, by the stratum's ray). Read after the pass.
    Vec3 u, v;
    std::vector<std::array<std::int64_t, 3>> strataRadiance;
    std::vector<float> strataDistance;

    // 2^20 fixed-point units per unit of inverse distance, and of radiance in ordinary scenes;
    // the radiance's unit follows the scene's brightness as the film's does (radianceScale).
    static constexpr double kScale = 1048576.0;
    // Units per unit of radiance for a film of 2^filmExponent units (Film::exponentFor): 2^20
    // at the film's default 2^32, moved with it, so that dim and bright scenes keep their
    // records' precision (a fixed 2^20 read 1e-10 of the Cornell box's light as 0, and 1e15 of
    // it wrapped the 64-bit sums).
    static double radianceScale(int filmExponent) { return std::ldexp(kScale, filmExponent - 32); }
    // Adds radiance l that stratum's ray brought: its ray, continuations and the shadow rays of
    // its light samples add in any order, from any thread. `scale`: units per unit radiance.
    void add(std::uint32_t stratum, const Vec3& l, double scale) {
        for (int c = 0; c < 3; ++c) {
            // Clamped where the 64-bit sum could not hold it (llround's range).
            double v = std::clamp(double(l[c]) * scale, -0x1p62, 0x1p62);
            std::int64_t units = std::llround(v);
            radiance[c].fetch_add(units, std::memory_order_relaxed);
            if (stratum < strataRadiance.size())
                std::atomic_ref<std::int64_t>(strataRadiance[stratum][std::size_t(c)])
                    .fetch_add(units, std::memory_order_relaxed);
        }
    }
};

// The prepass level's requests, one slot per new gather, claimed by an atomic counter. Slots
// are allocated in chunks when first claimed and kept for the next level: a level may claim up
// to two per pixel but claims a few thousand, and allocating every possible slot up front took
// half the prepass's time (cornell-box 256x256: 0.076 s of 0.15 s).
class IcRequests {
public:
    IcRequests() = default;
    IcRequests(const IcRequests&) = delete;
    IcRequests& operator=(const IcRequests&) = delete;
    ~IcRequests() {
        for (std::size_t c = 0; c < m_chunkCount; ++c) delete m_chunks[c].load();
    }

    // Starts a level that may claim up to `capacity` slots; not concurrent with claim().
    void beginLevel(std::size_t capacity) {
        std::size_t chunks = (capacity + kChunk - 1) / kChunk;
        if (chunks > m_chunkCount) {
            auto grown = std::make_unique<std::atomic<Chunk*>[]>(chunks);
            for (std::size_t c = 0; c < chunks; ++c)
                grown[c].store(c < m_chunkCount ? m_chunks[c].load() : nullptr);
            m_chunks = std::move(grown);
            m_chunkCount = chunks;
        }
        m_capacity = capacity;
        m_used.store(0);
    }
    // A zeroed slot and its index, or nullptr when the level's capacity is used up. Only the
    // claiming thread writes the slot's plain fields, before it spawns the slot's gather rays.
    IcRequest* claim(std::uint32_t& index) {
        index = m_used.fetch_add(1);
        if (index >= m_capacity) return nullptr;
        std::atomic<Chunk*>& cell = m_chunks[index / kChunk];
        Chunk* chunk = cell.load(std::memory_order_acquire);
        if (!chunk) {
            auto fresh = std::make_unique<Chunk>();
            if (cell.compare_exchange_strong(chunk, fresh.get(), std::memory_order_acq_rel))
                chunk = fresh.release();
        }
        IcRequest& r = chunk->slots[index % kChunk];
        r.key = 0;
        for (auto& c : r.radiance) c.store(0, std::memory_order_relaxed);
        r.inverseDistance.store(0, std::memory_order_relaxed);
        r.rays.store(0, std::memory_order_relaxed);
        r.strataRadiance.clear();
        r.strataDistance.clear();
        return &r;
    }
    // A slot this level claimed.
    IcRequest& operator[](std::uint32_t index) {
        return m_chunks[index / kChunk].load(std::memory_order_acquire)->slots[index % kChunk];
    }
    // The slots this level claimed (after its pass).
    std::size_t claimed() const { return std::min<std::size_t>(m_used.load(), m_capacity); }
    // The slots this level asked for, those refused for want of room included.
    std::size_t wanted() const { return m_used.load(); }
    // Units per unit radiance of the requests' sums (IcRequest::radianceScale).
    void setRadianceScale(double scale) { m_radianceScale = scale; }
    double radianceScale() const { return m_radianceScale; }

private:
    double m_radianceScale = IcRequest::kScale;
    static constexpr std::size_t kChunk = 256;
    struct Chunk {
        IcRequest slots[kChunk];
    };
    std::unique_ptr<std::atomic<Chunk*>[]> m_chunks;
    std::size_t m_chunkCount = 0;
    std::size_t m_capacity = 0;
    std::atomic<std::uint32_t> m_used{0};
};

class CausticPixelRadius;

struct GiData {
    GiSettings settings;
    const PhotonMap* global = nullptr;
    // The global map without the first-landing photons of delta lights and the sky
    // (GiSettings::gatherDirect; null otherwise): diffuse gather hits' estimate of the rest.
    const PhotonMap* globalIndirect = nullptr;
    const PhotonMap* caustic = nullptr;
    const IrradianceCache* cache = nullptr; // frozen during a pass
    float globalRadius = 0, causticRadius = 0;
    // Caustic estimates from every photon within causticRadius (progressive caustics), not
    // from the causticK nearest within it.
    bool causticFixedRadius = false;
    // With GiSettings::causticPixelRadius: each pixel's radius, and its photon counts.
    CausticPixelRadius* causticPixels = nullptr;
    // The caustic map carries the light through rough dielectric interfaces (a caustic pass
    // with GiSettings::roughCaustics): a gather leaves the emission and sky it finds past one to
    // it, as it leaves what it finds past smooth glass.
    bool roughCaustics = false;
    float icMinRadius = 0, icMaxRadius = 0;
    // The final gather's strata: M rings of equal sin^2(theta) by N azimuth sectors, one ray
    // each (M N ~ gatherRays, N ~ pi M as Ward & Heckbert suggest); see gatherStrata().
    int gatherTheta = 1, gatherPhi = 1;
    int filmGatherTheta = 1, filmGatherPhi = 1; // the same for film gathers (filmGatherRays)
    bool strataWanted = false; // the prepass records per-stratum results (for gradients)
    // Spectral mode (engine/spectral_render.h): the passes' paths and photons carry
    // wavelengths; the photon maps then hold CIE XYZ, the cache and the film RGB. Null: RGB.
    const SpectralRender* spectral = nullptr;
};

// M and N for a requested number of gather rays: M = round(sqrt(rays / pi)), N = round(rays / M),
// both at least 1, so strata are about square in (theta, phi) and M N is within M / 2 of rays.
inline void gatherStrata(int rays, int& thetaCount, int& phiCount) {
    thetaCount = int(std::lround(std::sqrt(double(std::max(rays, 1)) / 3.14159265358979)));
    thetaCount = std::max(1, thetaCount);
    phiCount = std::max(1, int(std::lround(double(std::max(rays, 1)) / thetaCount)));
}

// The rays of a film gather (GiSettings::filmGatherRays), "auto" (0) resolved.
inline int filmGatherRays(const GiSettings& s) {
    if (s.filmGatherRays > 0) return s.filmGatherRays;
    return std::max(1, int(std::lround(double(s.gatherRays) / double(std::max(s.spp, 1)))));
}

} // namespace rayproc
