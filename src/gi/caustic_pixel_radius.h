// Caustic radius per pixel: stochastic progressive photon mapping's statistics (Hachisuka &
// Jensen 2009, "Stochastic progressive photon mapping", ACM TOG 28(5)) kept per pixel, for the
// caustic map that gi traces anew every render pass (gi/progressive_caustics.h).
//
// Pixel j keeps a radius R_j and a photon count N_j. In a pass its camera samples' visible
// points (the first diffuse hit, through any specular chain) estimate the caustic from every
// photon of the pass's map within R_j and count the photons they found, M_j; after the pass
//   N_j <- N_j + alpha M_j,   R_j^2 <- R_j^2 (N_j + alpha M_j) / (N_j + M_j)   (SPPM, eqs. 9-10),
// so a pixel shrinks its radius only as fast as photons arrive: a caustic line sharpens where
// it is lit while the dark floor beside it keeps its wide, quiet disc. Each pass's estimate is
// still an independent one averaged by the film (Knaus & Zwicker 2011): R_j depends only on
// earlier passes' photons, so the pass's estimate is the irradiance blurred over R_j, and the
// bias (O(R_j^2)) and the noise both vanish as R_j shrinks while N_j grows.
//
// R_j starts at the distance to the causticK-th photon of the first map at the pixel's visible
// points (the mean of its squared value over the pixel's first-pass samples), at most the
// largest radius (gi's causticRadius: 2% of the view, --caustic-radius, or an sppm file's
// radius): Jensen's k-nearest radius, so a dense caustic starts as sharp as its photons allow
// and a sparse region as smooth as the old global start. That first pass estimates with the
// global first radius, as before; its photons choose R_j, later passes' are independent of it.
// N_j starts at the photons (per sample) the first map holds within R_j, not at SPPM's 0: the
// first pass counts as the sequence's first index, so under a constant density R_j follows the
// global sequence's (i + alpha) / (i + 1) instead of SPPM's first step alpha, whose faster start
// measured noisier (docs/caustics.md).
//
// A pass of s samples per pixel traces one map of s times the per-sample photons: M_j is
// turned into the photons per sample and lookup, m = M_j / (lookups s), and the update applied
// s times, so the sequence counts samples like the global one (ProgressiveRadius).
//
// Determinism: during a pass the radii are read only; the counts are integer atomics (their
// sum does not depend on the order of the adds) and the update runs between passes. Under MPI
// each pixel is rendered by one rank, so its statistics are that rank's alone.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace rayproc {

class CausticPixelRadius {
public:
    // `pixels` of the film; every R_j starts at maxRadius until the first pass has chosen it.
    CausticPixelRadius(std::size_t pixels, float maxRadius, double alpha);

    // True in the first pass: visible points report their k-th neighbour distance (seed()).
    bool seeding() const { return m_seeding; }
    // R_j for pixel j in this pass (maxRadius for a pixel outside the film).
    float radius(std::uint32_t pixel) const {
        return pixel < m_radius.size() ? m_radius[pixel] : m_maxRadius;
    }
    // A visible point of pixel j in the first pass: its k-th neighbour's distance^2 and the
    // photons within it (k, or fewer at the largest radius).
    void seed(std::uint32_t pixel, float radius2, std::uint32_t photons);
    // A visible point of pixel j in a later pass: the photons its estimate found within R_j.
    void found(std::uint32_t pixel, std::uint32_t photons);
    // After a pass of `samples` samples per pixel: the new radii (and the seed's, after the first).
    void endPass(int samples);

    // The mean R_j over pixels that have looked up the caustic (for the log), 0 if none.
    double meanRadius() const;
    float maxRadius() const { return m_maxRadius; }

private:
    float m_maxRadius;
    double m_alpha;
    bool m_seeding = true;
    std::vector<float> m_radius; // R_j
    std::vector<float> m_count;  // N_j
    // This pass's sums: lookups, and photons found (or, while seeding, sum of
    // radius^2 / maxRadius^2 in units of 2^-16, and m_seedPhotons the photons within).
    std::unique_ptr<std::atomic<std::uint32_t>[]> m_lookups, m_sum, m_seedPhotons;
};

} // namespace rayproc
