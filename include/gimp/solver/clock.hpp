// The clock a step reads from TS, the -log_view stages its phases run in, and which steps a
// report falls due in.
#pragma once

#include "gimp/core/petsc_compat.hpp"

#include <petscts.h>

namespace gimp {

/// Where a step stands: its index and time at the start, the time step, and the fraction of
/// the force it applies (0.5 on a leapfrog start, else 1).
struct StepClock {
  PetscInt step = 0;
  double t = 0, dt = 0, kick = 1;
};

/// The clock of the step TS is about to take; with `halfStepStart` the first step kicks by half
/// the force, so particle velocities stand at half steps and x += dt v, v += dt a is second
/// order in time.
PetscErrorCode readStepClock(TS ts, bool halfStepStart, StepClock &c);

/// The run's -log_view stages: Setup, and the step's P2G, Forces, Grid update, G2P, Stress,
/// Output.
struct StepStages {
  PetscLogStage setup = 0, p2g = 0, forces = 0, grid = 0, g2p = 0, stress = 0, output = 0;
  PetscLogStage regrid = 0; // level boxes that follow a point: their moves
  PetscErrorCode registerAll();
};

/// Whether a multiple of `interval` lies in [a, b): a report due within a (coarse) step.
inline bool dueIn(PetscInt a, PetscInt b, PetscInt interval) {
  return interval > 0 && (b - 1) / interval * interval >= a;
}

} // namespace gimp
