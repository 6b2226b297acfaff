// Cancel on Ctrl-C, SIGTERM or SIGHUP: the first asks the render to stop emitting and finish
// what is in flight, so the partial image can be written; a second one exits at once with
// 128 + the signal's number (130 for Ctrl-C).
#pragma once

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
// The handler's messages off: the other ranks of a distributed render leave them to rank 0.
void quietInterruptMessages();
void clearInterrupt();
// Withdraws a requestInterrupt() (rayproc serve's cancel) unless a stopping signal arrived,
// which stays in force.
void clearRequestedInterrupt();

} // namespace rayproc
