// Error-against-time curves of the bench: the lower envelope of a mode's renders (the best error
// any of its settings reached within a time), and reading it log-log between measured points:
// the time to reach a target error, and the error reached at a given time. Nothing is read off
// beyond the measured points: outside them the answer says so.
#pragma once

#include <vector>

namespace rayproc::bench {

// One render: wall seconds and relMSE against the reference.
struct CurvePoint {
    double seconds = 0;
    double relmse = 0;
    int tag = -1; // the caller's index of the render (kept through lowerEnvelope)
};

// The lower envelope (Pareto front) of `points`: sorted by time, each point kept only if its
// error is below that of every faster point. So the error falls strictly along the front, and
// for any time budget the best render within it is the front's last point not slower than it.
// Points with a non-finite or non-positive time or error are dropped (log axes).
std::vector<CurvePoint> lowerEnvelope(std::vector<CurvePoint> points);

// How a reading of the curve relates to the measured points.
enum class Reading {
    Interpolated, // between two measured points (or exactly at one)
    BeforeFirst,  // the query lies before the first point (the first point already meets it)
    AfterLast,    // the query lies past the last point: not measured
    NoData,       // the curve is empty
};

struct CurveReading {
    Reading kind = Reading::NoData;
    double value = 0; // Interpolated: the answer; BeforeFirst / AfterLast: the nearest end's
};

// The time the envelope needs to reach relMSE `target`, interpolated linearly in
// (log seconds, log relMSE) between the two points that bracket it. BeforeFirst (value = the
// first point's time, an upper bound) if the fastest render already reaches it; AfterLast
// (value = the last point's error) if no render does.
CurveReading timeToReach(const std::vector<CurvePoint>& envelope, double target);

// The error the envelope reaches at `seconds`, interpolated in log-log between the bracketing
// points. BeforeFirst (value = the first point's time) if every render took longer; AfterLast
// (value = the last point's error, measured at an earlier time) past the last point.
CurveReading errorAtTime(const std::vector<CurvePoint>& envelope, double seconds);

} // namespace rayproc::bench
