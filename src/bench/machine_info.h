// What the bench's report says about the machine, so its timings can be judged: core count,
// CPU model, load average (Linux /proc; "unknown" elsewhere), and the UTC time.
#pragma once

#include <string>

namespace rayproc::bench {

std::string cpuModel();     // /proc/cpuinfo's first "model name"
int hardwareThreads();      // std::thread::hardware_concurrency
std::string loadAverage();  // the 1-minute load average from /proc/loadavg
std::string utcTimestamp(); // "2026-11-22 01:23 UTC"

} // namespace rayproc::bench
