#include "bench/curve.h"

#include <algorithm>
#include <cmath>

namespace rayproc::bench {

namespace {

bool usable(const CurvePoint& p) {
    return std::isfinite(p.seconds) && std::isfinite(p.relmse) && p.seconds > 0 && p.relmse > 0;
}

// y at x on the line through (x0, y0) and (x1, y1) in log-log coordinates.
double logLogLerp(double x, double x0, double y0, double x1, double y1) {
    double lx0 = std::log(x0), lx1 = std::log(x1);
    if (lx1 == lx0) return std::min(y0, y1);
    double f = (std::log(x) - lx0) / (lx1 - lx0);
    return std::exp(std::log(y0) + f * (std::log(y1) - std::log(y0)));
}

} // namespace

std::vector<CurvePoint> lowerEnvelope(std::vector<CurvePoint> points) {
    points.erase(std::remove_if(points.begin(), points.end(),
                                [](const CurvePoint& p) { return !usable(p); }),
                 points.end());
    // Equal times: the lower error first, so the other one is dominated.
    std::sort(points.begin(), points.end(), [](const CurvePoint& a, const CurvePoint& b) {
        return a.seconds != b.seconds ? a.seconds < b.seconds : a.relmse < b.relmse;
    });
    std::vector<CurvePoint> front;
    for (const CurvePoint& p : points)
        if (front.empty() || p.relmse < front.back().relmse) front.push_back(p);
    return front;
}

CurveReading timeToReach(const std::vector<CurvePoint>& envelope, double target) {
    if (envelope.empty()) return {Reading::NoData, 0};
    if (envelope.front().relmse <= target) return {Reading::BeforeFirst, envelope.front().seconds};
    for (std::size_t i = 0; i + 1 < envelope.size(); ++i) {
        const CurvePoint& a = envelope[i];
        const CurvePoint& b = envelope[i + 1];
        if (b.relmse <= target) // a.relmse > target >= b.relmse: error is the abscissa here
            return {Reading::Interpolated,
                    logLogLerp(target, a.relmse, a.seconds, b.relmse, b.seconds)};
    }
    return {Reading::AfterLast, envelope.back().relmse};
}

CurveReading errorAtTime(const std::vector<CurvePoint>& envelope, double seconds) {
    if (envelope.empty()) return {Reading::NoData, 0};
    if (seconds < envelope.front().seconds)
        return {Reading::BeforeFirst, envelope.front().seconds};
    if (seconds > envelope.back().seconds) return {Reading::AfterLast, envelope.back().relmse};
    for (std::size_t i = 0; i + 1 < envelope.size(); ++i) {
        const CurvePoint& a = envelope[i];
        const CurvePoint& b = envelope[i + 1];
        if (seconds <= b.seconds)
            return {Reading::Interpolated,
                    logLogLerp(seconds, a.seconds, a.relmse, b.seconds, b.relmse)};
    }
    return {Reading::Interpolated, envelope.back().relmse}; // exactly the last point
}

} // namespace rayproc::bench
