// SIGINT and SIGTERM as a request to stop: the handler only records the signal; the run loop
// finishes the step, agrees on the request over the ranks in the step's one collective check
// (Solver::checks), writes a checkpoint, the last field frame and summary.json, and main exits
// 128 + the signal (130 for SIGINT, 143 for SIGTERM). A second signal ends the process at once.
// PETSc 3.18 built with Open MPI installs no handler for either signal (SIGINT's is disabled in
// its source, SIGTERM's is skipped under Open MPI, which uses SIGTERM to end its ranks);
// installing ours after PetscInitialize makes it win in any build.
#pragma once

namespace gimp {

/// Install the handler for SIGINT and SIGTERM (after PetscInitialize, so that it replaces any
/// handler PETSc installed). Returns false when the system refuses it.
bool installInterruptHandlers();

/// The last stop signal received by this process (SIGINT or SIGTERM), or 0.
int interruptSignal();

} // namespace gimp
