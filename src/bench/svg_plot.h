// A self-contained log-log plot as SVG text: both axes in decades with ticks, grid lines and
// labels at every power of ten, a title, axis labels, one colour per series, a legend, and
// dashed horizontal guide lines (the relMSE targets). Any browser shows it; no external tool
// or font file is needed.
#pragma once

#include <string>
#include <vector>

namespace rayproc::bench {

struct PlotPoint {
    double x = 0, y = 0;
};

struct PlotSeries {
    std::string label;   // in the legend; empty: not listed
    std::string colour;  // any SVG colour ("#1f77b4")
    std::vector<PlotPoint> points;
    bool line = true;    // joined by a polyline (in the given order)
    bool markers = true; // a marker at every point
    bool hollow = false; // hollow markers (the settings behind an envelope)
};

struct HorizontalGuide {
    double y = 0;
    std::string label;
};

struct LogLogPlot {
    std::string title;
    std::string xLabel = "seconds";
    std::string yLabel = "relMSE";
    std::vector<PlotSeries> series;
    std::vector<HorizontalGuide> guides;
    int width = 640, height = 440;
};

// The SVG document. Points with a non-finite or non-positive coordinate are left out (they have
// no place on log axes). Each drawn point is one <circle> with class "pt", so a reader (or a
// test) can count them; the axis range covers every point and guide, widened to whole decades.
std::string renderSvg(const LogLogPlot& plot);

// Escapes &, <, >, " for SVG text and attributes.
std::string xmlEscape(const std::string& s);

} // namespace rayproc::bench
