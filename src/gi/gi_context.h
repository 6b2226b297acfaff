// What the gi passes share: the photon maps, the irradiance cache, the settings of gi mode,
// and during the cache's prepass the records being computed. Read-only during a render pass
// except for the prepass requests' atomic sums.
#pragma once

#include "core/math.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rayproc {

class PhotonMap;
class IrradianceCache;

// Diagnostic images (the paper: "output can often be misleading").
enum class GiDebugView { None, Photons, IcRecords, Caustics, Indirect };

struct GiSettings {
    int spp = 16;
    int maxDepth = 8;
    int lightSamples = 4;
    int photons = 200000;        // emitted for the global map
    int causticPhotons = 200000; // emitted for the caustic map (only L S+ D paths are kept)
    int maxPhotonDepth = 16;
    int globalK = 64;            // photons per global estimate
    int causticK = 64;
    float globalRadius = 0.0f;   // 0: a fraction of the scene's diagonal
    float causticRadius = 0.0f;
    int gatherRays = 64;         // final-gather rays per new estimate
    float icAccuracy = 0.25f;    // Ward's a
    bool irradianceCache = true;
    bool caustics = true;
    bool precomputedIrradiance = true;
    bool roulette = true;        // Russian roulette of photons and of specular paths
    GiDebugView debugView = GiDebugView::None;
    std::string toString() const;
};

// A record the irradiance cache's prepass is computing: where it is, and the fixed-point sums
// its gather rays add (deterministic whatever their order).
struct IcRequest {
    std::uint64_t key = 0; // (pixel, branch) for a fixed insertion order
    Vec3 position, normal;
    std::atomic<std::int64_t> radiance[3] = {0, 0, 0};
    std::atomic<std::int64_t> inverseDistance{0};
    std::atomic<std::int32_t> rays{0};
};

struct IcRequests {
    std::vector<std::unique_ptr<IcRequest>> slots;
    std::atomic<std::uint32_t> used{0};
    static constexpr double kScale = 1048576.0; // 2^20 fixed-point units per unit
};

struct GiData {
    GiSettings settings;
    const PhotonMap* global = nullptr;
    const PhotonMap* caustic = nullptr;
    const IrradianceCache* cache = nullptr; // frozen during a pass
    IcRequests* requests = nullptr;         // set only in the cache's prepass
    float globalRadius = 0, causticRadius = 0;
    float icMinRadius = 0, icMaxRadius = 0;
};

} // namespace rayproc
