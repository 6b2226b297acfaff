// The SVG writer and the per-scene plot: well-formed XML, one marker per drawable point, decade
// labels, legend entries.
#include "bench/scene_plot.h"
#include "bench/svg_plot.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace rayproc::bench;

namespace {

std::size_t countOf(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
    return n;
}

// Checks that every element is closed in order (a minimal XML well-formedness check: tags
// balanced and nested, attributes quoted, no stray '<' or '&' in text).
bool wellFormed(const std::string& s, std::string& why) {
    std::vector<std::string> open;
    std::size_t i = 0;
    while (i < s.size()) {
        if (s[i] == '&') {
            std::size_t semi = s.find(';', i);
            std::string ent = s.substr(i, semi == std::string::npos ? 0 : semi - i + 1);
            if (ent != "&amp;" && ent != "&lt;" && ent != "&gt;" && ent != "&quot;") {
                why = "bad entity at " + std::to_string(i);
                return false;
            }
        }
        if (s[i] != '<') {
            ++i;
            continue;
        }
        std::size_t end = i + 1;
        bool inQuote = false;
        while (end < s.size() && (inQuote || s[end] != '>')) {
            if (s[end] == '"') inQuote = !inQuote;
            if (!inQuote && s[end] == '<') {
                why = "'<' inside a tag at " + std::to_string(end);
                return false;
            }
            ++end;
        }
        if (end >= s.size()) {
            why = "unterminated tag";
            return false;
        }
        std::string tag = s.substr(i + 1, end - i - 1);
        i = end + 1;
        if (tag[0] == '?') continue;
        if (tag[0] == '/') {
            std::string name = tag.substr(1);
            if (open.empty() || open.back() != name) {
                why = "unexpected </" + name + ">";
                return false;
            }
            open.pop_back();
            continue;
        }
        if (tag.back() == '/') continue;
        open.push_back(tag.substr(0, tag.find_first_of(" \n")));
    }
    if (!open.empty()) why = "unclosed <" + open.back() + ">";
    return open.empty();
}

} // namespace

TEST_CASE("renderSvg writes a well-formed log-log plot with one marker per point", "[bench]") {
    LogLogPlot plot;
    plot.title = "a <title> & more";
    double nan = std::numeric_limits<double>::quiet_NaN();
    plot.series = {{"path", "#1f77b4", {{0.05, 0.3}, {0.5, 0.03}, {5, 0.003}}, true, true, false},
                   {"gi: each setting", "#2ca02c", {{1, 0.02}, {2, 0.01}, {0, 0.1}, {nan, 1}},
                    false, true, true},
                   {"gi (best)", "#2ca02c", {{1, 0.02}, {2, 0.01}}, true, false, false}};
    plot.guides = {{0.01, "relMSE 0.01"}, {0.001, "relMSE 0.001"}};
    std::string svg = renderSvg(plot);
    std::string why;
    CHECK(wellFormed(svg, why));
    INFO(why);
    CHECK(svg.find("<svg xmlns=\"http://www.w3.org/2000/svg\"") != std::string::npos);
    // 3 + 2 drawable points (the zero and NaN ones have no place on log axes); none for the
    // marker-less envelope.
    CHECK(countOf(svg, "class=\"pt\"") == 5);
    CHECK(countOf(svg, "<polyline") == 2);
    // Decades: x from 0.01 to 10, y from 0.001 to 1 (the guide at 0.001 included).
    for (const char* label : {">0.01<", ">0.1<", ">1<", ">10<", ">0.001<"})
        CHECK(svg.find(label) != std::string::npos);
    CHECK(svg.find("a &lt;title&gt; &amp; more") != std::string::npos);
    for (const char* legend : {">path<", ">gi: each setting<", ">gi (best)<"})
        CHECK(svg.find(legend) != std::string::npos);
    CHECK(countOf(svg, "stroke-dasharray") == 2);
}

TEST_CASE("renderSvg labels far decades in exponent form and survives an empty plot",
          "[bench]") {
    LogLogPlot plot;
    plot.series = {{"x", "red", {{1e-6, 1e-7}, {1e5, 2}}, true, true, false}};
    std::string svg = renderSvg(plot);
    CHECK(svg.find(">1e-6<") != std::string::npos);
    CHECK(svg.find(">1e5<") != std::string::npos);
    CHECK(svg.find(">1e-7<") != std::string::npos);
    std::string why;
    CHECK(wellFormed(renderSvg(LogLogPlot{}), why));
}

TEST_CASE("scenePlot draws every render and gi's envelope", "[bench]") {
    std::vector<BenchRow> rows = {
        {"s", "path", "spp=1", 0.1, 1, 0.2, 0},
        {"s", "path", "spp=2", 0.2, 1, 0.1, 0},
        {"s", "path", "spp=4", 0.4, 1, 0.05, 0},
        {"s", "gi", "spp=1 gather=16", 1.0, 1, 0.03, 0},
        {"s", "gi", "spp=2 gather=16", 1.5, 1, 0.02, 0},
        {"s", "gi", "spp=1 gather=64", 2.0, 1, 0.025, 0}, // dominated
        {"s", "gi", "spp=2 gather=64", 3.0, 1, 0.01, 0},
        {"other", "path", "spp=1", 0.1, 1, 0.2, 0},
        {"s", "cycles", "samples=4", 0.3, 0, 0.04, 0},
        {"s", "cycles", "samples=16", 0.9, 0, 0.01, 0}, // one setting: a ladder, not a sweep
    };
    LogLogPlot plot = scenePlot(rows, "s", "test");
    CHECK(plot.title == "s: test");
    // path, gi envelope + gi points, the peer.
    REQUIRE(plot.series.size() == 4);
    CHECK(plot.series[0].label == "gi (best setting)");
    CHECK(plot.series[0].points.size() == 3); // (1, .03), (1.5, .02), (3, .01)
    CHECK(plot.series[1].points.size() == 4);
    CHECK(plot.series[2].label == "path");
    CHECK(plot.series[3].label == "cycles");
    CHECK(plot.series[3].colour != plot.series[2].colour);
    CHECK(plot.series[3].line);
    CHECK(plot.series[3].points.size() == 2);
    std::string svg = renderSvg(plot);
    CHECK(countOf(svg, "class=\"pt\"") == 9); // every row of scene s, one marker each
}
