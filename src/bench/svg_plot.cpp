#include "bench/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace rayproc::bench {

namespace {

bool drawable(const PlotPoint& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && p.x > 0 && p.y > 0;
}

// A decade's label: 0.001, 0.01, 0.1, 1, 10, 100, 1000, else 1e-5 / 1e+04 style.
std::string decadeLabel(int e) {
    if (e >= -3 && e <= 3) {
        char buf[16];
        std::snprintf(buf, sizeof buf, "%.*f", e < 0 ? -e : 0, std::pow(10.0, e));
        return buf;
    }
    return "1e" + std::to_string(e);
}

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", v);
    return buf;
}

// The decade range [lo, hi] covering the values, at least one decade wide.
void decadeRange(double minV, double maxV, int& lo, int& hi) {
    lo = int(std::floor(std::log10(minV) + 1e-9));
    hi = int(std::ceil(std::log10(maxV) - 1e-9));
    if (hi <= lo) hi = lo + 1;
}

} // namespace

std::string xmlEscape(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        default: out += c;
        }
    }
    return out;
}

namespace {

// The plot area in pixels and the decades it spans; px and py map data to pixels.
struct PlotFrame {
    int x0, x1, y0, y1;
    double left = 70, top = 40, w, h;
    double px(double x) const { return left + (std::log10(x) - x0) / (x1 - x0) * w; }
    double py(double y) const { return top + h - (std::log10(y) - y0) / (y1 - y0) * h; }
};

// The decades over every drawable point and guide; the plot area left of the legend.
PlotFrame plotFrame(const LogLogPlot& plot) {
    double minX = std::numeric_limits<double>::infinity(), maxX = -minX;
    double minY = minX, maxY = -minX;
    for (const PlotSeries& s : plot.series)
        for (const PlotPoint& p : s.points)
            if (drawable(p)) {
                minX = std::min(minX, p.x), maxX = std::max(maxX, p.x);
                minY = std::min(minY, p.y), maxY = std::max(maxY, p.y);
            }
    for (const HorizontalGuide& g : plot.guides)
        if (std::isfinite(g.y) && g.y > 0) minY = std::min(minY, g.y), maxY = std::max(maxY, g.y);
    if (!(minX <= maxX)) minX = 0.1, maxX = 10;
    if (!(minY <= maxY)) minY = 0.001, maxY = 1;
    PlotFrame f;
    decadeRange(minX, maxX, f.x0, f.x1);
    decadeRange(minY, maxY, f.y0, f.y1);
    const double bottom = 55, legendWidth = 190;
    f.w = plot.width - f.left - legendWidth - 15;
    f.h = plot.height - f.top - bottom;
    return f;
}

// Grid, ticks and labels at every decade; minor ticks at 2..9 times each decade.
void writeAxes(std::ostringstream& o, const PlotFrame& f, const LogLogPlot& plot) {
    const double left = f.left, top = f.top, w = f.w, h = f.h;
    auto px = [&](double x) { return f.px(x); };
    auto py = [&](double y) { return f.py(y); };
    o << "<g stroke=\"#dddddd\" stroke-width=\"1\">\n";
    for (int e = f.x0; e <= f.x1; ++e)
        o << "<line x1=\"" << num(px(std::pow(10.0, e))) << "\" y1=\"" << num(top) << "\" x2=\""
          << num(px(std::pow(10.0, e))) << "\" y2=\"" << num(top + h) << "\"/>\n";
    for (int e = f.y0; e <= f.y1; ++e)
        o << "<line x1=\"" << num(left) << "\" y1=\"" << num(py(std::pow(10.0, e))) << "\" x2=\""
          << num(left + w) << "\" y2=\"" << num(py(std::pow(10.0, e))) << "\"/>\n";
    o << "</g>\n<g stroke=\"black\" stroke-width=\"1\">\n";
    for (int e = f.x0; e < f.x1; ++e)
        for (int m = 2; m <= 9; ++m)
            o << "<line x1=\"" << num(px(m * std::pow(10.0, e))) << "\" y1=\"" << num(top + h)
              << "\" x2=\"" << num(px(m * std::pow(10.0, e))) << "\" y2=\"" << num(top + h + 3)
              << "\"/>\n";
    for (int e = f.y0; e < f.y1; ++e)
        for (int m = 2; m <= 9; ++m)
            o << "<line x1=\"" << num(left - 3) << "\" y1=\"" << num(py(m * std::pow(10.0, e)))
              << "\" x2=\"" << num(left) << "\" y2=\"" << num(py(m * std::pow(10.0, e)))
              << "\"/>\n";
    for (int e = f.x0; e <= f.x1; ++e)
        o << "<line x1=\"" << num(px(std::pow(10.0, e))) << "\" y1=\"" << num(top + h)
          << "\" x2=\"" << num(px(std::pow(10.0, e))) << "\" y2=\"" << num(top + h + 6) << "\"/>\n";
    for (int e = f.y0; e <= f.y1; ++e)
        o << "<line x1=\"" << num(left - 6) << "\" y1=\"" << num(py(std::pow(10.0, e)))
          << "\" x2=\"" << num(left) << "\" y2=\"" << num(py(std::pow(10.0, e))) << "\"/>\n";
    o << "<rect x=\"" << num(left) << "\" y=\"" << num(top) << "\" width=\"" << num(w)
      << "\" height=\"" << num(h) << "\" fill=\"none\"/>\n</g>\n";
    for (int e = f.x0; e <= f.x1; ++e)
        o << "<text x=\"" << num(px(std::pow(10.0, e))) << "\" y=\"" << num(top + h + 20)
          << "\" text-anchor=\"middle\">" << decadeLabel(e) << "</text>\n";
    for (int e = f.y0; e <= f.y1; ++e)
        o << "<text x=\"" << num(left - 9) << "\" y=\"" << num(py(std::pow(10.0, e)) + 4)
          << "\" text-anchor=\"end\">" << decadeLabel(e) << "</text>\n";
    o << "<text x=\"" << num(left + w / 2) << "\" y=\"" << num(top + h + 42)
      << "\" text-anchor=\"middle\">" << xmlEscape(plot.xLabel) << " (log)</text>\n"
      << "<text transform=\"translate(16 " << num(top + h / 2)
      << ") rotate(-90)\" text-anchor=\"middle\">" << xmlEscape(plot.yLabel) << " (log)</text>\n";
}

// Guides: dashed, labelled at the right end of the plot area.
void writeGuides(std::ostringstream& o, const PlotFrame& f, const LogLogPlot& plot) {
    for (const HorizontalGuide& g : plot.guides) {
        if (!(std::isfinite(g.y) && g.y > 0)) continue;
        o << "<line x1=\"" << num(f.left) << "\" y1=\"" << num(f.py(g.y)) << "\" x2=\""
          << num(f.left + f.w) << "\" y2=\"" << num(f.py(g.y))
          << "\" stroke=\"#888888\" stroke-dasharray=\"5 4\" stroke-width=\"1\"/>\n"
          << "<text x=\"" << num(f.left + f.w - 3) << "\" y=\"" << num(f.py(g.y) - 3)
          << "\" text-anchor=\"end\" fill=\"#666666\" font-size=\"10\">" << xmlEscape(g.label)
          << "</text>\n";
    }
}

// A marker's radius and fill: hollow or filled in the series' colour.
std::string markerStyle(const PlotSeries& s) {
    return std::string("\" r=\"") + (s.hollow ? "2.5" : "3.5") + "\" " +
           (s.hollow ? "fill=\"none\" stroke=\"" + xmlEscape(s.colour) + "\""
                     : "fill=\"" + xmlEscape(s.colour) + "\"");
}

// Series: polyline then markers, clipped to the plot area.
void writeSeries(std::ostringstream& o, const PlotFrame& f, const LogLogPlot& plot) {
    o << "<clipPath id=\"area\"><rect x=\"" << num(f.left - 4) << "\" y=\"" << num(f.top - 4)
      << "\" width=\"" << num(f.w + 8) << "\" height=\"" << num(f.h + 8) << "\"/></clipPath>\n"
      << "<g clip-path=\"url(#area)\">\n";
    for (const PlotSeries& s : plot.series) {
        std::vector<PlotPoint> pts;
        for (const PlotPoint& p : s.points)
            if (drawable(p)) pts.push_back(p);
        o << "<g class=\"series\" data-label=\"" << xmlEscape(s.label) << "\">\n";
        if (s.line && pts.size() > 1) {
            o << "<polyline fill=\"none\" stroke=\"" << xmlEscape(s.colour)
              << "\" stroke-width=\"2\" points=\"";
            for (const PlotPoint& p : pts) o << num(f.px(p.x)) << "," << num(f.py(p.y)) << " ";
            o << "\"/>\n";
        }
        if (s.markers)
            for (const PlotPoint& p : pts)
                o << "<circle class=\"pt\" cx=\"" << num(f.px(p.x)) << "\" cy=\""
                  << num(f.py(p.y)) << markerStyle(s) << "/>\n";
        o << "</g>\n";
    }
    o << "</g>\n";
}

// Legend, right of the plot area.
void writeLegend(std::ostringstream& o, const PlotFrame& f, const LogLogPlot& plot) {
    double lx = f.left + f.w + 15, ly = f.top + 8;
    for (const PlotSeries& s : plot.series) {
        if (s.label.empty()) continue;
        if (s.line)
            o << "<line x1=\"" << num(lx) << "\" y1=\"" << num(ly) << "\" x2=\"" << num(lx + 22)
              << "\" y2=\"" << num(ly) << "\" stroke=\"" << xmlEscape(s.colour)
              << "\" stroke-width=\"2\"/>\n";
        if (s.markers)
            o << "<circle cx=\"" << num(lx + 11) << "\" cy=\"" << num(ly) << markerStyle(s)
              << "/>\n";
        o << "<text x=\"" << num(lx + 28) << "\" y=\"" << num(ly + 4) << "\">"
          << xmlEscape(s.label) << "</text>\n";
        ly += 18;
    }
}

} // namespace

std::string renderSvg(const LogLogPlot& plot) {
    const PlotFrame f = plotFrame(plot);
    std::ostringstream o;
    o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << plot.width << "\" height=\""
      << plot.height << "\" viewBox=\"0 0 " << plot.width << " " << plot.height
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect x=\"0\" y=\"0\" width=\"" << plot.width << "\" height=\"" << plot.height
      << "\" fill=\"white\"/>\n"
      << "<text x=\"" << num(f.left + f.w / 2)
      << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << xmlEscape(plot.title)
      << "</text>\n";
    writeAxes(o, f, plot);
    writeGuides(o, f, plot);
    writeSeries(o, f, plot);
    writeLegend(o, f, plot);
    o << "</svg>\n";
    return o.str();
}

} // namespace rayproc::bench
