#include "bench/mode_curves.h"

#include "modes/modes.h"

#include <algorithm>

namespace rayproc::bench {

namespace {

// rayproc's own modes (modes/mode_registry.h), in their order; the others are peers'.
const std::vector<std::string>& ownModes() { return knownModes(); }

} // namespace

std::string settingsWithoutBudget(const std::string& settings) {
    std::string s = settings;
    for (const char* key : {"spp", "samples", "seconds", "time"}) s = settingsWithout(s, key);
    return s;
}

bool isProgressiveRow(const BenchRow& row) {
    return !settingValue(row.settings, "time-limit").empty();
}

std::vector<std::string> sceneNames(const std::vector<BenchRow>& rows) {
    std::vector<std::string> names;
    for (const BenchRow& r : rows)
        if (std::find(names.begin(), names.end(), r.scene) == names.end()) names.push_back(r.scene);
    return names;
}

std::vector<ModeCurve> modeCurves(const std::vector<BenchRow>& rows, const std::string& scene) {
    std::vector<std::string> order = ownModes();
    for (const BenchRow& r : rows)
        if (r.scene == scene && std::find(order.begin(), order.end(), r.mode) == order.end())
            order.push_back(r.mode);
    std::vector<ModeCurve> curves;
    for (const std::string& mode : order) {
        ModeCurve c;
        c.mode = mode;
        c.peer = std::find(ownModes().begin(), ownModes().end(), mode) == ownModes().end();
        std::vector<CurvePoint> points;
        for (const BenchRow& r : rows) {
            if (r.scene != scene || r.mode != mode) continue;
            std::string v = settingsWithoutBudget(r.settings);
            if (std::find(c.variants.begin(), c.variants.end(), v) == c.variants.end())
                c.variants.push_back(v);
            points.push_back({r.seconds, r.relmse, int(c.rows.size())});
            c.rows.push_back(r);
        }
        if (c.rows.empty()) continue;
        c.envelope = lowerEnvelope(points);
        curves.push_back(std::move(c));
    }
    return curves;
}

std::string modeColour(const std::string& mode, int peerIndex) {
    if (mode == "preview") return "#9467bd";
    if (mode == "raytrace") return "#ff7f0e";
    if (mode == "gi") return "#2ca02c";
    if (mode == "path") return "#1f77b4";
    static const char* peers[] = {"#d62728", "#8c564b", "#e377c2", "#17becf", "#7f7f7f"};
    return peers[peerIndex % 5];
}

} // namespace rayproc::bench
