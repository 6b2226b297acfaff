#include "bench/machine_info.h"

#include <ctime>
#include <fstream>
#include <thread>

namespace rayproc::bench {

std::string cpuModel() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            std::size_t colon = line.find(':');
            if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
        }
    return "unknown CPU";
}

int hardwareThreads() {
    return int(std::thread::hardware_concurrency());
}

std::string loadAverage() {
    std::ifstream in("/proc/loadavg");
    std::string one;
    if (in >> one) return one;
    return "unknown";
}

std::string utcTimestamp() {
    std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    char buf[40];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", &tm);
    return buf;
}

} // namespace rayproc::bench
