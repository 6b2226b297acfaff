#include "engine/cancel.h"

#include <csignal>
#include <unistd.h>

#include <atomic>

namespace rayproc {

namespace {
std::atomic<int> g_interrupts{0};
std::atomic<int> g_signal{0}; // the first stopping signal, 0 before one arrives
std::atomic<bool> g_quiet{false};

extern "C" void onStopSignal(int sig) {
    int expected = 0;
    g_signal.compare_exchange_strong(expected, sig);
    if (g_interrupts.fetch_add(1) >= 1) {
        const char msg[] = "\nrayproc: interrupted twice, exiting now\n";
        if (!g_quiet.load()) (void)!write(STDERR_FILENO, msg, sizeof msg - 1);
        _exit(128 + sig);
    }
    const char msg[] = "\nrayproc: interrupted; finishing rays in flight and writing the partial "
                       "image (Ctrl-C again to exit now)\n";
    if (!g_quiet.load()) (void)!write(STDERR_FILENO, msg, sizeof msg - 1);
}
} // namespace

void installInterruptHandler() {
    struct sigaction sa {};
    sa.sa_handler = onStopSignal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    // SIGTERM is what batch schedulers (Slurm, PBS) and `kill` send, SIGHUP what a closed
    // terminal sends: both keep the work done so far, like Ctrl-C.
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
}

bool interruptRequested() { return g_interrupts.load(std::memory_order_relaxed) > 0; }
int interruptExitStatus() {
    int sig = g_signal.load();
    return 128 + (sig > 0 ? sig : SIGINT);
}
int interruptSignal() { return g_signal.load(); }
void requestInterrupt() { g_interrupts.store(1); }
namespace {
constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP}; // bits 1, 2, 3 of interruptBits()
} // namespace

std::uint32_t interruptBits() {
    if (!interruptRequested()) return 0;
    std::uint32_t bits = kInterruptBit;
    for (int i = 0; i < 3; ++i)
        if (g_signal.load() == kStopSignals[i]) bits |= 2u << i;
    return bits;
}

void adoptInterrupt(std::uint32_t bits) {
    if (!(bits & kInterruptBit)) return;
    for (int i = 0; i < 3; ++i) {
        int expected = 0;
        if (bits & (2u << i)) g_signal.compare_exchange_strong(expected, kStopSignals[i]);
    }
    if (!interruptRequested()) requestInterrupt();
}

void quietInterruptMessages() { g_quiet.store(true); }
void clearRequestedInterrupt() {
    if (g_signal.load() == 0) g_interrupts.store(0);
}

void clearInterrupt() {
    g_interrupts.store(0);
    g_signal.store(0);
}

} // namespace rayproc
