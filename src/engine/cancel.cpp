#include "engine/cancel.h"

#include <csignal>
#include <unistd.h>

#include <atomic>

namespace rayproc {

namespace {
std::atomic<int> g_interrupts{0};

extern "C" void onSigint(int) {
    if (g_interrupts.fetch_add(1) >= 1) {
        const char msg[] = "\nrayproc: interrupted twice, exiting now\n";
        (void)!write(STDERR_FILENO, msg, sizeof msg - 1);
        _exit(130);
    }
    const char msg[] = "\nrayproc: interrupted; finishing rays in flight and writing the partial "
                       "image (Ctrl-C again to exit now)\n";
    (void)!write(STDERR_FILENO, msg, sizeof msg - 1);
}
} // namespace

void installInterruptHandler() {
    struct sigaction sa {};
    sa.sa_handler = onSigint;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
}

bool interruptRequested() { return g_interrupts.load(std::memory_order_relaxed) > 0; }
void requestInterrupt() { g_interrupts.store(1); }
void clearInterrupt() { g_interrupts.store(0); }

} // namespace rayproc
