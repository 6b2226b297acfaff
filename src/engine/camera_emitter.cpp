#include "engine/camera_emitter.h"

#include "kernels/sobol.h"

#include "kernels/random.h"

#include <algorithm>
#include <cmath>

namespace rayproc {

static_assert(CameraEmitter::kTile * CameraEmitter::kTile == kBatchSize);
// Keys the wavelength number's sequence apart from the film's and the lens's.
constexpr std::uint64_t kWavelengthKey = 0x6c8e9cf570932bd5ULL;
// filterShape converts the filter type by value.
static_assert(int(kernels::FilterType::Box) == int(PixelFilter::Type::Box) &&
              int(kernels::FilterType::Triangle) == int(PixelFilter::Type::Triangle) &&
              int(kernels::FilterType::Gaussian) == int(PixelFilter::Type::Gaussian) &&
              int(kernels::FilterType::Mitchell) == int(PixelFilter::Type::Mitchell) &&
              int(kernels::FilterType::Lanczos) == int(PixelFilter::Type::Lanczos));

kernels::CameraFrame cameraFrame(const Camera& cam) {
    Affine toWorld = Affine::lookAt(cam.position, cam.lookAt, cam.up);
    kernels::CameraFrame f;
    f.origin = cam.position;
    f.right = normalize(toWorld.vector({1, 0, 0}));
    f.up = normalize(toWorld.vector({0, 1, 0}));
    f.forward = normalize(toWorld.vector({0, 0, -1}));
    f.tanHalfFovY = std::tan(0.5f * cam.fovY * kPi / 180.0f);
    f.width = float(cam.width);
    f.height = float(cam.height);
    f.aspect = float(cam.width) / float(cam.height);
    f.lensRadius = cam.apertureRadius;
    f.focusDistance = cam.focusDistance > 0 ? cam.focusDistance : length(cam.lookAt - cam.position);
    return f;
}

kernels::FilterShape filterShape(const PixelFilter& f) {
    kernels::FilterShape s;
    s.type = kernels::FilterType(int(f.type));
    s.rx = f.radius.x;
    s.ry = f.radius.y;
    s.sigma = f.sigma;
    s.b = f.b;
    s.c = f.c;
    s.tau = f.tau;
    return s;
}

CameraEmitter::CameraEmitter(const RenderContext& rc, const Camera* camera)
    : m_rc(rc), m_camera(camera ? *camera : rc.scene.camera), m_frame(cameraFrame(m_camera)),
      m_filter(filterShape(m_camera.filter), /*positivePart=*/true) {
    const Camera& cam = m_camera;
    m_tilesX = (cam.width + kTile - 1) / kTile;
    m_tilesY = (cam.height + kTile - 1) / kTile;
}

void CameraEmitter::setShare(int rank, int size) {
    m_shareSize = std::max(size, 1);
    m_shareRank = std::clamp(rank, 0, m_shareSize - 1);
}

void CameraEmitter::beginPass(int firstSample, int count) {
    m_firstSample = firstSample;
    m_passCount = count;
    m_next.store(0);
    m_tiles.clear();
    const int width = m_camera.width, height = m_camera.height;
    for (int tile = m_shareRank; tile < m_tilesX * m_tilesY; tile += m_shareSize) {
        bool any = !m_mask;
        const int x0 = (tile % m_tilesX) * kTile, y0 = (tile / m_tilesX) * kTile;
        for (int y = y0; y < std::min(y0 + kTile, height) && !any; ++y)
            for (int x = x0; x < std::min(x0 + kTile, width) && !any; ++x)
                any = (*m_mask)[std::size_t(y) * std::size_t(width) + std::size_t(x)] != 0;
        if (any) m_tiles.push_back(tile);
    }
}

// One tile's camera samples, before they become rays.
struct CameraEmitter::TileSamples {
    alignas(64) float fx[kBatchSize], fy[kBatchSize], lu[kBatchSize], lv[kBatchSize];
    alignas(64) float lambdaU[kBatchSize];
    std::uint32_t pix[kBatchSize], samples[kBatchSize];
    std::uint64_t keys[kBatchSize];
};

// Unit u covers the share's tile (u / passCount) for sample (firstSample + u % passCount): all the
// samples of a tile are emitted together, which keeps rays of a region coherent in time.
bool CameraEmitter::emit(StageContext& ctx) {
    std::uint64_t unit = m_next.fetch_add(1);
    if (unit >= unitsPerPass()) return false;
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::CameraEmit);
    TileSamples t;
    const int n = sampleTile(m_tiles[std::size_t(unit / m_passCount)], int(unit % m_passCount), t);
    RayBatch& b = ctx.out(RayKind::Camera);
    // A tile is exactly one batch; start a fresh one if the open batch has other rays.
    RayBatch* batch = &b;
    if (batch->count != 0) {
        ctx.flush(RayKind::Camera);
        batch = &ctx.out(RayKind::Camera);
    }
    writeRays(t, n, *batch);
    stats.samples += std::uint64_t(n);
    stats.stages[int(StageId::CameraEmit)].raysOut += std::uint64_t(n);
    ctx.flush(RayKind::Camera); // hand the tile to the queue now: it is a full unit of coherent work
    return true;
}

int CameraEmitter::sampleTile(int tile, int ofPass, TileSamples& t) const {
    int x0 = (tile % m_tilesX) * kTile, y0 = (tile / m_tilesX) * kTile;
    int width = m_camera.width, height = m_camera.height;
    int n = 0;
    for (int y = y0; y < std::min(y0 + kTile, height); ++y) {
        for (int x = x0; x < std::min(x0 + kTile, width); ++x) {
            std::uint32_t p = std::uint32_t(y) * std::uint32_t(width) + std::uint32_t(x);
            if (m_mask && !(*m_mask)[p]) continue;
            // Adaptive passes continue each pixel's own sequence from its committed count.
            const int sample = m_mask ? int(m_rc.film.samplesOf(p)) + ofPass
                                      : m_firstSample + ofPass;
            std::uint64_t pixelKey = kernels::pathKey(m_rc.seed, p, 0xffffffffu);
            std::uint64_t key = kernels::pathKey(m_rc.seed, p, std::uint32_t(sample));
            // The film position and the lens position: Owen-scrambled Sobol points over the
            // pixel's samples, each pair its own sequence (kernels/sobol.h); independent
            // numbers of the sample's stream with --no-stratification.
            const bool sobol = m_rc.policy.stratify;
            Vec2 s = sobol ? kernels::owenSobol2D(std::uint32_t(sample), pixelKey)
                           : Vec2{kernels::uniform(key, 2), kernels::uniform(key, 3)};
            Vec2 lens;
            if (m_frame.lensRadius > 0)
                lens = sobol ? kernels::owenSobol2D(std::uint32_t(sample), kernels::mix64(pixelKey))
                             : Vec2{kernels::uniform(key, 0), kernels::uniform(key, 1)};
            if (m_camera.filter.type == PixelFilter::Type::Box) {
                // x + (0.5 - r) + 2 r s: for the default radius 0.5 exactly x + s, the film
                // positions (and images) rayproc has always produced.
                float rx = m_camera.filter.radius.x, ry = m_camera.filter.radius.y;
                t.fx[n] = float(x) + (0.5f - rx) + 2.0f * rx * s.x;
                t.fy[n] = float(y) + (0.5f - ry) + 2.0f * ry * s.y;
            } else {
                kernels::FilterSample fs = m_filter.sample(s);
                t.fx[n] = float(x) + 0.5f + fs.offset.x;
                t.fy[n] = float(y) + 0.5f + fs.offset.y;
            }
            // The wavelength number of spectral mode: its own sequence over the pixel's samples.
            t.lambdaU[n] = sobol ? kernels::owenSobol2D(std::uint32_t(sample),
                                                        kernels::mix64(pixelKey ^ kWavelengthKey))
                                       .x
                                 : kernels::uniform(key, 4);
            t.lu[n] = lens.x;
            t.lv[n] = lens.y;
            t.pix[n] = p;
            t.samples[n] = std::uint32_t(sample);
            t.keys[n] = key;
            ++n;
        }
    }
    return n;
}

void CameraEmitter::writeRays(const TileSamples& t, int n, RayBatch& batch) const {
    kernels::generateCameraRays(m_frame, n, t.fx, t.fy, t.lu, t.lv, batch.ox.data(),
                                batch.oy.data(), batch.oz.data(), batch.dx.data(),
                                batch.dy.data(), batch.dz.data());
    for (int i = 0; i < n; ++i) {
        batch.tnear[i] = 0.0f;
        batch.tfar[i] = kInfinity;
        batch.pixel[i] = t.pix[i];
        batch.sample[i] = t.samples[i];
        batch.prevPdf[i] = 0.0f;
        batch.prevCos[i] = 0.0f;
        batch.lambdaU[i] = t.lambdaU[i];
        batch.wr[i] = batch.wg[i] = batch.wb[i] = 1.0f;
        batch.rngKey[i] = kernels::hashCombine(t.keys[i], 1);
        batch.depth[i] = 0;
        batch.specularDepth[i] = 0;
        batch.flags[i] = kFlagCountEmission | kFlagCountEnvironment;
        m_rc.film.addSample(t.pix[i]);
    }
    batch.count = n;
}

} // namespace rayproc
