// The critical time step of the current configuration (the stability room's eigenvalues) and
// what the run does with it: the step chosen without -ts_dt, the refusals of an explicit -ts_dt
// and of -gimp_penalty, and the re-checks every -gimp_stability_interval steps.
#include "gimp/solver/solver.hpp"

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

PetscErrorCode Solver::stabilityEstimate(bool springs, bool smallest, stability::Estimate &e) {
  // The step's own phases build the stencils and the nodal mass and masks; the next step
  // rebuilds them, so the nodal vectors may be overwritten here.
  PetscCall(slepc_.start());
  PetscCall(migrate());
  ParticleView<2> p;
  PetscCall(p.get(sw_));
  const double *centres = stencilCentres(p);
  PetscCall(buildStencils(p, centres));
  centres = affineCentres(p, centres);
  PetscCall(particlesToGrid(p, centres));
  stability::OperatorInput in;
  in.sc = &sc_;
  in.grid = &grid_;
  in.st = &st_;
  in.p = &p;
  in.boundary = sc_.dbcs.empty() ? nullptr : &boundary_;
  in.springs = springs;
  in.stressOnUpdated = !scheme_.stressFromReprojection && !scheme_.stressBeforeGridUpdate;
  in.mask = nodal_.mask;
  in.invMass = nodal_.invMass;
  if (sc_.transfer == Transfer::Apic) { // R: APIC's affine re-projection
    in.centres = centres;
    in.slotX = slotCoordinates();
  }
  try {
    PetscCall(stability::estimate(comm_, in, smallest, e));
  } catch (...) {
    (void)p.restore(sw_);
    throw;
  }
  PetscCall(p.restore(sw_));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::stabilityAtStart() {
  PetscBool explicitDt = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-ts_dt", &explicitDt));
  const bool traction = !sc_.dbcs.empty() && sc_.penaltyTraction;
  stability::Estimate e;
  PetscCall(stabilityEstimate(true, traction, e));
  dtCritical_ = e.dtCritical;
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(ts_, &dt));
  if (!explicitDt) {
    dt = sc_.cfl * e.dtCritical;
    PetscCall(TSSetTimeStep(ts_, dt));
  }
  PetscCall(PetscPrintf(
      comm_,
      "gimp: stability: omega_max = %.6g rad/s (eigenvalue %.6g%+.3gi of B = "
      "M^-1 (K_U %s + K_W (2 - R)), %" PetscInt_FMT " iterations), dt_critical = %.6g s, dt = %.6g "
      "s (%s)\n",
      e.omega, e.lambdaRe, e.lambdaIm,
      scheme_.stressFromReprojection || scheme_.stressBeforeGridUpdate ? "R" : "(2 - R)",
      e.iterations, e.dtCritical, dt, explicitDt ? "-ts_dt" : "-gimp_cfl x dt_critical"));
  if (sc_.transfer == Transfer::Xpic)
    PetscCall(PetscPrintf(comm_, "gimp: stability: R is the PIC re-projection: with xpic "
                                 "dt_critical is an estimate not verified (docs/method.md)\n"));
  if (e.hasSmallest)
    PetscCall(PetscPrintf(
        comm_,
        "gimp: stability: smallest real part %.6g%+.3gi (%" PetscInt_FMT
        " iterations), largest imaginary part %.6g%+.3gi (%" PetscInt_FMT " iterations%s)\n",
        e.smallestRe, e.smallestIm, e.smallestIterations, e.complexRe, e.complexIm,
        e.complexIterations, e.complexConverged ? "" : ", not converged"));
  if (e.hasSmallest) refuseGrowingModes(e, boundary_.alpha());
  if (!(dt > e.dtCritical) || sc_.allowUnstableDt) return PETSC_SUCCESS;
  if (!sc_.dbcs.empty()) { // is it the penalty springs that make the step unstable?
    stability::Estimate free;
    PetscCall(stabilityEstimate(false, false, free));
    if (dt <= free.dtCritical)
      throw InputError("option -gimp_penalty " + formatNumber(boundary_.alpha()) +
                       ": its springs lower dt_critical to " + formatNumber(e.dtCritical) +
                       " s, below -ts_dt " + formatNumber(dt) + " (without them " +
                       formatNumber(free.dtCritical) + " s); lower it, or -ts_dt");
  }
  throw InputError("option -ts_dt " + formatNumber(dt) +
                   ": exceeds dt_critical = " + formatNumber(e.dtCritical) +
                   " s (largest eigenvalue of the step operator B); choose -ts_dt <= " +
                   formatNumber(e.dtCritical) + ", or -gimp_allow_unstable_dt to run it anyway");
}

PetscErrorCode Solver::stabilityRecheck(PetscInt step, double t) {
  stability::Estimate e;
  PetscCall(stabilityEstimate(true, false, e));
  dtCritical_ = std::fmin(dtCritical_, e.dtCritical);
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(ts_, &dt));
  PetscCall(PetscInfo(nullptr,
                      "step %" PetscInt_FMT ": dt_critical %g s (%" PetscInt_FMT " iterations)\n",
                      step, e.dtCritical, e.iterations));
  if (!(dt > e.dtCritical)) return PETSC_SUCCESS;
  if (sc_.allowUnstableDt) {
    PetscCall(PetscPrintf(comm_,
                          "gimp: warning: step %" PetscInt_FMT " t %.9g s: dt %.6g s exceeds the "
                          "critical step %.6g s of the current configuration\n",
                          step, t, dt, e.dtCritical));
    return PETSC_SUCCESS;
  }
  failed_ = true; // every rank has the same eigenvalue
  PetscCall(PetscPrintf(comm_,
                        "gimp: error: step %" PetscInt_FMT " t %.9g s: dt %.6g s exceeds the "
                        "critical step %.6g s of the current configuration (the run would go "
                        "unstable; reduce -ts_dt)\n",
                        step, t, dt, e.dtCritical));
  return PETSC_SUCCESS;
}

} // namespace gimp
