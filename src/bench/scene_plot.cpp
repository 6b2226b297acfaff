#include "bench/scene_plot.h"

#include "bench/mode_curves.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace rayproc::bench {

LogLogPlot scenePlot(const std::vector<BenchRow>& rows, const std::string& scene,
                     const std::string& subtitle) {
    LogLogPlot plot;
    plot.title = scene + (subtitle.empty() ? "" : ": " + subtitle);
    plot.xLabel = "render time, seconds";
    plot.yLabel = "relMSE against the reference";
    plot.guides = {{0.01, "relMSE 0.01"}, {0.001, "relMSE 0.001"}};
    int peerIndex = 0;
    for (const ModeCurve& c : modeCurves(rows, scene)) {
        std::string colour = modeColour(c.mode, c.peer ? peerIndex++ : 0);
        if (c.variants.size() > 1) {
            PlotSeries each{c.mode + ": each setting", colour, {}, false, true, true};
            for (const BenchRow& r : c.rows) each.points.push_back({r.seconds, r.relmse});
            PlotSeries best{c.mode + " (best setting)", colour, {}, true, false, false};
            for (const CurvePoint& p : c.envelope) best.points.push_back({p.seconds, p.relmse});
            plot.series.push_back(best);
            plot.series.push_back(each);
        } else if (isProgressiveRow(c.rows.front())) {
            // One progressive render (--progressive): its passes in time order as a line,
            // thinned to a point per 1/100 decade of time so a long render stays a small file.
            PlotSeries s{c.mode, colour, {}, true, false, false};
            double lastKept = -INFINITY;
            for (std::size_t i = 0; i < c.rows.size(); ++i) {
                const BenchRow& r = c.rows[i];
                double t = std::log10(r.seconds);
                if (i + 1 == c.rows.size() || !(t < lastKept + 0.01)) {
                    s.points.push_back({r.seconds, r.relmse});
                    lastKept = t;
                }
            }
            plot.series.push_back(s);
        } else {
            // One setting: the ladder in budget order (spp when present, else time).
            std::vector<BenchRow> ladder = c.rows;
            std::stable_sort(ladder.begin(), ladder.end(), [](const BenchRow& a, const BenchRow& b) {
                long sa = std::atol(settingValue(a.settings, "spp").c_str());
                long sb = std::atol(settingValue(b.settings, "spp").c_str());
                return sa != sb ? sa < sb : a.seconds < b.seconds;
            });
            PlotSeries s{c.mode, colour, {}, true, true, false};
            for (const BenchRow& r : ladder) s.points.push_back({r.seconds, r.relmse});
            plot.series.push_back(s);
        }
    }
    return plot;
}

} // namespace rayproc::bench
