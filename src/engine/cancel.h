// Cancel on Ctrl-C, SIGTERM or SIGHUP: the first asks the render to stop emitting and finish
// what is in flight, so the partial image can be written; a second one exits at once with
// 128 + the signal's number (130 for Ctrl-C).
#pragma once

#include <cstdint>

namespace rayproc {

void installInterruptHandler();
bool interruptRequested();
// 128 + the first stopping signal's number (SIGINT's when set by requestInterrupt): the shell's
// convention, which the commands return after writing what they have.
int interruptExitStatus();
// The first stopping signal that arrived (SIGINT, SIGTERM, SIGHUP), 0 when none did, even if
// requestInterrupt() stopped a render (rayproc serve's cancel is not a signal).
int interruptSignal();
void requestInterrupt(); // as if SIGINT arrived (tests, and a distributed render's agreement)
// An interrupt as bits for a distributed render's agreement (Cluster::orAll): 0 without one,
// else kInterruptBit and a bit for the signal that arrived here (SIGHUP, SIGINT, SIGTERM).
constexpr std::uint32_t kInterruptBit = 1;
std::uint32_t interruptBits();
// Takes over the agreed bits of all ranks: an interrupt is requested here too, with the signal
// another rank received, so that every rank, rank 0 included, exits with 128 + that signal (a
// SIGTERM to one rank made rank 0 exit with 130). Bits without kInterruptBit do nothing.
void adoptInterrupt(std::uint32_t bits);
// The handler's messages off: the other ranks of a distributed render leave them to rank 0.
void quietInterruptMessages();
void clearInterrupt();
// Withdraws a requestInterrupt() (rayproc serve's cancel) unless a stopping signal arrived,
// which stays in force.
void clearRequestedInterrupt();

} // namespace rayproc
