// Photon emitter: the first pass of Jensen's photon mapping. Lights emit in proportion to
// their power; each photon is a deterministic function of its index (stratified over the
// photons of the pass: the light choice, the point on the light and the direction each use
// their own permutation), so the photon maps do not depend on the thread count. Photons travel
// in their own batches (PhotonBatch: power, index, random stream, depth, flags, wavelength).
#pragma once

#include "core/math.h"
#include "engine/render_context.h"
#include "engine/stage.h"
#include "gi/photon_stage.h"
#include "lighting/light_set.h"

#include <atomic>
#include <cstdint>
#include <vector>

namespace rayproc {

class SpectralRender;

class PhotonEmitter : public Emitter {
public:
    // sceneBounds: where directional and environment photons start (a disk covering the
    // scene's bounding sphere). focus (may be empty): a region the camera sees at which
    // focusShare of those photons are aimed (gi/focus_region.h); the others still cover the
    // whole disk and every photon's flux is divided by the mixture's density, so the maps stay
    // unbiased. tag separates the random streams of the two photon passes.
    PhotonEmitter(const LightSet& lights, const Bounds3& sceneBounds, std::uint32_t count,
                  std::uint64_t seed, std::uint64_t tag, const Bounds3& focus = {},
                  float focusShare = 0.0f);
    // A distributed render's share (cluster/cluster.h): only photons [first, last) of the
    // `count` are emitted here; each photon is the same whichever process emits it.
    void setRange(std::uint64_t first, std::uint64_t last);
    // Spectral mode (engine/spectral_render.h): each photon carries three wavelengths of its
    // own, from a number u stratified over the pass's photons (a stream keyed by the seed, the
    // pass's tag and the photon's index, so the same whichever thread or rank emits it), and
    // its power is its light's spectrum at them, set up as spectral path mode evaluates lights.
    void setSpectral(const SpectralRender* spectral) { m_spectral = spectral; }
    bool emit(StageContext& ctx) override;
    // Photons of the range handed to the processor so far, and the range's size (progress).
    std::uint64_t photonsEmitted() const;
    std::uint64_t photonsInRange() const { return m_last - m_first; }
    // Photon powers are in units of powerUnit() (W): 1 when the lights' total luminance power
    // lies within 2^-kWattsRange .. 2^kWattsRange W (every ordinary scene: its photons are as
    // they always were), else the power of two nearest below that total, so that a light of
    // 3e37 W/m^2/sr, a directional light over a 1e15-wide scene or one of 1e-30 gives finite,
    // normal photon powers. PhotonMap::setPowerUnit turns estimates back into W; scaling by a
    // power of two is exact.
    static constexpr int kWattsRange = 60;
    static double powerUnit(const LightSet& lights, const Bounds3& sceneBounds);
    Vec3 totalPower() const { return m_totalPower; } // in powerUnit()s
    bool empty() const { return m_cdf.empty(); }

private:
    struct Emission {
        Vec3 origin, direction, power;
        bool valid = false;
        bool deltaOrSky = false; // from a delta light or the sky (kPhotonDeltaOrSky)
        std::size_t light = 0;   // LightSet::lights' index; the sky is lights.size()
    };
    // Photon `index`'s wavelength number, and its power at those wavelengths.
    float lambdaU(std::uint32_t index) const;
    Vec3 spectralPower(const Emission& e, float u) const;
    // A photon's light (index `light`; the sky is lights.size()), the probability it was
    // chosen, its flux, and its stratified numbers for the choice, the position and the
    // direction.
    struct Choice {
        std::size_t light;
        float pChoice;
        Vec3 share;
        Vec2 uPick, uPos, uDir;
    };
    Emission emitOne(std::uint32_t index) const;
    Emission emitFromSky(const Choice& ch) const;
    Emission emitFromLight(const LightSource& l, const Choice& ch) const;
    Emission lambertian(const Vec3& p, const Vec3& err, Vec3 n, bool twoSided,
                        const Choice& ch) const;
    // A photon origin on the emission plane behind the scene, perpendicular to dir, and the
    // inverse of its area density under the focus mixture.
    Vec3 diskPoint(const Vec3& dir, Vec2 u, float uChoice, float& invDensity) const;

    const LightSet& m_lights;
    Vec3 m_center;
    float m_radius;
    double m_unit = 1; // powerUnit()
    Vec3 m_focusCenter{0, 0, 0};
    float m_focusRadius = 0.0f;
    float m_focusShare = 0.0f; // 0: every photon uniform on the whole disk
    std::uint32_t m_count;
    std::uint64_t m_key;
    std::vector<float> m_cdf;       // over lights (and the sky, last) by luminance of power
    std::vector<Vec3> m_power;      // per choice
    Vec3 m_totalPower{0, 0, 0};
    std::uint64_t m_first = 0, m_last = 0; // the range emitted: all photons by default
    std::atomic<std::uint64_t> m_next{0};
    const SpectralRender* m_spectral = nullptr;
};

} // namespace rayproc
