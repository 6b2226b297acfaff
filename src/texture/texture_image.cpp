#include "texture/texture_image.h"

#include "core/named_loop.h"
#include "image/image.h"
#include "texture/direct_readers.h"
#include "texture/oiio_module.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <mutex>

#include <sys/stat.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace rayproc {

namespace {

float decode(float v, const TextureEncoding& e) {
    switch (e.kind) {
    case TextureEncoding::Kind::Linear: return v;
    case TextureEncoding::Kind::Gamma: return std::pow(std::max(v, 0.0f), e.gamma);
    case TextureEncoding::Kind::Srgb: return srgbToLinear(std::clamp(v, 0.0f, 1.0f));
    }
    return v;
}

// decode() remembered by the stored value's bits. An integer file holds at most 2^bits distinct
// values (256 for 8-bit ones), where a 1000x1000 colour image decodes three million samples
// through pow(); the same function of the same bits, so the same texels. Values past the
// table's room are decoded each time.
class DecodeMemo {
public:
    explicit DecodeMemo(const TextureEncoding& e) : m_encoding(e) {}
    float operator()(float v) {
        if (m_encoding.kind == TextureEncoding::Kind::Linear) return v;
        std::uint32_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        std::size_t slot = std::size_t((bits * 2654435761u) >> (32 - kLogSize));
        for (int probe = 0; probe < kProbes; ++probe, slot = (slot + 1) & (kSize - 1)) {
            Entry& e = m_table[slot];
            if (e.used && e.bits == bits) return e.value;
            if (!e.used) {
                e = Entry{bits, decode(v, m_encoding), true};
                return e.value;
            }
        }
        return decode(v, m_encoding);
    }

private:
    static constexpr int kLogSize = 12, kProbes = 8;
    static constexpr std::size_t kSize = std::size_t(1) << kLogSize;
    struct Entry {
        std::uint32_t bits = 0;
        float value = 0;
        bool used = false;
    };
    TextureEncoding m_encoding;
    std::vector<Entry> m_table = std::vector<Entry>(kSize);
};

// The file through OpenImageIO (texture/oiio_module.h), loaded on first use.
RawPixels readWithOiio(const std::string& path) {
    auto fail = [&](const std::string& why) {
        return ImageIoError("cannot read the texture \"" + path + "\": " + why);
    };
    const OiioModule* module = nullptr;
    try {
        module = &OiioModule::get();
    } catch (const ImageIoError& e) {
        throw fail(e.what());
    }
    const OiioModule& oiio = *module;
    char error[1024] = "";
    RayprocOiioInfo info{};
    std::unique_ptr<void, RayprocOiioCloseFn> in(oiio.open(path.c_str(), &info, error, sizeof error),
                                                 oiio.close);
    if (!in) throw fail(error);
    const int w = info.width, h = info.height, nch = info.channels;
    if (w <= 0 || h <= 0 || nch <= 0 || std::int64_t(w) * h > (std::int64_t(1) << 28))
        throw fail("unsupported size " + std::to_string(w) + "x" + std::to_string(h));
    checkImageDimensions(path, w, h);
    RawPixels raw;
    raw.width = w;
    raw.height = h;
    raw.channels = nch;
    raw.alphaChannel = info.alphaChannel;
    raw.isFloat = info.isFloat != 0;
    raw.pixels.resize(std::size_t(w) * h * nch);
    if (!oiio.read(in.get(), raw.pixels.data(), error, sizeof error)) throw fail(error);
    return raw;
}

std::shared_ptr<const TextureImage> decodeFile(const std::string& path,
                                               const TextureEncoding& encoding) {
    // Before any reader sees the file: it must be a regular file (OpenImageIO's fallback reader
    // seeks through /dev/zero forever), an EXR header must not make OpenEXR allocate more than
    // the file holds, a PNG must pass its checksums. A file that cannot be opened is said so
    // here (without loading OpenImageIO to say it).
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0)
        throw ImageIoError("cannot read the texture \"" + path + "\": " + std::strerror(errno));
    checkImageHeader(path);
    RawPixels raw;
    if (!readWithoutOiio(path, raw)) raw = readWithOiio(path);
    const int w = raw.width, h = raw.height, nch = raw.channels;
    // Integer files store encoded values; float files hold linear radiance or reflectance.
    TextureEncoding e = raw.isFloat ? TextureEncoding{TextureEncoding::Kind::Linear} : encoding;
    const int alphaChannel = raw.alphaChannel >= 0 ? raw.alphaChannel
                                                    : (nch == 2 || nch == 4 ? nch - 1 : -1);
    auto img = std::make_shared<TextureImage>();
    TextureImage::Level base;
    base.width = w;
    base.height = h;
    base.rgb.resize(std::size_t(w) * h * 3);
    if (alphaChannel >= 0) {
        img->hasAlpha = true;
        img->alpha.resize(std::size_t(w) * h);
    }
    // Rows in parallel, each texel's samples through `decoded` (alpha is never encoded).
    auto rows = [&](const auto* samples, auto&& decoded, auto&& asFloat) {
        tbb::parallel_for(tbb::blocked_range<int>(0, h, 32), [&](const tbb::blocked_range<int>& r) {
            auto decode = decoded(); // per range: a memo is not shared between threads
            const std::size_t end = std::size_t(r.end()) * std::size_t(w);
            for (std::size_t i = std::size_t(r.begin()) * std::size_t(w); i < end; ++i) {
                const auto* p = &samples[i * nch];
                for (int c = 0; c < 3; ++c) // grey (+ alpha) files repeat their one channel
                    base.rgb[3 * i + c] = decode(p[nch >= 3 ? c : 0]);
                if (alphaChannel >= 0) img->alpha[i] = asFloat(p[alphaChannel]);
            }
        });
    };
    namedLoop("texture_decode", [&] {
        if (raw.bytes) {
            // 8-bit samples: their 256 decodes, the same values the memo gives their floats.
            std::array<float, 256> table;
            DecodeMemo memo(e);
            for (int b = 0; b < 256; ++b) table[b] = memo(byteSample((unsigned char)b));
            rows(raw.bytes.get(), [&] { return [&](unsigned char b) { return table[b]; }; },
                 [](unsigned char b) { return byteSample(b); });
        } else {
            rows(raw.pixels.data(), [&] { return DecodeMemo(e); }, [](float v) { return v; });
        }
    });
    img->levels.push_back(std::move(base));
    buildMipLevels(*img);
    return img;
}

// Texel (x, y) of the coarser level c: the mean of the finer level f's 2x2 texels under it
// (edge texels repeated where f's size is odd).
void downsample(const TextureImage::Level& f, int x, int y, TextureImage::Level& c) {
    float sum[3] = {0, 0, 0};
    int n = 0;
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            int fx = std::min(2 * x + dx, f.width - 1), fy = std::min(2 * y + dy, f.height - 1);
            const float* p = f.at(fx, fy);
            for (int k = 0; k < 3; ++k) sum[k] += p[k];
            ++n;
        }
    float* q = &c.rgb[3 * (std::size_t(y) * c.width + x)];
    for (int k = 0; k < 3; ++k) q[k] = sum[k] / float(n);
}

} // namespace

void buildMipLevels(TextureImage& img) {
    img.levels.resize(1);
    while (img.levels.back().width > 1 || img.levels.back().height > 1) {
        const TextureImage::Level& f = img.levels.back();
        TextureImage::Level c;
        c.width = (f.width + 1) / 2;
        c.height = (f.height + 1) / 2;
        c.rgb.resize(std::size_t(c.width) * c.height * 3); // downsample writes every texel
        auto rows = [&](const tbb::blocked_range<int>& r) {
            for (int y = r.begin(); y < r.end(); ++y)
                for (int x = 0; x < c.width; ++x) downsample(f, x, y, c);
        };
        namedLoop("texture_mips",
                  [&] { tbb::parallel_for(tbb::blocked_range<int>(0, c.height, 32), rows); });
        img.levels.push_back(std::move(c));
    }
}

std::shared_ptr<const TextureImage> loadTextureImage(const std::string& path,
                                                     const TextureEncoding& encoding) {
    static std::mutex mutex;
    static std::map<std::string, std::weak_ptr<const TextureImage>> cache;
    std::string key = path + "\n" + std::to_string(int(encoding.kind)) + "\n" +
                      std::to_string(encoding.gamma);
    std::lock_guard<std::mutex> lock(mutex);
    if (auto hit = cache[key].lock()) return hit;
    auto img = decodeFile(path, encoding);
    cache[key] = img;
    return img;
}

} // namespace rayproc
