// A mode's own stages beside the engine's in a render pass (gi: the gather and correction
// stages). The render job builds the engine's stages for the render's context, then the mode
// attaches its own: it routes its ray kinds (engine/ray_batch.h, modeRayKind) to them in the
// processor and hands the surface stage's diffuse hits to its handlers. The engine knows no
// mode: it only calls these.
#pragma once

#include "engine/stats.h"

#include <vector>

namespace rayproc {

class RayProcessor;
class ShadowStage;
class SurfaceStage;
struct RenderContext;

// The engine's side of a render pass, as a mode's stages see it when they attach.
struct EngineStages {
    const RenderContext& rc;
    RayProcessor& processor;
    SurfaceStage& surface;
    ShadowStage& shadow; // light samples for the mode's paths (routed by the mode if it needs them)
};

class ModeStages {
public:
    virtual ~ModeStages() = default;
    // Builds the mode's stages for `engine.rc`, routes their ray kinds in `engine.processor`
    // and registers their hit handlers with `engine.surface`. The stages live until the next
    // attach or the mode's object goes; they are used only while the render pass runs.
    virtual void attach(const EngineStages& engine) = 0;
    // The mode's stages as --stats names them, after the engine's (RenderStats::pipeline).
    virtual std::vector<StageLabel> labels() const = 0;
};

} // namespace rayproc
