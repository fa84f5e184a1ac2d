// The run loop: a (coarse) step, its reports and checkpoints until TS's step or time limit, the
// rest criterion, a failure or an interrupt; then the final outputs.
#include "gimp/solver/solver.hpp"

#include <csignal>

namespace gimp {

template <int D> PetscErrorCode Solver<D>::run() {
  RunState<D> &s = s_;
  if (s.sc.help) return PETSC_SUCCESS;
  if (s.sc.restart.empty()) PetscCall(reporter_.start()); // a restart continues its checkpoint's
  PetscInt steps = 0, maxSteps = 0;
  PetscReal t = 0, maxTime = 0;
  PetscCall(TSGetStepNumber(s.ts, &steps));
  PetscCall(TSGetTime(s.ts, &t));
  PetscCall(TSGetMaxSteps(s.ts, &maxSteps));
  PetscCall(TSGetMaxTime(s.ts, &maxTime));
  PetscCall(TSMonitor(s.ts, steps, t, s.nodal.P));
  const RunStatus &st = s.status;
  while (steps < maxSteps && t < maxTime && !st.failed && !st.atRest && !st.interrupt) {
    if (s.sc.stabilityInterval > 0 && steps > 0 && steps % s.sc.stabilityInterval == 0) {
      PetscCall(stability_.recheck(steps, t));
      if (st.failed) break;
    }
    PetscCall(advance());
    PetscCall(TSGetStepNumber(s.ts, &steps));
    PetscCall(TSGetTime(s.ts, &t));
    // The state after the step's report: a restart from it continues with the next step.
    const bool due = dueIn(steps - s.stride() + 1, steps + 1, s.sc.checkpointInterval);
    if (!st.failed && (due || st.interrupt)) PetscCall(checkpoint_.write(steps, t));
  }
  // A signal during the last step: the run is complete (its checkpoint stays as written).
  if (steps >= maxSteps || t >= maxTime) s.status.interrupt = 0;
  if (st.interrupt && !st.failed)
    PetscCall(PetscPrintf(s.comm,
                          "gimp: interrupted by %s at step %" PetscInt_FMT " t %.9g s: "
                          "checkpoint %s/checkpoint.h5 written\n",
                          st.interrupt == SIGINT ? "SIGINT" : "SIGTERM", steps, t,
                          s.sc.outputDir.c_str()));
  PetscCall(TSViewFromOptions(s.ts, nullptr, "-ts_view"));
  return reporter_.finish(steps, t);
}

template <int D> PetscErrorCode Solver<D>::advance() {
  StepClock done;
  PetscInt step = 0;
  PetscReal t = 0;
  PetscCall(TSGetStepNumber(s_.ts, &step));
  PetscCall(TSGetTime(s_.ts, &t));
  PetscCall(reporter_.energiesDue(step, t, s_.work.measureStrain));
  if (multirate_)
    PetscCall(multirate_->run(done)); // R fine steps, a step per level (multirate.cpp)
  else
    PetscCall(step_.run(done));
  PetscCall(reporter_.report(done.step, done.t));
  PetscCall(growCracks(done.step, done.t));
  return followLevels(done.step, done.t);
}

template PetscErrorCode Solver<2>::run();
template PetscErrorCode Solver<3>::run();

} // namespace gimp
