#include "gimp/solver/clock.hpp"

namespace gimp {

PetscErrorCode readStepClock(TS ts, bool halfStepStart, StepClock &c) {
  PetscReal t = 0, dt = 0;
  PetscCall(TSGetStepNumber(ts, &c.step));
  PetscCall(TSGetTime(ts, &t));
  PetscCall(TSGetTimeStep(ts, &dt));
  c.t = t;
  c.dt = dt;
  c.kick = c.step == 0 && halfStepStart ? 0.5 : 1.0;
  return PETSC_SUCCESS;
}

namespace {

/// The stage of this name: registered the first time, found after (a process that sets up more
/// than one run, as the in-process bad-input test does).
PetscErrorCode stage(const char *name, PetscLogStage &s) {
  PetscCall(PetscLogStageGetId(name, &s));
  if (s < 0) PetscCall(PetscLogStageRegister(name, &s));
  return PETSC_SUCCESS;
}

} // namespace

PetscErrorCode StepStages::registerAll() {
  PetscCall(stage("Setup", setup));
  PetscCall(stage("P2G", p2g));
  PetscCall(stage("Forces", forces));
  PetscCall(stage("Grid update", grid));
  PetscCall(stage("G2P", g2p));
  PetscCall(stage("Stress", stress));
  PetscCall(stage("Output", output));
  PetscCall(stage("Regrid", regrid));
  return PETSC_SUCCESS;
}

} // namespace gimp
