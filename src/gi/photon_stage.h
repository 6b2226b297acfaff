// Photon stage: the retrace stage of photon rays, which travel in PhotonBatches (the paper's
// photon "retrace processor"; it shares the intersection handler with the camera pass). At
// diffuse and glossy hits a photon is stored — every one in the global pass; in the caustic
// pass only those that came from the light through specular surfaces alone (L S+ D). It then
// scatters by Russian roulette on the surface's reflectance (Jensen 2001): it survives with
// probability q = max channel of the BSDF weight and carries power * weight / q, so the stored
// power stays unbiased.
#pragma once

#include "engine/render_context.h"
#include "engine/stage.h"
#include "gi/photon_lists.h"
#include "gi/photon_map.h"

#include <tbb/enumerable_thread_specific.h>

#include <functional>
#include <utility>
#include <vector>

namespace rayproc {

struct SurfaceHit;
class LaneShading;

// A photon ray's flags: it scattered diffusely / specularly on its way (the caustic pass keeps
// L S+ D paths only), and it left a delta light or the sky (set by the photon emitter).
enum PhotonFlags : std::uint8_t { kPhotonDiffuse = 1, kPhotonSpecular = 2, kPhotonDeltaOrSky = 4 };

// What a photon's power is multiplied by when it refracts through a smooth dielectric of index
// `ior`, entering it (from its front side) or leaving it: 1 / eta^2 with eta = n_t / n_i, so a
// stored photon carries flux / n^2 of the medium it landed in and its estimate is the basic
// radiance L / n^2 that rayproc's camera and gather chains carry (they refract without eta^2).
inline float smoothTransmissionScale(float ior, bool entering) {
    return entering ? 1.0f / (ior * ior) : ior * ior;
}

class PhotonStage : public RetraceStage {
public:
    // roughCaustics: in the caustic pass, photons go on through rough dielectric interfaces as
    // through smooth ones (GiSettings::roughCaustics).
    PhotonStage(const RenderContext& rc, bool causticPass, int maxDepth,
                bool roughCaustics = false)
        : m_rc(rc), m_causticPass(causticPass), m_roughCaustics(causticPass && roughCaustics),
          m_maxDepth(maxDepth) {}
    void retracePhotons(PhotonBatch& batch, StageContext& ctx) override;
    // A photon's key: its index and bounce, (index << 8) | depth, unique in a pass.
    using KeyedPhoton = rayproc::KeyedPhoton;
    // The stored photons in key order (photon index, then bounce), whatever the threads;
    // nothing when `stop` turns true.
    KeyedPhotons takeKeyedPhotons(const std::function<bool()>& stop = {});
    // The same without keys.
    PhotonList takePhotons(const std::function<bool()>& stop = {});
    // Records of keyed, sorted lists (the shares of a distributed photon pass) in key order.
    static PhotonList photonsInKeyOrder(KeyedPhotons keyed, const std::function<bool()>& stop = {});

private:
    // The photon lane i of b leaves at its hit h (power: its flux there; wl: its lane).
    PhotonRecord record(const PhotonBatch& b, int i, const SurfaceHit& h, const Vec3& wo,
                        const Vec3& power, const LaneShading& wl) const;
    const RenderContext& m_rc;
    bool m_causticPass;
    bool m_roughCaustics;
    int m_maxDepth;
    tbb::enumerable_thread_specific<std::vector<KeyedPhoton>> m_stored;
};

} // namespace rayproc
