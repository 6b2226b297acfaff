// The work items that flow through the ray processor, a batch of rays at a time: RayBatch (rays
// traced to their closest hit), ShadowBatch (occlusion rays) and PhotonBatch (gi's photons,
// traced to their closest hit). Structure of arrays, so the intersect stage can load packets
// straight from them and kernels can loop over lanes.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>

namespace rayproc {

// Rays per batch. A multiple of 16 (the widest Embree packet). 64, 128, 256 and 512 measured
// within noise of each other on the Cornell box in raytrace mode (docs/performance.md, "Batch
// size"); 256 keeps queue traffic at 0.5 ns per ray, a batch (25 KB of rays, 16 KB of occlusion
// rays) fits in L2, and a 16x16 camera tile is exactly one batch.
constexpr int kBatchSize = 256;

// What a ray is for. The kind selects the retrace stage that receives the ray's result, and the
// type of batch it travels in (RayProcessor::setStage; occlusion rays for shadow rays). The engine
// names its own kinds; a mode's stages take the kinds from kFirstModeRayKind on, named in the
// mode's own header (gi: gi/gi_pipeline.h). A kind's value also keys its stages' sample
// numbers, so a mode keeps its kinds' values.
enum class RayKind : std::uint8_t {
    Camera,     // primary rays from the camera emitter
    Reflection, // spawned by the reflection stage
    Refraction, // spawned by the refraction stage
    Shadow,     // occlusion rays from the shadow stage
};
constexpr int kFirstModeRayKind = 4;
constexpr int kModeRayKindCount = 5; // a mode's kinds at most
constexpr int kRayKindCount = kFirstModeRayKind + kModeRayKindCount;
// A mode's i-th own kind.
constexpr RayKind modeRayKind(int i) { return RayKind(kFirstModeRayKind + i); }
// The engine's kinds' names; "mode-<i>" for a mode's.
const char* rayKindName(RayKind k);

// What a batch holds: rays whose closest hits its stage shades (RayBatch), occlusion rays
// whose stage only needs to know whether each reached its end (ShadowBatch, pbrt-v4's
// ShadowRayWorkItem), or photons whose closest hits the photon stage stores and scatters
// (PhotonBatch). The queue, the pool and the processor move all three; a route (RayRoute)
// says which one its kind's batches are.
enum class BatchType : std::uint8_t { Rays, Shadow, Photons };
constexpr int kBatchTypeCount = 3;

// How a batch is traced: its closest hits, or only whether anything lies before tfar (an
// occluded ray gets tfar < 0). Its type says which.
enum class RayQuery : std::uint8_t { Closest, Occlusion };
constexpr RayQuery queryOf(BatchType t) {
    return t == BatchType::Shadow ? RayQuery::Occlusion : RayQuery::Closest;
}
// The engine's kinds' batches: occlusion rays for shadow rays, rays for the others. A mode's
// kinds say theirs when routed (engine/pipeline.h).
inline BatchType defaultBatchType(RayKind k) {
    return k == RayKind::Shadow ? BatchType::Shadow : BatchType::Rays;
}

// One queue of a pipeline (engine/pipeline.h): the rays of one kind, its name for --stats and
// the type of its batches, which says how the intersector traces them. A mode names its
// kinds' queues (gi: gi/gi_pipeline.h).
struct RayRoute {
    RayKind kind;
    const char* name;
    BatchType batch;
};
// An engine kind's queue: its name (rayKindName) and batch type (defaultBatchType).
inline RayRoute engineRoute(RayKind kind) {
    return {kind, rayKindName(kind), defaultBatchType(kind)};
}

// Per-ray flags.
enum RayFlags : std::uint8_t {
    kFlagCountEmission = 1,    // add emission where this ray lands (camera and specular chains)
    kFlagCountEnvironment = 2, // add the sky's radiance if this ray escapes
    kFlagModeBit = 4, // a mode's own meaning (gi: a gather ray of an irradiance-cache record)
    // raytrace, gi: a ray sampled from a glossy lobe whose light the shadow stage also sampled:
    // emission (and with the second flag the sky) it lands on counts with the MIS weight of
    // its prevPdf against the light samples' (prevPdf 0: no light sample covered it, weight 1).
    kFlagMisEmission = 8,
    kFlagMisEnvironment = 16,
    // Sampled at a path's last vertex (past --max-depth; raytrace and gi: of a glossy lobe): it
    // adds the MIS share of the emission or sky it finds and nothing else.
    kFlagEmissionOnly = 32,
    // A path ray whose escape adds nothing (gi's correction paths leave the sky's direct light
    // at their origin to their gather's light samples).
    kFlagSkipEnvironment = 64,
    // A camera chain through smooth and rough dielectric interfaces only (a rough one cleared
    // kFlagCountEmission): a mode may take its first diffuse hit as a visible point, as it
    // takes one reached through mirrors and smooth glass (gi: light samples, the caustic map,
    // the final gather). Kept through delta bounces, cleared by any other glossy one.
    kFlagVisibleChain = 128,
};
// The first diffuse hit of a camera chain (kFlagCountEmission or kFlagVisibleChain).
inline bool visiblePoint(std::uint8_t flags) {
    return (flags & (kFlagCountEmission | kFlagVisibleChain)) != 0;
}

// What every batch starts with: its kind, how many lanes are filled, and the rays as Embree
// takes them (structure of arrays, so the intersect stage loads packets straight from them).
struct WorkBatch {
    RayKind kind = RayKind::Camera;
    BatchType type = BatchType::Rays;
    int count = 0;
    bool fresh = false; // new work from an emitter: queued behind work already in flight

    alignas(64) std::array<float, kBatchSize> ox, oy, oz;
    alignas(64) std::array<float, kBatchSize> dx, dy, dz;
    alignas(64) std::array<float, kBatchSize> tnear, tfar;

    bool full() const { return count == kBatchSize; }

    // Appends a ray and returns its lane; the caller fills the payload.
    int push(float oxv, float oyv, float ozv, float dxv, float dyv, float dzv, float tn, float tf) {
        int i = count++;
        ox[i] = oxv; oy[i] = oyv; oz[i] = ozv;
        dx[i] = dxv; dy[i] = dyv; dz[i] = dzv;
        tnear[i] = tn; tfar[i] = tf;
        return i;
    }

protected:
    explicit WorkBatch(BatchType t) : type(t) {}
    // Not virtual, so protected: a batch is owned, and deleted, as its own type.
    ~WorkBatch() = default;
    WorkBatch(const WorkBatch&) = default;
    WorkBatch& operator=(const WorkBatch&) = default;
};

// What a batch traced to its closest hits adds: the hit, written by the intersect stage. The
// intersector traces every such batch (RayBatch, PhotonBatch) through this one base.
struct HitBatch : WorkBatch {
    alignas(64) std::array<float, kBatchSize> t, u, v;
    alignas(64) std::array<std::uint32_t, kBatchSize> geomId, primId, instId;

    bool hit(int i) const { return geomId[i] != 0xffffffffu; }

protected:
    explicit HitBatch(BatchType type) : WorkBatch(type) {}
    ~HitBatch() = default;
    HitBatch(const HitBatch&) = default;
    HitBatch& operator=(const HitBatch&) = default;
};

// Rays traced to their closest hit: camera, reflection, refraction, a mode's path and gather
// rays. The payload is what the stage that shades the hit needs to go on with the path.
struct RayBatch : HitBatch {
    static constexpr BatchType kType = BatchType::Rays;
    RayBatch() : HitBatch(kType) {}

    alignas(64) std::array<std::uint32_t, kBatchSize> pixel;  // film slot
    alignas(64) std::array<std::uint32_t, kBatchSize> sample; // the pixel's sample index
    alignas(64) std::array<float, kBatchSize> wr, wg, wb;     // path throughput
    alignas(64) std::array<std::uint64_t, kBatchSize> rngKey; // the ray's random stream
    alignas(64) std::array<std::uint8_t, kBatchSize> depth;   // bounces so far
    alignas(64) std::array<std::uint8_t, kBatchSize> specularDepth; // reflection + refraction bounces
    alignas(64) std::array<std::uint8_t, kBatchSize> flags;
    // Path mode: how the ray was sampled, for multiple importance sampling where it lands.
    alignas(64) std::array<float, kBatchSize> prevPdf; // BSDF pdf (solid angle); 0 = delta/camera
    alignas(64) std::array<float, kBatchSize> prevCos; // cos(wi, previous facing normal)
    // Spectral mode: the path's wavelength number (engine/spectral_render.h; its sign bit marks
    // a path past a dispersive interface), which its successors and shadow rays inherit;
    // wr/wg/wb are then the throughput at those wavelengths. Written but unread in RGB mode.
    alignas(64) std::array<float, kBatchSize> lambdaU;
};

// Occlusion rays: each carries the contribution it adds where it is not blocked (a light or
// sky sample's), and where that goes. The intersect stage writes tfar < 0 for a blocked ray.
struct ShadowBatch : WorkBatch {
    static constexpr BatchType kType = BatchType::Shadow;
    ShadowBatch() : WorkBatch(kType) {}

    alignas(64) std::array<std::uint32_t, kBatchSize> pixel;  // film slot (gi: a record's)
    alignas(64) std::array<std::uint32_t, kBatchSize> sample; // the pixel's sample index
    alignas(64) std::array<float, kBatchSize> wr, wg, wb;     // unoccluded contribution
    alignas(64) std::array<float, kBatchSize> lambdaU;        // spectral: the path's wavelengths
    // Path mode: 1 + the contribution's category for --stats' noise breakdown (0: none).
    alignas(64) std::array<std::uint32_t, kBatchSize> category;
    // The spawning ray's flags, as a mode keeps them (gi: whether it serves a cache record).
    alignas(64) std::array<std::uint8_t, kBatchSize> flags;

    bool occluded(int i) const { return tfar[i] < 0.0f; }
};

// gi's photons (gi/photon_emitter.h, gi/photon_stage.h): a photon carries its power and what
// its next bounce samples with, no film slot and no MIS state; the photon stage stores it at
// its closest hit and scatters it on.
struct PhotonBatch : HitBatch {
    static constexpr BatchType kType = BatchType::Photons;
    PhotonBatch() : HitBatch(kType) {}

    // The photon's index in its pass: its stored records' key (with its depth), unique in the
    // pass whatever thread traced it.
    alignas(64) std::array<std::uint32_t, kBatchSize> index;
    alignas(64) std::array<float, kBatchSize> wr, wg, wb;     // power
    alignas(64) std::array<std::uint64_t, kBatchSize> rngKey; // the photon's random stream
    alignas(64) std::array<std::uint8_t, kBatchSize> depth;   // bounces so far
    alignas(64) std::array<std::uint8_t, kBatchSize> flags;   // gi's PhotonFlags
    // Spectral mode: the photon's wavelength number, as RayBatch::lambdaU; unread in RGB mode.
    alignas(64) std::array<float, kBatchSize> lambdaU;
};

// Calls f with b as its own type (RayBatch&, ShadowBatch& or PhotonBatch&): the one place that
// turns a batch's type into its C++ type, so the pool, the recorder and the processor handle
// every type with one generic body.
template <class Batch, class F> decltype(auto) visitBatch(Batch& b, F&& f) {
    constexpr bool isConst = std::is_const_v<Batch>;
    using Rays = std::conditional_t<isConst, const RayBatch, RayBatch>;
    using Shadows = std::conditional_t<isConst, const ShadowBatch, ShadowBatch>;
    using Photons = std::conditional_t<isConst, const PhotonBatch, PhotonBatch>;
    switch (b.type) {
    case BatchType::Shadow: return f(static_cast<Shadows&>(b));
    case BatchType::Photons: return f(static_cast<Photons&>(b));
    case BatchType::Rays: break;
    }
    return f(static_cast<Rays&>(b));
}

} // namespace rayproc
