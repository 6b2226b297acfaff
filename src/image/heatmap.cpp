// The heatmap maps each pixel's error through the inferno colour map (perceptually uniform,
// black at no error) on a log or linear scale, and draws its legend into the picture: a
// vertical colour bar right of the image with ticks and labels in a 5x7 bitmap font, scaled up
// with the image height so the labels stay readable on large renders.
#include "image/heatmap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

namespace rayproc {

namespace {

constexpr int kMinPanelHeight = 96;
constexpr int kLabelChars = 7; // the longest label heatmapTickLabel makes, e.g. "0.00125"

// 5x7 glyphs, one byte per row, bit 4 = leftmost column.
struct Glyph {
    char c;
    std::array<std::uint8_t, 7> rows;
};
constexpr std::array<Glyph, 14> kFont{{
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {'e', {0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
}};

// Inferno (matplotlib, by Smith and van der Walt), 10 evenly spaced sRGB stops.
constexpr std::array<std::uint32_t, 10> kInferno{0x000004, 0x1B0C42, 0x4B0C6B, 0x781C6D, 0xA52C60,
                                                 0xCF4446, 0xED6925, 0xFB9A06, 0xF7D13D, 0xFCFFA4};

struct Rgb {
    float r = 0, g = 0, b = 0;
};

Rgb linearFromSrgb(float r, float g, float b) {
    return {srgbToLinear(r), srgbToLinear(g), srgbToLinear(b)};
}

const Rgb kNonFinite{0.0f, 1.0f, 1.0f}; // cyan: not in inferno
const Rgb kCropOutline{0.0f, 1.0f, 0.0f};
const Rgb kBackground = linearFromSrgb(0.12f, 0.12f, 0.12f);
const Rgb kForeground = linearFromSrgb(0.92f, 0.92f, 0.92f);

// t in [0, 1] -> linear RGB; interpolated between the sRGB stops.
Rgb inferno(double t) {
    t = std::clamp(t, 0.0, 1.0) * double(kInferno.size() - 1);
    std::size_t i = std::min(std::size_t(t), kInferno.size() - 2);
    float f = float(t - double(i));
    auto channel = [&](int shift) {
        float a = float((kInferno[i] >> shift) & 0xFF) / 255.0f;
        float b = float((kInferno[i + 1] >> shift) & 0xFF) / 255.0f;
        return a + (b - a) * f;
    };
    return linearFromSrgb(channel(16), channel(8), channel(0));
}

void setPixel(Image& img, int x, int y, const Rgb& c) {
    if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
    float* p = img.at(x, y);
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
}

void fillRect(Image& img, int x0, int y0, int x1, int y1, const Rgb& c) {
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) setPixel(img, x, y, c);
}

// Draws `text` with its top-left corner at (x, y), each font pixel `scale` pixels wide.
void drawText(Image& img, int x, int y, const std::string& text, int scale, const Rgb& c) {
    for (char ch : text) {
        for (const Glyph& g : kFont) {
            if (g.c != ch) continue;
            for (int row = 0; row < 7; ++row)
                for (int col = 0; col < 5; ++col)
                    if (g.rows[row] & (0x10 >> col))
                        fillRect(img, x + col * scale, y + row * scale, x + (col + 1) * scale,
                                 y + (row + 1) * scale, c);
        }
        x += 6 * scale;
    }
}

// Position of an error on the colour bar: 0 at lo, 1 at hi, clamped; NaN for non-finite errors.
double normalised(double v, const HeatmapRange& r, HeatmapScale scale) {
    if (!std::isfinite(v)) return std::nan("");
    if (scale == HeatmapScale::Log) {
        if (v <= 0) return 0.0;
        return std::clamp(
            (std::log10(v) - std::log10(r.lo)) / (std::log10(r.hi) - std::log10(r.lo)), 0.0, 1.0);
    }
    return std::clamp((v - r.lo) / (r.hi - r.lo), 0.0, 1.0);
}

// 1, 2 or 5 times a power of ten, >= v.
double niceCeil(double v) {
    double p = std::pow(10.0, std::floor(std::log10(v)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * p >= v * (1 - 1e-12)) return m * p;
    return 10 * p;
}

// Legend geometry at font scale s: margins, bar, ticks, label column.
struct Legend {
    int scale = 1, panelX = 0, panelWidth = 0, height = 0;
    int barX = 0, barWidth = 0, barTop = 0, barBottom = 0, labelX = 0;
    std::vector<std::pair<double, std::string>> ticks; // value, label
};

std::vector<double> tickCandidates(const HeatmapRange& r, HeatmapScale scale) {
    // Ends first, so they win when labels would overlap.
    std::vector<double> c{r.hi, r.lo};
    if (scale == HeatmapScale::Log) {
        int top = int(std::floor(std::log10(r.hi) + 1e-9));
        int bottom = int(std::ceil(std::log10(r.lo) - 1e-9));
        // Every decade, or every n-th past six of them; overlapping labels are dropped later.
        int decades = top - bottom;
        int step = std::max(1, (decades + 5) / 6);
        for (int d = top; d >= bottom; d -= step) c.push_back(std::pow(10.0, d));
    } else {
        for (int i = 1; i < 4; ++i) c.push_back(r.lo + (r.hi - r.lo) * i / 4.0);
    }
    return c;
}

Legend layoutLegend(int width, int height, const HeatmapRange* range, HeatmapScale scale) {
    Legend g;
    g.height = std::max(height, kMinPanelHeight);
    g.scale = std::clamp(g.height / 240, 1, 4);
    int s = g.scale;
    g.panelX = width;
    g.barX = width + 4 * s;
    g.barWidth = 8 * s;
    g.barTop = 4 * s + 4 * s;
    g.barBottom = g.height - 4 * s - 4 * s;
    g.labelX = g.barX + g.barWidth + 3 * s + 2 * s;
    // Room for 7-character labels whatever the range, so the size is known before the range.
    g.panelWidth = (g.labelX - width) + kLabelChars * 6 * s - s + 4 * s;
    if (range) {
        int minGap = 7 * s + 3 * s;
        for (double v : tickCandidates(*range, scale)) {
            double t = normalised(v, *range, scale);
            if (std::isnan(t)) continue;
            bool fits = true;
            for (auto& [u, label] : g.ticks)
                fits &=
                    std::abs(normalised(u, *range, scale) - t) * double(g.barBottom - g.barTop) >=
                    minGap;
            if (fits) g.ticks.emplace_back(v, heatmapTickLabel(v));
        }
    }
    return g;
}

void drawLegend(Image& out, const Legend& g, const HeatmapRange& r, HeatmapScale scale) {
    int s = g.scale;
    fillRect(out, g.panelX, 0, out.width, out.height, kBackground);
    // Frame, then the colour bar: hi at the top.
    fillRect(out, g.barX - 1, g.barTop - 1, g.barX + g.barWidth + 1, g.barBottom + 1, kForeground);
    for (int y = g.barTop; y < g.barBottom; ++y) {
        double t = double(g.barBottom - 1 - y) / double(std::max(1, g.barBottom - g.barTop - 1));
        fillRect(out, g.barX, y, g.barX + g.barWidth, y + 1, inferno(t));
    }
    for (auto& [v, label] : g.ticks) {
        double t = normalised(v, r, scale);
        int y = g.barBottom - 1 - int(std::lround(t * double(g.barBottom - g.barTop - 1)));
        fillRect(out, g.barX + g.barWidth, y, g.barX + g.barWidth + 3 * s, y + s, kForeground);
        drawText(out, g.labelX, y - (7 * s) / 2, label, s, kForeground);
    }
}

void outlineCrop(Image& out, const CropRect& c, int width, int height) {
    // Just outside the rectangle, so the compared pixels stay visible.
    int x0 = c.x0 - 1, y0 = c.y0 - 1, x1 = c.x1, y1 = c.y1;
    for (int x = std::max(x0, 0); x <= std::min(x1, width - 1); ++x) {
        if (y0 >= 0) setPixel(out, x, y0, kCropOutline);
        if (y1 < height) setPixel(out, x, y1, kCropOutline);
    }
    for (int y = std::max(y0, 0); y <= std::min(y1, height - 1); ++y) {
        if (x0 >= 0) setPixel(out, x0, y, kCropOutline);
        if (x1 < width) setPixel(out, x1, y, kCropOutline);
    }
}

} // namespace

std::vector<double> pixelErrors(const Image& a, const Image& b, HeatmapMetric metric,
                                const Image* relmseDenominator) {
    const Image& den = relmseDenominator ? *relmseDenominator : b;
    std::vector<double> e(std::size_t(a.width) * std::size_t(a.height));
    for (std::size_t i = 0; i < e.size(); ++i) {
        double sum = 0;
        for (std::size_t c = 0; c < 3; ++c) {
            double va = a.pixels[3 * i + c], vb = b.pixels[3 * i + c];
            double vd = den.pixels[3 * i + c];
            double d = va - vb;
            sum += metric == HeatmapMetric::RelMse ? d * d / (vd * vd + 0.01) : std::abs(d);
        }
        e[i] = sum / 3.0;
    }
    return e;
}

HeatmapRange heatmapRange(const std::vector<double>& errors, int width, int height,
                          const HeatmapSettings& s) {
    if (s.hi > 0) {
        HeatmapRange r{s.lo, s.hi};
        if (s.scale == HeatmapScale::Log && !(r.lo > 0)) r.lo = r.hi * 1e-4;
        if (!(r.lo < r.hi)) r.lo = s.scale == HeatmapScale::Log ? r.hi / 10 : 0.0;
        return r;
    }
    CropRect c = s.crop ? *s.crop : CropRect{0, 0, width, height};
    double largest = 0, smallest = INFINITY;
    for (int y = c.y0; y < c.y1; ++y)
        for (int x = c.x0; x < c.x1; ++x) {
            double v = errors[std::size_t(y) * std::size_t(width) + std::size_t(x)];
            if (!std::isfinite(v) || v <= 0) continue;
            largest = std::max(largest, v);
            smallest = std::min(smallest, v);
        }
    if (s.scale == HeatmapScale::Linear) return {0.0, largest > 0 ? niceCeil(largest) : 1.0};
    if (largest <= 0) return {1e-4, 1.0};
    double lo = std::max(smallest, largest * 1e-4);
    int top = int(std::ceil(std::log10(largest) - 1e-9));
    int bottom = int(std::floor(std::log10(lo) + 1e-9));
    if (bottom >= top) bottom = top - 1;
    return {std::pow(10.0, bottom), std::pow(10.0, top)};
}

HeatmapSize heatmapSize(int width, int height, const HeatmapSettings& s) {
    if (!s.legend) return {width, height};
    Legend g = layoutLegend(width, height, nullptr, s.scale);
    return {width + g.panelWidth, g.height};
}

Image renderHeatmap(const Image& a, const Image& b, const HeatmapSettings& s) {
    // Validates the sizes and the crop with the metrics' messages.
    compareImages(a, b, s.crop, s.relmseDenominator);
    std::vector<double> errors = pixelErrors(a, b, s.metric, s.relmseDenominator);
    HeatmapRange range = heatmapRange(errors, a.width, a.height, s);
    HeatmapSize size = heatmapSize(a.width, a.height, s);
    Image out(size.width, size.height);
    fillRect(out, 0, 0, out.width, out.height, kBackground);
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            double t = normalised(errors[std::size_t(y) * std::size_t(a.width) + std::size_t(x)],
                                  range, s.scale);
            setPixel(out, x, y, std::isnan(t) ? kNonFinite : inferno(t));
        }
    if (s.crop) outlineCrop(out, *s.crop, a.width, a.height);
    if (s.legend) drawLegend(out, layoutLegend(a.width, a.height, &range, s.scale), range, s.scale);
    return out;
}

Image differenceImage(const Image& a, const Image& b, float scale, std::size_t* clamped) {
    compareImages(a, b);
    Image out(a.width, a.height);
    constexpr double kLargest = std::numeric_limits<float>::max();
    std::size_t n = 0;
    for (std::size_t i = 0; i < out.pixels.size(); ++i) {
        // In double: a finite difference times a large scale must not become Inf (or NaN
        // where the difference is 0 and the scale has overflowed).
        double d = std::abs(double(a.pixels[i]) - double(b.pixels[i])) * double(scale);
        if (std::isfinite(d) && d > kLargest) {
            d = kLargest;
            ++n;
        }
        out.pixels[i] = float(d);
    }
    if (clamped) *clamped = n;
    return out;
}

std::string heatmapTickLabel(double v) {
    if (v == 0) return "0";
    char buf[32];
    int e = int(std::floor(std::log10(std::abs(v)) + 1e-9));
    if (e >= -3 && e <= 3) {
        // Up to 3 significant digits, never in exponent form: 0.001, 0.25, 1000.
        std::snprintf(buf, sizeof buf, "%.*f", std::max(0, 2 - e), v);
        std::string t = buf;
        if (t.find('.') != std::string::npos) {
            while (t.back() == '0') t.pop_back();
            if (t.back() == '.') t.pop_back();
        }
        return t;
    }
    std::snprintf(buf, sizeof buf, "%.2g", v);
    // "1e-05" -> "1e-5", "2.5e+04" -> "2.5e+4".
    std::string t = buf;
    std::size_t p = t.find('e');
    if (p != std::string::npos && p + 2 < t.size()) {
        std::size_t digits = p + 2;
        while (digits + 1 < t.size() && t[digits] == '0') t.erase(digits, 1);
    }
    return t;
}

} // namespace rayproc
