// Photon stage: the retrace stage of photon rays (the paper's photon "retrace processor"; it
// shares the intersection handler with the camera pass). At diffuse and glossy hits a photon
// is stored — every one in the global pass; in the caustic pass only those that came from
// the light through specular surfaces alone (L S+ D). It then scatters by Russian roulette on
// the surface's reflectance (Jensen 2001): it survives with probability q = max channel of the
// BSDF weight and carries power * weight / q, so the stored power stays unbiased.
#pragma once

#include "engine/render_context.h"
#include "engine/stage.h"
#include "gi/photon_map.h"

#include <tbb/enumerable_thread_specific.h>

#include <functional>
#include <utility>
#include <vector>

namespace rayproc {

class PhotonStage : public RetraceStage {
public:
    PhotonStage(const RenderContext& rc, bool causticPass, int maxDepth)
        : m_rc(rc), m_causticPass(causticPass), m_maxDepth(maxDepth) {}
    void retrace(RayBatch& batch, StageContext& ctx) override;
    // The stored photons, in a fixed order (photon index, then bounce) whatever the threads.
    // The stored photons in (photon index, depth) order; nothing when `stop` turns true.
    std::vector<PhotonRecord> takePhotons(const std::function<bool()>& stop = {});

private:
    const RenderContext& m_rc;
    bool m_causticPass;
    int m_maxDepth;
    tbb::enumerable_thread_specific<std::vector<std::pair<std::uint64_t, PhotonRecord>>> m_stored;
};

} // namespace rayproc
