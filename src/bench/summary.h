// summary.md: the bench's findings in Markdown. Per scene: the plot; the time each mode needs
// to reach the suite's relMSE targets (0.01 and 0.001 unless it says); the error each reaches
// at equal times (up to five times of the 1-2-5 series inside the measured span of at least two
// modes, those most modes span first); for a swept mode, which setting is best at each time.
// Readings are log-log interpolations between measured renders (curve.h); outside the measured
// range a cell says so instead of extrapolating.
#pragma once

#include "bench/results_csv.h"
#include "bench/runner.h"
#include "bench/suite.h"

#include <string>
#include <vector>

namespace rayproc::bench {

struct SummaryContext {
    const BenchSuite* suite = nullptr;
    std::vector<SceneInfo> scenes;
    std::vector<std::string> peerCsvs;
    std::string commandLine;
    std::string started; // UTC
    std::string loadAtStart, loadAtEnd;
    double totalSeconds = 0;
    int threads = 0;
    double timeCapSeconds = 0; // 0: the suite's
    bool interrupted = false;
    bool regenerated = false; // --report-only: no run, rows from an existing results.csv
};

// The times (seconds) at which the summary compares errors for one scene: 1, 2 or 5 times a
// power of ten, inside the measured span of at least two modes' envelopes; at most five, those
// inside the most spans first (then the later ones), in increasing order.
std::vector<double> equalTimePoints(const std::vector<BenchRow>& rows, const std::string& scene);

std::string renderSummary(const std::vector<BenchRow>& rows, const SummaryContext& context);

// Plot file of a scene, relative to the output directory ("cornell-box.svg").
std::string plotFileName(const std::string& scene);

} // namespace rayproc::bench
