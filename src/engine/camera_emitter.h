// Camera emitter: generates primary rays tile by tile (16x16 pixels = one batch, coherent),
// one stratified sub-pixel sample per pixel per unit, for the samples of one pass. The camera's
// pixel filter places each sample: its offset from the pixel centre is drawn from the filter
// (kernels/filter_sampling.h), so the film's plain per-pixel average is the filtered pixel.
#pragma once

#include "engine/render_context.h"
#include "engine/stage.h"
#include "kernels/camera_rays.h"
#include "kernels/filter_sampling.h"

#include <atomic>
#include <cstdint>
#include <vector>

namespace rayproc {

// The kernel's view of a scene camera: world-space axes, field of view, lens.
kernels::CameraFrame cameraFrame(const Camera& camera);
// The kernel's view of a scene pixel filter.
kernels::FilterShape filterShape(const PixelFilter& filter);

class CameraEmitter : public Emitter {
public:
    static constexpr int kTile = 16; // kTile * kTile == kBatchSize

    // `camera` overrides the scene's (gi's cache prepass renders at lower resolutions).
    CameraEmitter(const RenderContext& rc, const Camera* camera = nullptr);
    // A distributed render's share (cluster/cluster.h): this emitter takes the tiles t with
    // t % size == rank (interleaved, so every rank gets a like mix of cheap and costly
    // regions). Each pixel's samples do not depend on which process renders them.
    void setShare(int rank, int size);
    // Prepares the emission of samples [first, first + count) of every pixel of the share.
    void beginPass(int firstSample, int count);
    // Adaptive sampling (engine/adaptive_sampler.h): from the next beginPass on, only the
    // pixels with mask[p] set are sampled, each with its own next samples [n_p, n_p + count)
    // (n_p: the film's committed samples of p), and tiles without such pixels are skipped.
    // Null: every pixel, samples [first, first + count).
    void setMask(const std::vector<std::uint8_t>* mask) { m_mask = mask; }
    bool emit(StageContext& ctx) override;
    std::uint64_t unitsEmitted() const { return m_next.load(); }
    std::uint64_t unitsPerPass() const { return std::uint64_t(m_tiles.size()) * m_passCount; }
    int tilesInShare() const {
        int tiles = m_tilesX * m_tilesY;
        return tiles / m_shareSize + (m_shareRank < tiles % m_shareSize ? 1 : 0);
    }

private:
    struct TileSamples;
    // The film and lens positions of a tile's samples for the pass's sample ofPass; their count.
    int sampleTile(int tile, int ofPass, TileSamples& t) const;
    // The samples' camera rays into the empty batch, each pixel's sample counted on the film.
    void writeRays(const TileSamples& t, int n, RayBatch& batch) const;

    const RenderContext& m_rc;
    Camera m_camera;
    kernels::CameraFrame m_frame;
    // Signed weights (mitchell's and lanczos's negative lobes) would have to travel with each
    // path to the film; until the stages carry them, the positive part of the filter is used.
    kernels::FilterSampler m_filter;
    int m_tilesX, m_tilesY;
    int m_shareRank = 0, m_shareSize = 1;
    int m_firstSample = 0, m_passCount = 0;
    const std::vector<std::uint8_t>* m_mask = nullptr;
    std::vector<int> m_tiles; // the pass's tiles: the share's, less those the mask leaves out
    std::atomic<std::uint64_t> m_next{0};
};

} // namespace rayproc
