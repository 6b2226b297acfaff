// results.csv rows grouped for the report: per scene, per mode (rayproc's modes in pipeline
// order, then peer renderers in order of appearance), the mode's settings (what stays fixed
// along a ladder) and its lower envelope of error against time.
#pragma once

#include "bench/curve.h"
#include "bench/results_csv.h"

#include <string>
#include <vector>

namespace rayproc::bench {

struct ModeCurve {
    std::string mode;
    std::vector<BenchRow> rows;        // this scene's rows of the mode, in file order
    std::vector<std::string> variants; // distinct settingsWithoutBudget, in order of appearance
    std::vector<CurvePoint> envelope;  // tag = index into rows
    bool peer = false;                 // not one of rayproc's modes
};

// The settings without the budget, i.e. what stays fixed along a ladder: every key=value pair
// but spp=, samples=, seconds= and time= (a peer renderer may name its budget any of these).
std::string settingsWithoutBudget(const std::string& settings);

// A row of a --progressive render (one pass of a time-limited render: its settings name the
// time-limit), not of a ladder.
bool isProgressiveRow(const BenchRow& row);

// Scene names in order of first appearance.
std::vector<std::string> sceneNames(const std::vector<BenchRow>& rows);

std::vector<ModeCurve> modeCurves(const std::vector<BenchRow>& rows, const std::string& scene);

// The plot colour of a mode: fixed for rayproc's modes, from a palette for peers (by index).
std::string modeColour(const std::string& mode, int peerIndex);

} // namespace rayproc::bench
