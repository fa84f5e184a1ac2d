// The critical time step of the current configuration (the stability room's eigenvalues) and
// what the run does with it: the step chosen without -ts_dt, the refusals of an explicit -ts_dt
// and of -gimp_penalty, and the re-checks every -gimp_stability_interval steps.
#include "gimp/solver/stability_check.hpp"

#include <cmath>
#include <complex>
#include <string>

namespace gimp {

namespace {

/// The traction term of Eq. 9 is not symmetric: below some penalty it gives B eigenvalues of
/// negative real part or with an imaginary part, whose modes grow whatever the step (at the rate
/// Im sqrt(lambda)). Beyond round-off of the largest eigenvalue they are refused. A search for
/// the largest imaginary part that does not converge refuses nothing (it is printed).
void refuseGrowingModes(const stability::Estimate &e, double alpha) {
  const double roundoff = 1e-6 * std::hypot(e.lambdaRe, e.lambdaIm);
  std::string what;
  if (e.smallestRe < -roundoff) {
    what = "an eigenvalue of negative real part (" + formatNumber(e.smallestRe) + " 1/s^2)";
  } else if (e.complexConverged && std::fabs(e.complexIm) > roundoff) {
    const double growth = std::sqrt(std::complex<double>(e.complexRe, e.complexIm)).imag();
    what = "a complex eigenvalue (" + formatNumber(e.complexRe) + " + " +
           formatNumber(std::fabs(e.complexIm)) + "i 1/s^2, growth " +
           formatNumber(std::fabs(growth)) + " 1/s)";
  }
  if (what.empty()) return;
  throw InputError("option -gimp_penalty " + formatNumber(alpha) +
                   ": the traction term of Eq. 9 "
                   "gives B " +
                   what +
                   ", unstable at every -ts_dt; raise it, or use "
                   "-gimp_penalty_traction false");
}

} // namespace

template <int D>
PetscErrorCode StabilityCheck<D>::estimate(bool springs, bool smallest, stability::Estimate &e) {
  // The step's own phases build the stencils and the nodal mass and masks; the next step
  // rebuilds them, so the nodal vectors may be overwritten here.
  RunState<D> &s = s_;
  PetscCall(slepc_.start());
  PetscCall(step_.migrate());
  ParticleView<D> p;
  PetscCall(p.get(s.sw));
  const double *centres = step_.stencilCentres(p);
  PetscCall(step_.buildStencils(p, centres));
  centres = step_.affineCentres(p, centres);
  PetscCall(step_.particlesToGrid(p, centres));
  stability::OperatorInput<D> in;
  in.sc = &s.sc;
  in.grid = &s.grid;
  in.st = &s.st;
  in.p = &p;
  in.boundary = s.sc.dbcs.empty() ? nullptr : &s.boundary;
  in.springs = springs;
  in.stressOnUpdated = !s.scheme.stressFromReprojection && !s.scheme.stressBeforeGridUpdate;
  in.mask = s.nodal.mask;
  in.invMass = s.nodal.invMass;
  if (s.sc.transfer == Transfer::Apic) { // R: APIC's affine re-projection
    in.centres = centres;
    in.slotX = step_.slotCoordinates();
  }
  try {
    PetscCall(stability::estimate<D>(s.comm, in, smallest, e));
  } catch (...) {
    (void)p.restore(s.sw);
    throw;
  }
  PetscCall(p.restore(s.sw));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode StabilityCheck<D>::atStart() {
  RunState<D> &s = s_;
  PetscBool explicitDt = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-ts_dt", &explicitDt));
  const bool traction = !s.sc.dbcs.empty() && s.sc.penaltyTraction;
  stability::Estimate e;
  PetscCall(estimate(true, traction, e));
  s.measures.dtCritical = e.dtCritical;
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(s.ts, &dt));
  if (!explicitDt) {
    dt = s.sc.cfl * e.dtCritical;
    PetscCall(TSSetTimeStep(s.ts, dt));
  }
  PetscCall(PetscPrintf(
      s.comm,
      "gimp: stability: omega_max = %.6g rad/s (eigenvalue %.6g%+.3gi of B = "
      "M^-1 (K_U %s + K_W (2 - R)), %" PetscInt_FMT " iterations), dt_critical = %.6g s, dt = %.6g "
      "s (%s)\n",
      e.omega, e.lambdaRe, e.lambdaIm,
      s.scheme.stressFromReprojection || s.scheme.stressBeforeGridUpdate ? "R" : "(2 - R)",
      e.iterations, e.dtCritical, dt, explicitDt ? "-ts_dt" : "-gimp_cfl x dt_critical"));
  if (s.sc.transfer == Transfer::Xpic)
    PetscCall(PetscPrintf(s.comm, "gimp: stability: R is the PIC re-projection: with xpic "
                                  "dt_critical is an estimate not verified (docs/method.md)\n"));
  if (e.hasSmallest)
    PetscCall(PetscPrintf(
        s.comm,
        "gimp: stability: smallest real part %.6g%+.3gi (%" PetscInt_FMT
        " iterations), largest imaginary part %.6g%+.3gi (%" PetscInt_FMT " iterations%s)\n",
        e.smallestRe, e.smallestIm, e.smallestIterations, e.complexRe, e.complexIm,
        e.complexIterations, e.complexConverged ? "" : ", not converged"));
  if (e.hasSmallest) refuseGrowingModes(e, s.boundary.alpha());
  if (!(dt > e.dtCritical)) return PETSC_SUCCESS;
  if (!s.sc.allowUnstableDt) return refuseStep(dt, e);
  // Allowed, but said at the start: such a run goes unstable, often hundreds of steps later.
  PetscCall(PetscPrintf(s.comm,
                        "gimp: warning: -ts_dt %s s exceeds dt_critical = %s s "
                        "(-gimp_allow_unstable_dt): the run will likely go unstable; %s\n",
                        formatNumber(dt).c_str(), formatNumber(e.dtCritical).c_str(),
                        s.stepAgainstCfl().c_str()));
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode StabilityCheck<D>::refuseStep(double dt, const stability::Estimate &e) {
  const RunState<D> &s = s_;
  if (!s.sc.dbcs.empty()) { // is it the penalty springs that make the step unstable?
    stability::Estimate free;
    PetscCall(estimate(false, false, free));
    if (dt <= free.dtCritical)
      throw InputError("option -gimp_penalty " + formatNumber(s.boundary.alpha()) +
                       ": its springs lower dt_critical to " + formatNumber(e.dtCritical) +
                       " s, below -ts_dt " + formatNumber(dt) + " (without them " +
                       formatNumber(free.dtCritical) + " s); lower it, or -ts_dt");
  }
  throw InputError("option -ts_dt " + formatNumber(dt) +
                   ": exceeds dt_critical = " + formatNumber(e.dtCritical) +
                   " s (largest eigenvalue of the step operator B); choose -ts_dt <= " +
                   formatNumber(e.dtCritical) + ", or -gimp_allow_unstable_dt to run it anyway");
}

template <int D> PetscErrorCode StabilityCheck<D>::recheck(PetscInt step, double t) {
  RunState<D> &s = s_;
  stability::Estimate e;
  PetscCall(estimate(true, false, e));
  s.measures.dtCritical = std::fmin(s.measures.dtCritical, e.dtCritical);
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(s.ts, &dt));
  PetscCall(PetscInfo(nullptr,
                      "step %" PetscInt_FMT ": dt_critical %g s (%" PetscInt_FMT " iterations)\n",
                      step, e.dtCritical, e.iterations));
  if (!(dt > e.dtCritical)) return PETSC_SUCCESS;
  if (s.sc.allowUnstableDt) {
    PetscCall(PetscPrintf(s.comm,
                          "gimp: warning: step %" PetscInt_FMT " t %.9g s: dt %.6g s exceeds the "
                          "critical step %.6g s of the current configuration\n",
                          step, t, dt, e.dtCritical));
    return PETSC_SUCCESS;
  }
  s.status.failed = true; // every rank has the same eigenvalue
  char line[384];
  std::snprintf(line, sizeof(line),
                "step %lld t %.9g s: dt %.6g s exceeds the critical step %.6g s of the current "
                "configuration (the run would go unstable; reduce -ts_dt); %s",
                static_cast<long long>(step), t, dt, e.dtCritical, s.stepAgainstCfl().c_str());
  s.status.failure = line;
  PetscCall(PetscPrintf(s.comm, "gimp: error: %s\n", line));
  return PETSC_SUCCESS;
}

template class StabilityCheck<2>;
template class StabilityCheck<3>;

} // namespace gimp
