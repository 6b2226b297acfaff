#include "bench/runner.h"

#include "bench/bench_render.h"
#include "core/error.h"
#include "engine/cancel.h"
#include "image/image.h"
#include "image/metrics.h"
#include "scene/scene_loader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace rayproc::bench {

namespace {

// --progressive renders' spp: more than any time cap allows (passes of 1 spp), as
// `render --time-limit` is run with a large --spp.
constexpr int kProgressiveSpp = 100000;

std::string formatSeconds(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g s", s);
    return buf;
}

// The configurations a mode's ladder runs: one, or one per swept gi setting.
std::vector<RenderConfig> ladderConfigs(const BenchScene& b, const BenchSuite& suite,
                                        const ModeLadder& ladder, const BenchOptions& options) {
    std::vector<RenderConfig> configs;
    RenderConfig base = RenderConfig::forMode(*b.scene, ladder.mode, ladder.spp.front());
    base.engine.threads = options.threads;
    base.engine.spectral = options.spectral;
    if (ladder.mode != "gi") return {base};
    for (const GiVariant& v : suite.giVariants) {
        RenderConfig c = base;
        applyGiVariant(c, v);
        configs.push_back(c);
    }
    return configs;
}

// --reference SPEC (FILE, or NAME=FILE) onto its job: the image read once, the job's size set
// to the image's.
void giveReference(std::vector<SceneJob>& jobs, const std::string& spec) {
    namespace fs = std::filesystem;
    // NAME=FILE, unless the whole argument is a file (a file name may hold '=').
    std::string name, file = spec;
    std::size_t eq = spec.find('=');
    if (eq != std::string::npos && !fs::is_regular_file(spec)) {
        name = spec.substr(0, eq);
        file = spec.substr(eq + 1);
    }
    SceneJob* job = nullptr;
    if (name.empty()) {
        if (jobs.size() != 1)
            throw InputError("--reference " + spec + " is the reference of one scene, but "
                             "the run has " + std::to_string(jobs.size()) +
                             " scenes; pick one with --scene FILE or name it: "
                             "--reference NAME=FILE");
        job = &jobs[0];
    } else {
        std::string names;
        for (SceneJob& j : jobs) {
            if (sceneJobName(j) == name) job = &j;
            names += (names.empty() ? "" : ", ") + sceneJobName(j);
        }
        if (!job)
            throw InputError("--reference " + spec + ": the run has no scene called '" +
                             name + "' (its scenes: " + names + ")");
    }
    if (job->source == ReferenceSource::Given)
        throw InputError("--reference " + spec + ": " + sceneJobName(*job) +
                         " already has a reference (" + job->reference + ")");
    if (!fs::is_regular_file(file))
        throw InputError("--reference " + spec + ": " + file + ": no such file");
    // The scene renders at its reference's size.
    auto image = std::make_shared<const Image>(readImage(file));
    nonFiniteReferencePixels(*image, file); // some left out of the error; none is an error
    job->width = image->width;
    job->height = image->height;
    job->givenImage = image;
    job->reference = file;
    job->referenceSpp = 0;
    job->source = ReferenceSource::Given;
}

} // namespace

double predictSeconds(int prevSpp, double prevSeconds, int spp, double seconds, int nextSpp) {
    if (prevSpp <= 0 || spp <= prevSpp) return seconds * double(nextSpp) / spp;
    double perSample = std::max(0.0, (seconds - prevSeconds) / (spp - prevSpp));
    return seconds + perSample * (nextSpp - spp);
}

std::vector<SceneJob> benchSceneJobs(const BenchSuite& suite, const BenchOptions& options) {
    namespace fs = std::filesystem;
    std::vector<SceneJob> jobs;
    if (!options.sceneFiles.empty()) {
        for (const std::string& f : options.sceneFiles) {
            SceneJob job;
            job.file = f;
            job.width = suite.width;
            job.height = suite.height;
            jobs.push_back(job);
        }
    } else {
        for (const SuiteScene& s : suite.scenes) {
            SceneJob job;
            job.file = (fs::path(options.scenesDir) / s.file).string();
            job.name = s.name;
            RenderSize size = renderSize(suite, s);
            job.width = size.width;
            job.height = size.height;
            // The shipped golden images are RGB renders: a spectral run renders its own.
            if (!s.shippedReference.empty() && !options.spectral) {
                fs::path ref = fs::path(options.scenesDir) / s.shippedReference;
                if (fs::is_regular_file(ref)) {
                    job.reference = ref.lexically_normal().string();
                    job.referenceSpp = s.shippedReferenceSpp;
                    job.source = ReferenceSource::Shipped;
                }
            }
            jobs.push_back(job);
        }
    }
    for (const SceneJob& j : jobs)
        if (!fs::is_regular_file(j.file))
            throw InputError(j.file + ": no such scene file" +
                             (options.sceneFiles.empty()
                                  ? " (" + fs::absolute(j.file).lexically_normal().string() +
                                        "; the suite's scenes are looked up in --scenes-dir)"
                                  : std::string()));
    for (const std::string& spec : options.referenceImages) giveReference(jobs, spec);
    return jobs;
}

bool forEachBenchScene(const std::vector<SceneJob>& jobs, const BenchSuite& suite,
                       const BenchOptions& options, const BenchLog& log,
                       std::vector<SceneInfo>& scenes,
                       const std::function<bool(const BenchScene&)>& body) {
    for (const SceneJob& job : jobs) {
        BenchScene b = prepareForSuite(job, suite, options, log);
        scenes.push_back(sceneInfo(b));
        if (b.reference.cancelled || interruptRequested() || !body(b)) return false;
    }
    return true;
}

std::vector<ModeLadder> selectedLadders(const BenchSuite& suite, const BenchOptions& options) {
    if (options.modes.empty()) return suite.ladders;
    std::vector<ModeLadder> ladders;
    std::string known;
    for (const ModeLadder& l : suite.ladders) known += (known.empty() ? "" : ", ") + l.mode;
    for (const std::string& mode : options.modes) {
        auto it = std::find_if(suite.ladders.begin(), suite.ladders.end(),
                               [&](const ModeLadder& l) { return l.mode == mode; });
        if (it == suite.ladders.end())
            throw InputError("--modes: '" + mode + "' is not a mode of suite '" + suite.name +
                             "' (its modes: " + known + ")");
        if (std::none_of(ladders.begin(), ladders.end(),
                         [&](const ModeLadder& l) { return l.mode == mode; }))
            ladders.push_back(*it);
    }
    return ladders;
}

BenchScene prepareForSuite(const SceneJob& job, const BenchSuite& suite,
                           const BenchOptions& options, const BenchLog& log) {
    std::string refsDir = options.refsDir.empty()
                              ? (std::filesystem::path(options.outDir) / "refs").string()
                              : options.refsDir;
    if (job.reference.empty() &&
        !std::filesystem::exists(referencePath(refsDir, job.file, job.width, job.height,
                                               suite.referenceSpp, sceneJobName(job),
                                               options.spectral)))
        log("rendering the reference of " + job.file + " (path mode" +
            (options.spectral ? ", spectral, " : ", ") +
            std::to_string(suite.referenceSpp) + " spp, " + std::to_string(job.width) + "x" +
            std::to_string(job.height) + "); it is cached in " + refsDir);
    BenchScene b =
        prepareBenchScene(job, refsDir, suite.referenceSpp, options.threads, options.spectral);
    if (b.reference.rendered && !b.reference.cancelled)
        log("  done in " + formatSeconds(b.reference.seconds) + ": " + b.reference.path);
    return b;
}

SceneInfo sceneInfo(const BenchScene& b) {
    SceneInfo i;
    i.name = b.name;
    i.file = b.file;
    i.nativeWidth = b.nativeWidth;
    i.nativeHeight = b.nativeHeight;
    i.width = b.scene->camera.width;
    i.height = b.scene->camera.height;
    i.referencePath = b.reference.path;
    i.referenceSource = b.source;
    i.referenceSpp = b.referenceSpp;
    i.referenceSpectral = b.referenceSpectral;
    i.referenceRendered = b.reference.rendered;
    i.referenceSeconds = b.reference.seconds;
    return i;
}

SceneInfo describeSceneJob(const SceneJob& job, const BenchSuite& suite,
                           const BenchOptions& options) {
    SceneInfo i;
    i.file = job.file;
    i.name = sceneJobName(job);
    std::unique_ptr<Scene> scene = loadScene(job.file);
    i.nativeWidth = scene->camera.width;
    i.nativeHeight = scene->camera.height;
    i.width = job.width;
    i.height = job.height;
    i.referenceSource = job.source;
    i.referenceSpp = job.referenceSpp;
    i.referencePath = job.reference;
    if (job.reference.empty()) {
        std::string refsDir = options.refsDir.empty()
                                  ? (std::filesystem::path(options.outDir) / "refs").string()
                                  : options.refsDir;
        i.referencePath = referencePath(refsDir, job.file, job.width, job.height,
                                        suite.referenceSpp, i.name, options.spectral);
        i.referenceSpp = suite.referenceSpp;
        i.referenceSpectral = options.spectral;
    }
    return i;
}

std::string commonRenderSize(const std::vector<SceneInfo>& scenes, const BenchSuite& suite) {
    int w = scenes.empty() ? suite.width : scenes.front().width;
    int h = scenes.empty() ? suite.height : scenes.front().height;
    for (const SceneInfo& s : scenes)
        if (s.width != w || s.height != h) return "";
    return std::to_string(w) + "x" + std::to_string(h);
}

LadderRun runLadders(const std::vector<SceneJob>& jobs, const BenchSuite& suite,
                     const BenchOptions& options, ResultsCsvWriter& results, const BenchLog& log) {
    LadderRun run;
    double timeCap = options.timeCapSeconds > 0 ? options.timeCapSeconds : suite.timeCapSeconds;
    run.interrupted = !forEachBenchScene(jobs, suite, options, log, run.scenes,
                                         [&](const BenchScene& b) {
        for (const ModeLadder& ladder : selectedLadders(suite, options)) {
            for (RenderConfig c : ladderConfigs(b, suite, ladder, options)) {
                double prevSeconds = 0;
                for (std::size_t k = 0; k < ladder.spp.size(); ++k) {
                    int spp = ladder.spp[k];
                    c.setSpp(spp);
                    TimedRender t = renderTimed(*b.scene, *b.accel, c);
                    if (t.cancelled || interruptRequested()) return false;
                    ImageMetrics m = compareImages(t.image, b.reference.image);
                    BenchRow row{b.name, c.mode, c.settingsString(), t.seconds, t.rays,
                                 m.relmse, m.rmse};
                    results.append(row);
                    run.rows.push_back(row);
                    char line[256];
                    std::snprintf(line, sizeof line, "%s %s %s: %s, relMSE %.4g",
                                  b.name.c_str(), c.mode.c_str(), row.settings.c_str(),
                                  formatSeconds(t.seconds).c_str(), m.relmse);
                    log(line);
                    if (k + 1 < ladder.spp.size() &&
                        predictSeconds(k > 0 ? ladder.spp[k - 1] : 0, prevSeconds, spp,
                                       t.seconds, ladder.spp[k + 1]) > timeCap)
                        break;
                    prevSeconds = t.seconds;
                }
            }
        }
        return true;
    });
    return run;
}

LadderRun runProgressive(const std::vector<SceneJob>& jobs, const BenchSuite& suite,
                         const BenchOptions& options, ResultsCsvWriter& results,
                         const BenchLog& log) {
    LadderRun run;
    const double timeLimit =
        options.timeCapSeconds > 0 ? options.timeCapSeconds : suite.timeCapSeconds;
    run.interrupted = !forEachBenchScene(jobs, suite, options, log, run.scenes,
                                         [&](const BenchScene& b) {
        for (const ModeLadder& ladder : selectedLadders(suite, options)) {
            RenderConfig c = ladderConfigs(b, suite, ladder, options).front();
            // As many samples as the time allows: the limit ends the render.
            c.setSpp(kProgressiveSpp);
            c.control.timeLimitSeconds = timeLimit;
            c.control.reference = &b.reference.image;
            char limit[48];
            std::snprintf(limit, sizeof limit, "time-limit=%g", timeLimit);
            std::string fixed = settingsWithout(c.settingsString(), "spp");
            fixed += (fixed.empty() ? "" : " ") + std::string(limit);
            std::size_t firstRow = run.rows.size();
            c.control.onPassError = [&](const RenderControl::PassError& e) {
                BenchRow row{b.name, c.mode, "spp=" + std::to_string(e.spp) + " " + fixed,
                             e.seconds, e.rays, e.relmse, e.rmse};
                results.append(row);
                run.rows.push_back(row);
            };
            TimedRender t = renderTimed(*b.scene, *b.accel, c);
            if (t.cancelled || interruptRequested()) return false;
            char line[256];
            std::size_t n = run.rows.size() - firstRow;
            std::snprintf(line, sizeof line, "%s %s %s: %zu passes in %s, relMSE %.4g",
                          b.name.c_str(), c.mode.c_str(), fixed.c_str(), n,
                          formatSeconds(t.seconds).c_str(), n ? run.rows.back().relmse : NAN);
            log(line);
        }
        return true;
    });
    return run;
}

} // namespace rayproc::bench
