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

PetscErrorCode StepStages::registerAll() {
  PetscCall(PetscLogStageRegister("P2G", &p2g));
  PetscCall(PetscLogStageRegister("Forces", &forces));
  PetscCall(PetscLogStageRegister("Grid update", &grid));
  PetscCall(PetscLogStageRegister("G2P", &g2p));
  PetscCall(PetscLogStageRegister("Stress", &stress));
  PetscCall(PetscLogStageRegister("Output", &output));
  return PETSC_SUCCESS;
}

} // namespace gimp
