// Cancel on Ctrl-C: the first SIGINT asks the render to stop emitting and finish what is in
// flight, so the partial image can be written; a second one exits at once with status 130.
#pragma once

namespace rayproc {

void installInterruptHandler();
bool interruptRequested();
void requestInterrupt(); // as if SIGINT arrived (tests)
void clearInterrupt();

} // namespace rayproc
