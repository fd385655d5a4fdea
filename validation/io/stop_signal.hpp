#pragma once
// SIGTERM and SIGINT as a request to stop at the next checkpoint (a batch queue's wall-time limit sends
// SIGTERM, then SIGKILL after a grace period). Installed only by a run that writes checkpoints; the handler
// records the signal and restores the default action, so a second signal ends the process at once.
namespace aggkit {

void catch_stop_signals();   // installs the handlers (idempotent)
void release_stop_signals(); // the default actions again
int stop_signal();           // the signal received since catch_stop_signals(), 0 if none

}  // namespace aggkit
