#include "bench/summary.h"

#include "bench/curve.h"
#include "bench/machine_info.h"
#include "bench/mode_curves.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace rayproc::bench {

namespace {

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}
std::string secs(double s) {
    return fmt("%.3g s", s);
}
std::string err(double e) {
    return fmt("%.3g", e);
}

std::string timeCell(const ModeCurve& c, double target) {
    CurveReading r = timeToReach(c.envelope, target);
    switch (r.kind) {
    case Reading::Interpolated: return secs(r.value);
    case Reading::BeforeFirst: return "≤ " + secs(r.value) + " (first render)";
    case Reading::AfterLast:
        return "not reached (best " + err(r.value) + " at " + secs(c.envelope.back().seconds) + ")";
    case Reading::NoData: break;
    }
    return "–";
}

std::string errorCell(const ModeCurve& c, double seconds) {
    CurveReading r = errorAtTime(c.envelope, seconds);
    switch (r.kind) {
    case Reading::Interpolated: return err(r.value);
    case Reading::BeforeFirst: return "– (fastest render " + secs(r.value) + ")";
    case Reading::AfterLast:
        return "not measured (" + err(r.value) + " at " + secs(c.envelope.back().seconds) + ")";
    case Reading::NoData: break;
    }
    return "–";
}

std::string modeLabel(const ModeCurve& c) {
    std::string label = c.mode;
    if (c.variants.size() > 1) label += " (best of " + std::to_string(c.variants.size()) + " settings)";
    else if (!c.variants.front().empty()) label += " (" + c.variants.front() + ")";
    if (c.peer) label += ", peer";
    return label;
}

} // namespace

std::string plotFileName(const std::string& scene) {
    return scene + ".svg";
}

std::vector<double> equalTimePoints(const std::vector<BenchRow>& rows, const std::string& scene) {
    std::vector<ModeCurve> curves = modeCurves(rows, scene);
    double lo = INFINITY, hi = 0;
    for (const ModeCurve& c : curves)
        if (!c.envelope.empty()) {
            lo = std::min(lo, c.envelope.front().seconds);
            hi = std::max(hi, c.envelope.back().seconds);
        }
    if (!(lo <= hi)) return {};
    // Candidates 1, 2, 5 times a power of ten; each scored by the modes measured at it.
    std::vector<std::pair<double, int>> candidates;
    for (int e = int(std::floor(std::log10(lo))); e <= int(std::ceil(std::log10(hi))); ++e)
        for (double m : {1.0, 2.0, 5.0}) {
            double t = m * std::pow(10.0, e);
            int spanning = 0;
            for (const ModeCurve& c : curves)
                spanning += errorAtTime(c.envelope, t).kind == Reading::Interpolated;
            if (spanning >= 2) candidates.push_back({t, spanning});
        }
    // The most comparable times first (more modes, then later times), at most kMaxColumns of
    // them, shown in time order.
    constexpr std::size_t kMaxColumns = 5;
    std::stable_sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) {
        return a.second != b.second ? a.second > b.second : a.first > b.first;
    });
    if (candidates.size() > kMaxColumns) candidates.resize(kMaxColumns);
    std::vector<double> times;
    for (const auto& c : candidates) times.push_back(c.first);
    std::sort(times.begin(), times.end());
    return times;
}

namespace {

// When, where and how the run was made.
void writeRunLines(std::ostringstream& o, const SummaryContext& ctx) {
    o << "- Command: `" << ctx.commandLine << "`\n";
    if (ctx.regenerated)
        o << "- This report was regenerated on " << ctx.started
          << " from an existing results.csv (and peer CSVs): when, on which machine and under "
             "which load its renders ran is not recorded there.\n";
    else
        o << "- Started " << ctx.started << ", took " << secs(ctx.totalSeconds)
          << " (references included when they were rendered).\n"
          << "- Machine: " << hardwareThreads() << " hardware threads, " << cpuModel()
          << "; engine threads: " << (ctx.threads > 0 ? std::to_string(ctx.threads) : "all")
          << ". Load average (1 min) " << ctx.loadAtStart << " at the start, " << ctx.loadAtEnd
          << " at the end: on a shared machine the times are indicative only; compare modes "
             "within one run.\n";
}

// What the times count and what each mode rendered: time-limited progressive renders, or
// spp ladders and gi's settings sweep.
void writeBudgets(std::ostringstream& o, const std::vector<BenchRow>& rows,
                  const SummaryContext& ctx) {
    const BenchSuite& suite = *ctx.suite;
    const bool progressive = std::any_of(rows.begin(), rows.end(), isProgressiveRow);
    if (progressive) {
        o << " Times are seconds from the start of the mode's work to the end of a pass: for gi "
             "the photon passes, precomputed irradiance and irradiance-cache prepass included; "
             "scene loading, the BVH build and the error measurements excluded. Seed 1.\n"
          << "- Budgets (`--progressive`): each mode renders once with its defaults (gi: "
          << suite.giVariants.front().gatherRays << " gather rays, IC accuracy "
          << suite.giVariants.front().icAccuracy << ", " << suite.giVariants.front().photons
          << " global photons per round, the caustic map's default), in passes of 1 spp until "
             "its time limit (the settings' `time-limit`), and its error is measured after "
             "every pass: each point of a curve is one pass of one render, as a user's "
             "time-limited render would show it. A curve is the render's lower envelope (the "
             "best error reached by each time).\n";
        return;
    }
    o << " Times are the wall time of one mode driver call, from the start of the mode's "
         "work to the finished image: for gi the photon passes, precomputed irradiance and "
         "irradiance-cache prepass included; scene loading and the BVH build excluded. One "
         "render per budget, seed 1.\n"
      << "- Budgets: each mode's spp ladder";
    for (const ModeLadder& l : suite.ladders) {
        o << "; " << l.mode << " ";
        for (std::size_t i = 0; i < l.spp.size(); ++i) o << (i ? "," : "") << l.spp[i];
    }
    o << ". A ladder stops before a render predicted to take longer than "
      << secs(ctx.timeCapSeconds > 0 ? ctx.timeCapSeconds : suite.timeCapSeconds) << ".\n"
      << "- gi settings swept (gather rays, IC accuracy a, global photons per round; "
         "caustic photons gi's default):";
    for (const GiVariant& v : suite.giVariants)
        o << " (" << v.gatherRays << ", " << v.icAccuracy << ", " << v.photons << ")";
    o << ". gi's curve is the lower envelope: at each time, the best of these.\n";
}

// Each scene's resolutions and where its reference came from; `size` is the common render
// size ("" if the scenes differ: then a column says each one's).
void writeSceneTable(std::ostringstream& o, const SummaryContext& ctx, const std::string& size) {
    if (size.empty())
        o << "\n| scene | file's resolution | rendered at | reference |\n|---|---|---|---|\n";
    else
        o << "\n| scene | file's resolution | reference |\n|---|---|---|\n";
    for (const SceneInfo& s : ctx.scenes) {
        o << "| " << s.name << " | " << s.nativeWidth << "x" << s.nativeHeight << " | ";
        if (size.empty()) o << s.width << "x" << s.height << " | ";
        switch (s.referenceSource) {
        case ReferenceSource::Cache:
            o << (s.referenceSpectral ? "path (spectral), " : "path, ") << s.referenceSpp
              << " spp, its own seed ("
              << (s.referenceRendered ? "rendered in this run, " + secs(s.referenceSeconds)
                                      : std::string("cached"))
              << ")";
            break;
        case ReferenceSource::Shipped:
            o << "shipped golden image `" << s.referencePath << "` (path, " << s.referenceSpp
              << " spp, its own seed)";
            break;
        case ReferenceSource::Given: o << "given: `" << s.referencePath << "`"; break;
        }
        o << " |\n";
    }
}

// One table: a row per mode, a column per value of `columns` (header cells by `header`, body
// cells by `cell`).
template <typename Header, typename Cell>
void writeModeTable(std::ostringstream& o, const std::vector<ModeCurve>& curves,
                    const std::vector<double>& columns, Header header, Cell cell) {
    o << "| mode |";
    for (double t : columns) o << " " << header(t) << " |";
    o << "\n|---|";
    for (std::size_t i = 0; i < columns.size(); ++i) o << "---|";
    o << "\n";
    for (const ModeCurve& c : curves) {
        o << "| " << modeLabel(c) << " |";
        for (double t : columns) o << " " << cell(c, t) << " |";
        o << "\n";
    }
}

// A scene's plot, its time-to-error and error-at-time tables and gi's envelopes.
void writeSceneSection(std::ostringstream& o, const std::vector<BenchRow>& rows,
                       const std::string& scene, const std::vector<double>& targets) {
    std::vector<ModeCurve> curves = modeCurves(rows, scene);
    o << "\n## " << scene << "\n\n![" << scene << ": relMSE against time](" << plotFileName(scene)
      << ")\n\n### Time to reach a relMSE\n\n";
    writeModeTable(o, curves, targets,
                   [](double t) {
                       std::ostringstream h;
                       h << "relMSE " << t;
                       return h.str();
                   },
                   timeCell);
    std::vector<double> times = equalTimePoints(rows, scene);
    o << "\n### relMSE at equal time\n\n";
    if (times.empty())
        o << "No time (1, 2 or 5 times a power of ten seconds) lies inside the measured "
             "span of two modes.\n";
    else
        writeModeTable(o, curves, times, secs, errorCell);
    for (const ModeCurve& c : curves) {
        if (c.variants.size() < 2) continue;
        o << "\n### " << c.mode << ": the best setting at each time (the envelope)\n\n"
          << "| seconds | relMSE | settings |\n|---|---|---|\n";
        for (const CurvePoint& p : c.envelope)
            o << "| " << secs(p.seconds) << " | " << err(p.relmse) << " | `"
              << c.rows[std::size_t(p.tag)].settings << "` |\n";
    }
}

} // namespace

std::string renderSummary(const std::vector<BenchRow>& rows, const SummaryContext& ctx) {
    const BenchSuite& suite = *ctx.suite;
    std::ostringstream o;
    o << "# rayproc bench: suite `" << suite.name << "`\n\n";
    if (ctx.interrupted)
        o << "**Interrupted (Ctrl-C): the tables hold only the renders that completed.**\n\n";
    writeRunLines(o, ctx);
    const std::string size = commonRenderSize(ctx.scenes, suite);
    if (!size.empty())
        o << "- Every scene rendered at **" << size
          << "** (the scene files' own resolutions are overridden; see the table below).";
    else
        o << "- Each scene rendered at its own size, the table's *rendered at* (the scene files' "
             "own resolutions are overridden).";
    writeBudgets(o, rows, ctx);
    o << "- Error: relMSE (docs/image-comparison.md) against the reference. Readings between "
         "renders are log-log interpolations; nothing is extrapolated.\n";
    for (const std::string& peer : ctx.peerCsvs) o << "- Peer results from `" << peer << "`.\n";
    writeSceneTable(o, ctx, size);
    for (const std::string& scene : sceneNames(rows))
        writeSceneSection(o, rows, scene, suite.summaryTargets);
    if (rows.empty()) o << "\nNo render completed.\n";
    o << "\nEvery render: `results.csv` (scene, mode, settings, seconds, rays, relmse, rmse).\n";
    return o.str();
}

} // namespace rayproc::bench
