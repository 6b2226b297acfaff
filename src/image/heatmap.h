// Pictures of the error between a test image and its reference, for `rayproc diff`: the
// difference image (per-channel |a - b|, scaled) and a false-colour heatmap of the per-pixel
// error with a colour bar and tick labels drawn into the picture (a built-in 5x7 bitmap font).
//
// The per-pixel errors are the summands of the metrics in metrics.h, so the heatmap's mean over
// the compared region is the printed figure: `relmse` maps (a - b)^2 / (b^2 + 0.01) averaged
// over the channels (mean = relMSE), `abs` maps |a - b| averaged over the channels (mean = MAE).
// See docs/image-comparison.md.
#pragma once

#include "image/image.h"
#include "image/metrics.h"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace rayproc {

enum class HeatmapMetric { RelMse, Abs };
enum class HeatmapScale { Log, Linear };

struct HeatmapSettings {
    HeatmapMetric metric = HeatmapMetric::RelMse;
    HeatmapScale scale = HeatmapScale::Log;
    // Errors mapped to the bottom and top of the colour bar; values outside take the end
    // colours. hi <= 0: automatic (see heatmapRange).
    double lo = 0, hi = 0;
    bool legend = true;           // false: exactly the image's size, no colour bar
    std::optional<CropRect> crop; // outlined in green; the automatic range looks only inside it
    // The relmse metric's b from this image (the test's size) instead of the reference, as
    // compareImages' relmseDenominator; not owned.
    const Image* relmseDenominator = nullptr;
};

// The colour range a heatmap uses.
struct HeatmapRange {
    double lo = 0, hi = 1;
};

// Per-pixel error of `test` against `reference` (same size), row-major, width * height values;
// relmse's b from relmseDenominator when given (the same size too).
// Non-finite inputs give a non-finite error.
std::vector<double> pixelErrors(const Image& test, const Image& reference, HeatmapMetric metric,
                                const Image* relmseDenominator = nullptr);

// The settings' range, or the automatic one from the finite errors inside the crop: log scale:
// [max(smallest positive, largest / 1e4), largest] widened to whole decades; linear scale:
// [0, largest] with the top rounded up to 1, 2 or 5 times a power of ten. Never empty.
HeatmapRange heatmapRange(const std::vector<double>& errors, int width, int height,
                          const HeatmapSettings& settings);

// Pixel size of the heatmap of a width x height image: the image plus, with the legend, a panel
// on its right holding the colour bar; the panel is at least 96 pixels tall.
struct HeatmapSize {
    int width = 0, height = 0;
};
HeatmapSize heatmapSize(int width, int height, const HeatmapSettings& settings);

// The false-colour heatmap (colour map: inferno; black = no error; NaN or Inf: cyan). Pixels are
// linear RGB, so writeImage to PNG reproduces the colour map's sRGB values exactly. Throws
// ImageIoError on a size mismatch or a crop outside the image.
Image renderHeatmap(const Image& test, const Image& reference, const HeatmapSettings& settings);

// Per-channel |test - reference| * scale, linear; the paper's difference image. Computed in
// double: a value beyond float's range is clamped to the largest float and counted in
// `clamped` (optional); a non-finite input pixel stays non-finite.
Image differenceImage(const Image& test, const Image& reference, float scale = 1.0f,
                      std::size_t* clamped = nullptr);

// The label printed at a tick of the colour bar ("0.01", "1e-5", "2.5e+4"): only the characters
// the built-in font has (0-9 . e - +).
std::string heatmapTickLabel(double value);

} // namespace rayproc
