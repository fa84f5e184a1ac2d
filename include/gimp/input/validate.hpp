// Validation of what the options describe, before step 1. Each check ends the run on every rank
// with one line naming the option, the value and what is valid (InputError, thrown by all ranks
// alike: the checks use only data every rank has, or reduce what one rank found).
#pragma once

#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"

#include <petscts.h>

#include <functional>

namespace gimp {

/// readScene, with PETSc's own parse errors (a number that is not one) as one line.
template <int D> PetscErrorCode readSceneOneLine(MPI_Comm comm, Scene<D> &sc);

/// Check every option's value (given, finite, in range of PetscInt), then run `read` with PETSc's
/// option errors turned into one InputError line (readSceneOneLine is this with readScene).
PetscErrorCode readOptionsOneLine(const std::function<PetscErrorCode()> &read);

/// Run `call` (PETSc objects set up from the options: the DMDAs' -da_*, the swarm, TS, the
/// eigen-solver's EPS and ST, viewers) with PETSc's error handler replaced: a PETSc error becomes
/// one InputError line, naming the option whose value PETSc's message holds, else the options
/// set under `prefix` ("da_": -da_processors_x 3). Every rank must fail alike (option values are
/// the same on every rank), followed by `hint`. PETSc's out-of-memory error is thrown as
/// std::bad_alloc (main ends every rank).
PetscErrorCode petscOneLine(const std::function<PetscErrorCode()> &call,
                            const std::string &prefix = "", const std::string &hint = "");

/// The viewers of -ts_view and -log_view opened and closed once, through petscOneLine.
PetscErrorCode checkViewerOptions(MPI_Comm comm);

/// Combinations readScene cannot judge alone: the model and plane, particle density limits, the
/// multi-rate step's limits.
template <int D> void checkSceneCombinations(const Scene<D> &sc);

/// TSSetFromOptions with parse errors as one line, then the time stepper's type, adaptivity and
/// step checked (explicit euler, fixed dt > 0 and, unless -gimp_stability_check bounds it by the
/// eigenvalue instead, below the stable h_min / c_p).
template <int D>
PetscErrorCode timeStepFromOptions(TS ts, const Scene<D> &sc, const Lattice<D> &grid);
/// The same for any scene: TSSetFromOptions, then -ts_type euler and -ts_adapt_type none only,
/// -ts_max_steps >= 0, -ts_max_time > 0, 0 < -ts_dt <= hMin / cp unless unstableAllowed; with
/// damping (1/s) a warning above the damped step's bound (hMin / cp)(sqrt(1 + xi^2) - xi).
PetscErrorCode timeStepFromOptions(TS ts, double cp, double hMin, bool unstableAllowed,
                                   double damping = 0);

/// Unknown or misspelled options stop the run (options PETSc reads at exit are allowed; an option
/// of the other dimension was refused with its reason when the scene was read).
PetscErrorCode rejectUnusedOptions();

} // namespace gimp
