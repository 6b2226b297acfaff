// `rayproc diff A B`: compares a test image A with a reference B (error metrics of
// image/metrics.h, a difference image, an error heatmap) and gates on limits, so scripts and CI
// can check a render against a reference. Exit status: 0 within limits, 1 a limit exceeded,
// 2 an error (every error, its usage errors included; see main.cpp).
#include "cli/commands.h"
#include "cli/output_paths.h"
#include "core/error.h"
#include "image/heatmap.h"
#include "image/image.h"
#include "image/metrics.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <vector>

namespace rayproc::cli {

namespace {

constexpr int kExitWithinLimits = 0;
constexpr int kExitLimitExceeded = 1;
constexpr int kExitError = 2;

struct DiffArgs {
    std::string test, reference;
    std::string relmseDenominator; // --relmse-denominator: relMSE's b from this image
    std::string output, heatmap;
    float scale = 1.0f;
    std::string heatmapMetric = "relmse";
    std::string heatmapScale = "log";
    std::vector<double> heatmapRange;
    bool noLegend = false;
    std::vector<int> crop;
    double maxRelmse = 0, maxRmse = 0;
    bool hasMaxRelmse = false, hasMaxRmse = false;
    bool json = false;
};

// A limit that is not met; NaN metrics (NaN in an input) never pass.
struct Exceeded {
    std::string metric, option;
    double value, limit;
};

// Fails before reading or comparing anything: an output that cannot be written is known early.
std::optional<CropRect> cropOf(const DiffArgs& a) {
    if (a.crop.empty()) return std::nullopt;
    return CropRect{a.crop[0], a.crop[1], a.crop[2], a.crop[3]};
}

HeatmapSettings heatmapSettings(const DiffArgs& a) {
    HeatmapSettings s;
    s.metric = a.heatmapMetric == "abs" ? HeatmapMetric::Abs : HeatmapMetric::RelMse;
    s.scale = a.heatmapScale == "linear" ? HeatmapScale::Linear : HeatmapScale::Log;
    if (a.heatmapRange.size() == 2) {
        s.lo = a.heatmapRange[0];
        s.hi = a.heatmapRange[1];
        if (!(s.hi > s.lo) || s.lo < 0 || (s.scale == HeatmapScale::Log && s.lo <= 0))
            throw ImageIoError("--heatmap-range " + std::to_string(s.lo) + " " +
                               std::to_string(s.hi) +
                               ": needs 0 <= LO < HI (LO > 0 on the log scale)");
    }
    s.legend = !a.noLegend;
    s.crop = cropOf(a);
    return s;
}

std::string formatNumber(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

// JSON has no infinity: psnr of identical images (and any NaN) becomes null.
nlohmann::ordered_json jsonNumber(double v) {
    if (!std::isfinite(v)) return nullptr;
    return v;
}

void printText(const DiffArgs& a, const Image& img, const ImageMetrics& m, int factor) {
    std::printf("size     %dx%d\n", img.width, img.height);
    if (factor > 1) std::printf("reference box-downsampled by %d\n", factor);
    if (auto c = cropOf(a)) std::printf("crop     %d %d %d %d\n", c->x0, c->y0, c->x1, c->y1);
    std::printf("pixels   %zu\n", m.pixels);
    std::printf("rmse     %s\n", formatNumber(m.rmse).c_str());
    if (a.relmseDenominator.empty())
        std::printf("relmse   %s\n", formatNumber(m.relmse).c_str());
    else
        std::printf("relmse   %s (denominators from %s)\n", formatNumber(m.relmse).c_str(),
                    a.relmseDenominator.c_str());
    std::printf("psnr     %s dB\n", formatNumber(m.psnr).c_str());
    std::printf("mae      %s\n", formatNumber(m.mae).c_str());
    std::printf("max_abs  %s\n", formatNumber(m.maxAbs).c_str());
    std::printf("mean_rel %s (R %s, G %s, B %s)\n", formatNumber(m.meanRel).c_str(),
                formatNumber(m.meanRelRgb[0]).c_str(), formatNumber(m.meanRelRgb[1]).c_str(),
                formatNumber(m.meanRelRgb[2]).c_str());
    std::printf("block_rel %s (%zu blocks of %dx%d, %zu near-black skipped)\n",
                formatNumber(m.blockRel).c_str(), m.blocks, kMetricBlock, kMetricBlock,
                m.blocksSkipped);
    if (m.referenceNonFinite > 0)
        std::printf("skipped  %zu pixels with a non-finite reference\n", m.referenceNonFinite);
}

void printJson(const DiffArgs& a, const Image& img, const ImageMetrics& m, int factor,
               const std::vector<Exceeded>& exceeded) {
    nlohmann::ordered_json j;
    j["test"] = a.test;
    j["reference"] = a.reference;
    if (!a.relmseDenominator.empty()) j["relmse_denominator"] = a.relmseDenominator;
    j["width"] = img.width;
    j["height"] = img.height;
    if (auto c = cropOf(a)) j["crop"] = {c->x0, c->y0, c->x1, c->y1};
    j["pixels"] = m.pixels;
    j["rmse"] = jsonNumber(m.rmse);
    j["relmse"] = jsonNumber(m.relmse);
    j["psnr"] = jsonNumber(m.psnr);
    j["mae"] = jsonNumber(m.mae);
    j["max_abs"] = jsonNumber(m.maxAbs);
    j["mean_rel"] = jsonNumber(m.meanRel);
    j["mean_rel_rgb"] = {jsonNumber(m.meanRelRgb[0]), jsonNumber(m.meanRelRgb[1]),
                         jsonNumber(m.meanRelRgb[2])};
    j["block_rel"] = jsonNumber(m.blockRel);
    j["blocks"] = m.blocks;
    j["blocks_skipped"] = m.blocksSkipped;
    j["reference_nonfinite"] = m.referenceNonFinite;
    j["reference_downsample"] = factor;
    j["exceeded"] = nlohmann::ordered_json::array();
    for (const Exceeded& e : exceeded) j["exceeded"].push_back(e.metric);
    // A file name need not be UTF-8 (Linux allows any bytes): its invalid bytes print as
    // U+FFFD, so the output stays JSON (nlohmann's dump would throw type_error 316).
    std::printf("%s\n",
                j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace).c_str());
}

// Reads an image to compare with `test`: its size, or an integer multiple of it (a
// full-resolution reference for a fraction-resolution render), box-downsampled to the test's
// size; `factor` receives the multiple. `label` names it in the error ("the reference").
Image readAtTestSize(const std::string& label, const std::string& path, const Image& test,
                     const std::string& testPath, int& factor) {
    Image image = readImage(path);
    factor = downsampleFactor(test, image);
    if (factor == 0)
        throw ImageIoError("cannot compare images of different sizes: " + testPath + " is " +
                           std::to_string(test.width) + "x" + std::to_string(test.height) + ", " +
                           label + " " + path + " is " + std::to_string(image.width) + "x" +
                           std::to_string(image.height) +
                           " (not an integer multiple of the test's size)");
    return factor > 1 ? boxDownsample(image, factor) : image;
}

int runDiff(const DiffArgs& a) {
    if (!a.output.empty()) imageFormatFromPath(a.output); // throws for an unknown extension
    if (!a.heatmap.empty()) imageFormatFromPath(a.heatmap);
    checkDistinctFiles({{"test", a.test, false},
                        {"reference", a.reference, false},
                        {"--relmse-denominator", a.relmseDenominator, false},
                        {"-o", a.output, true},
                        {"--heatmap", a.heatmap, true}});
    checkOutputFile("-o", a.output);
    checkOutputFile("--heatmap", a.heatmap);
    HeatmapSettings hs = heatmapSettings(a);

    Image test = readImage(a.test);
    int factor = 1, denominatorFactor = 1;
    Image reference = readAtTestSize("the reference", a.reference, test, a.test, factor);
    nonFiniteReferencePixels(reference, a.reference); // none finite: nothing to compare
    std::optional<Image> denominator;
    if (!a.relmseDenominator.empty())
        denominator = readAtTestSize("--relmse-denominator", a.relmseDenominator, test, a.test,
                                     denominatorFactor);
    const Image* relmseB = denominator ? &*denominator : nullptr;
    ImageMetrics m = compareImages(test, reference, cropOf(a), relmseB); // throws for a bad crop

    if (!a.output.empty()) {
        std::size_t clamped = 0;
        writeImage(a.output, differenceImage(test, reference, a.scale, &clamped));
        if (clamped > 0)
            std::fprintf(stderr,
                         "rayproc: warning: %zu values of the difference image times --scale %g "
                         "exceed float's range; clamped to %g\n",
                         clamped, double(a.scale), double(std::numeric_limits<float>::max()));
    }
    hs.relmseDenominator = relmseB;
    if (!a.heatmap.empty()) writeImage(a.heatmap, renderHeatmap(test, reference, hs));

    std::vector<Exceeded> exceeded;
    if (a.hasMaxRelmse && !(m.relmse <= a.maxRelmse))
        exceeded.push_back({"relmse", "--max-relmse", m.relmse, a.maxRelmse});
    if (a.hasMaxRmse && !(m.rmse <= a.maxRmse))
        exceeded.push_back({"rmse", "--max-rmse", m.rmse, a.maxRmse});

    if (a.json)
        printJson(a, test, m, factor, exceeded);
    else
        printText(a, test, m, factor);
    for (const Exceeded& e : exceeded)
        std::fprintf(stderr, "rayproc diff: %s %s exceeds %s %s\n", e.metric.c_str(),
                     formatNumber(e.value).c_str(), e.option.c_str(),
                     formatNumber(e.limit).c_str());
    return exceeded.empty() ? kExitWithinLimits : kExitLimitExceeded;
}

// The images compared and how the metrics are printed.
void addInputOptions(CLI::App* cmd, DiffArgs& args) {
    cmd->add_option("test", args.test, "Image to check (.png, .exr, .hdr or .pfm)")->required();
    cmd->add_option("reference", args.reference,
                    "Reference image (the metrics' b; e.g. a high-spp path-traced render): the "
                    "test's size, or an integer multiple f of it on both axes, in which case it "
                    "is box-downsampled by f automatically (non-finite pixels left out of each "
                    "average)")
        ->required();
    cmd->add_option("--relmse-denominator", args.relmseDenominator,
                    "Take relMSE's b in (a-b)^2 / (b^2 + 0.01) from this image instead of the "
                    "reference (the test's size or an integer multiple, downsampled like the "
                    "reference), in the relmse heatmap too; the other metrics are unchanged. For "
                    "a render's noise alone: the reference a converged render of the same mode, "
                    "the denominator the true (e.g. path-traced) reference")
        ->type_name("IMAGE");
    cmd->add_flag("--json", args.json,
                  "Print the metrics as JSON: width, height, pixels, rmse, relmse, psnr (null "
                  "when the images are equal), mae, max_abs, mean_rel, mean_rel_rgb (signed, "
                  "per channel), block_rel, blocks, blocks_skipped, reference_nonfinite, "
                  "reference_downsample, exceeded (names of failed limits)");
}

// The difference image.
void addDifferenceImageOptions(CLI::App* cmd, DiffArgs& args) {
    cmd->add_option("-o,--output", args.output,
                    "Write the difference image |test - reference| per channel, times --scale "
                    "(.pfm/.exr/.hdr: linear values; .png: clamped to 1, sRGB-encoded)");
    cmd->add_option("--scale", args.scale,
                    "Multiply the difference image by this factor (default 1; values beyond "
                    "float's range are clamped to 3.4e38, with a warning)")
        ->check(finiteFloat())
        ->check(CLI::PositiveNumber);
}

// The error heatmap: its metric, scale, range and legend.
void addHeatmapOptions(CLI::App* cmd, DiffArgs& args) {
    cmd->add_option("--heatmap", args.heatmap,
                    "Write a false-colour map of the per-pixel error (inferno: black = none; "
                    "cyan = NaN/Inf) with a colour bar and tick labels on its right")
        ->type_name("FILE");
    cmd->add_option("--heatmap-metric", args.heatmapMetric,
                    "Per-pixel error the heatmap shows: relmse (default; (a-b)^2/(b^2+0.01) "
                    "averaged over R, G, B) or abs (|a-b| averaged over R, G, B)")
        ->check(CLI::IsMember({"relmse", "abs"}));
    cmd->add_option("--heatmap-scale", args.heatmapScale,
                    "Colour scale: log (default; from the largest error down at most 4 decades, "
                    "widened to whole decades) or linear (0 to the largest error, rounded up "
                    "to 1, 2 or 5 x 10^k)")
        ->check(finiteNumber())
        ->check(CLI::IsMember({"log", "linear"}));
    cmd->add_option("--heatmap-range", args.heatmapRange,
                    "Fixed colour range LO HI (0 <= LO < HI; LO > 0 on the log scale) instead "
                    "of the automatic one, so heatmaps of several renders compare; errors "
                    "outside take the end colours")
        ->check(finiteNumber())
        ->expected(2)
        ->type_name("FLOAT");
    cmd->add_flag("--no-legend", args.noLegend,
                  "Heatmap without the colour bar: exactly the images' size");
}

} // namespace

std::function<int()> addDiffCommand(CLI::App& app) {
    auto args = std::make_shared<DiffArgs>();
    CLI::App* cmd = app.add_subcommand(
        "diff", "Compare an image with a reference: RMSE, relMSE, PSNR, mean and maximum "
                "absolute difference; optionally a difference image and an error heatmap");
    addInputOptions(cmd, *args);
    addDifferenceImageOptions(cmd, *args);
    addHeatmapOptions(cmd, *args);
    cmd->add_option("--crop", args->crop,
                    "Compare only the pixels X0 <= x < X1, Y0 <= y < Y1 (top-left origin); the "
                    "difference image still covers the whole image, the heatmap outlines the "
                    "region in green and takes its automatic range from it")
        ->expected(4)
        ->type_name("INT");
    CLI::Option* maxRelmse =
        cmd->add_option("--max-relmse", args->maxRelmse,
                        "Exit with status 1 if relMSE exceeds this (or is NaN)")
        ->check(finiteNumber())
            ->check(CLI::NonNegativeNumber);
    CLI::Option* maxRmse = cmd->add_option("--max-rmse", args->maxRmse,
                                           "Exit with status 1 if RMSE exceeds this (or is NaN)")
        ->check(finiteNumber())
                               ->check(CLI::NonNegativeNumber);
    cmd->footer("Metrics (over pixels and R, G, B of the compared region; b = reference): "
                "rmse = sqrt(mean (a-b)^2); relmse = mean (a-b)^2 / (b^2 + 0.01) (b there from "
                "--relmse-denominator when given); "
                "psnr = 10 log10(1 / mean (a-b)^2) dB, peak 1, inf when equal; "
                "mae = mean |a-b|; max_abs = max |a-b|; mean_rel = max over R, G, B of "
                "|mean a - mean b| / mean b; block_rel = mean over 32x32 blocks of |A-B| / B "
                "(A, B the block averages over pixels and channels; blocks with B below 1e-3 "
                "of the image mean skipped). Pixels with a non-finite reference are left out "
                "of every metric. PNG inputs are decoded to linear.\n"
                "Exit status: 0 within the limits, 1 a limit exceeded (named on stderr), "
                "2 error (missing or unreadable file, different sizes, bad crop or option).\n"
                "See docs/image-comparison.md.");
    return [args, maxRelmse, maxRmse] {
        args->hasMaxRelmse = maxRelmse->count() > 0;
        args->hasMaxRmse = maxRmse->count() > 0;
        // Errors end here, not in main(): diff reserves status 1 for "limit exceeded".
        try {
            return runDiff(*args);
        } catch (const ImageIoError& e) {
            printError(e.what());
        } catch (const InputError& e) {
            printError(e.what());
        } catch (const std::bad_alloc&) {
            printError("out of memory");
        } catch (const std::exception& e) {
            printError(std::string("error: ") + e.what());
        }
        return kExitError;
    };
}

} // namespace rayproc::cli
