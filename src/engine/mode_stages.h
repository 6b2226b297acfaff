// A mode's own stages beside the engine's in a render pass (gi: the gather and correction
// stages). The render job lists the engine's stages in the render's pipeline, then the mode
// attaches its own: it appends them to the pipeline (engine/pipeline.h) with the queues of its
// ray kinds (engine/ray_batch.h, modeRayKind) and hands the surface stage's diffuse hits to its
// handlers. The engine knows no
// mode: it only calls these.
#pragma once

#include "engine/stats.h"

#include <vector>

namespace rayproc {

class Pipeline;
class ShadowStage;
class SurfaceStage;
struct RenderContext;

// The engine's side of a render pass, as a mode's stages see it when they attach.
struct EngineStages {
    const RenderContext& rc;
    Pipeline& pipeline;
    SurfaceStage& surface;
    ShadowStage& shadow; // light samples for the mode's paths (routed by the mode if it needs them)
};

class ModeStages {
public:
    virtual ~ModeStages() = default;
    // Builds the mode's stages for `engine.rc`, appends them to `engine.pipeline` and
    // registers their hit handlers with `engine.surface`. The stages live until the next
    // attach or the mode's object goes; they are used only while the render pass runs.
    virtual void attach(const EngineStages& engine) = 0;
    // The mode's stages as --stats names them, after the engine's (RenderStats::pipeline).
    virtual std::vector<StageLabel> labels() const = 0;
};

} // namespace rayproc
