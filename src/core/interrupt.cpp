#include "gimp/core/interrupt.hpp"

#include <csignal>

namespace gimp {

namespace {

// The one global of the program: a signal handler can only talk to the program through an
// object of static storage, and the standard allows it nothing but a volatile sig_atomic_t.
// File-static, written only by onStopSignal, read only by interruptSignal.
volatile std::sig_atomic_t stopSignal = 0;

// The first signal asks the run to stop after its step; a second one (the run is stuck, or the
// user insists) ends the process at once with the signal's default action. signal() and raise()
// are async-signal-safe.
extern "C" void onStopSignal(int sig) {
  if (stopSignal != 0) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  stopSignal = sig;
}

} // namespace

bool installInterruptHandlers() {
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART; // system calls (MPI, HDF5, file writes) continue after the handler
  return sigaction(SIGINT, &sa, nullptr) == 0 && sigaction(SIGTERM, &sa, nullptr) == 0;
}

int interruptSignal() {
  return static_cast<int>(stopSignal);
}

} // namespace gimp
