// The per-scene figure of the bench: relMSE against wall time, log-log, one colour per mode.
// A mode with one setting is a line through its ladder; a mode with several (gi's sweep) shows
// every render as a hollow point and its lower envelope (the best setting at each time) as
// the line; a progressive render (--progressive, rows with time-limit=) is a line through its
// passes in time order, without markers, thinned to a point per 1/100 decade of time. Dashed
// guides at relMSE 0.01 and 0.001.
#pragma once

#include "bench/results_csv.h"
#include "bench/svg_plot.h"

#include <string>
#include <vector>

namespace rayproc::bench {

// Every row of `scene` becomes one point (a progressive render's: one per 1/100 decade of
// time); `subtitle` follows the scene's name in the title.
LogLogPlot scenePlot(const std::vector<BenchRow>& rows, const std::string& scene,
                     const std::string& subtitle);

} // namespace rayproc::bench
