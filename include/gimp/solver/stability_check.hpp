// The critical time step of the current configuration (the stability room's eigenvalues) and
// what the run does with it: the step chosen without -ts_dt, the refusals of an explicit -ts_dt
// and of -gimp_penalty, and the re-checks every -gimp_stability_interval steps.
#pragma once

#include "gimp/solver/step.hpp"
#include "gimp/stability/stability.hpp"

namespace gimp {

template <int D> class StabilityCheck {
public:
  StabilityCheck(RunState<D> &s, Step<D> &step, stability::SlepcSession &slepc)
      : s_(s), step_(step), slepc_(slepc) {}
  /// At setup: dt_critical, the refusals of -ts_dt and -gimp_penalty, the step without -ts_dt.
  PetscErrorCode atStart();
  /// Every -gimp_stability_interval steps: the run stops when dt exceeds the new dt_critical.
  PetscErrorCode recheck(PetscInt step, double t);

private:
  /// Stencils and P2G of the current particles, then the eigenvalues of M^-1 K.
  PetscErrorCode estimate(bool springs, bool smallest, stability::Estimate &e);
  /// An explicit -ts_dt above dt_critical: refused, naming the penalty when its springs are why.
  PetscErrorCode refuseStep(double dt, const stability::Estimate &e);

  RunState<D> &s_;
  Step<D> &step_;
  stability::SlepcSession &slepc_;
};

} // namespace gimp
