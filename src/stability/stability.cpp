#include "gimp/stability/stability.hpp"

#include "gimp/physics/material.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/internal_force.hpp"
#include "gimp/transfer/transfer.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#ifdef GIMP_HAVE_SLEPC
#include <slepceps.h>
#endif

namespace gimp::stability {

double criticalStep(double omega, double damping) {
  if (!(omega > 0)) return INFINITY;
  const double xi = damping / (2.0 * omega);
  return (2.0 / omega) * (std::sqrt(1.0 + xi * xi) - xi);
}

#ifdef GIMP_HAVE_SLEPC

namespace {

/// The linear tangent of the material at zero stress, into ds (Hooke with lambda*, mu; the
/// small-strain tangent for neo-Hookean): the Jaumann update of a zero stress over dt = 1.
template <int D> void tangentStress(const Material &m, const double *L, double *ds) {
  Tensor<D> dsk = Tensor<D>::Zero();
  if constexpr (D == 2) {
    double szz = 0;
    material::jaumannUpdate(m, tensorAt<2>(L, 0), 1.0, dsk, szz);
  } else {
    material::jaumannUpdate(m, Tensor<3>(tensorAt<3>(L, 0)), 1.0, dsk);
  }
  setStress<D>(ds, 0, dsk);
}

/// The shell matrix's context: the input and the work vectors of one application.
template <int D> struct Shell {
  OperatorInput<D> in;
  Vec xm = nullptr, r = nullptr, w = nullptr; // global
  Vec uW = nullptr, fW = nullptr;             // window
  std::vector<double> L, ds, vp, xp, B, C;    // B, C: APIC's affine fields
  double bScale = 1, rScale = 0;              // the shell applies bScale B + rScale R
};

/// out = R in, R = M^-1 M_c the re-projection of MUSL: `in` interpolated to the particles (G2P
/// with dt = 0 and no FLIP, on scratch arrays) and projected back (P2G, masked, over the nodal
/// mass).
template <int D> PetscErrorCode reproject(Shell<D> &s, Vec in, Vec out) {
  const ParticleView<D> &p = *s.in.p;
  PetscCall(s.in.grid->toWindow(in, s.uW));
  const PetscScalar *u = nullptr;
  PetscScalar *mom = nullptr;
  const bool affine = s.in.centres != nullptr;
  PetscCall(VecGetArrayRead(s.uW, &u));
  if (affine) {
    transfer::gridToParticlesAffine<D>(*s.in.st, p.n, u, s.in.centres, s.in.slotX, 0.0, s.vp.data(),
                                       s.B.data(), s.xp.data());
    transfer::affineVelocity<D>(*s.in.st, p.n, s.in.centres, s.in.slotX, s.B.data(), s.C.data());
  } else {
    transfer::gridToParticles<D>(*s.in.st, p.n, u, u, 0.0, 0.0, s.vp.data(), s.xp.data());
  }
  PetscCall(VecRestoreArrayRead(s.uW, &u));
  PetscCall(VecZeroEntries(s.fW));
  PetscCall(VecGetArray(s.fW, &mom));
  if (affine)
    transfer::particlesToGridAffine<D>(*s.in.st, p.n, p.m, s.vp.data(), s.C.data(), s.in.centres,
                                       s.in.slotX, mom, nullptr);
  else
    transfer::particlesToGrid<D>(*s.in.st, p.n, p.m, s.vp.data(), mom, nullptr);
  PetscCall(VecRestoreArray(s.fW, &mom));
  PetscCall(VecZeroEntries(out));
  PetscCall(s.in.grid->addFromWindow(s.fW, out));
  PetscCall(VecPointwiseMult(out, out, s.in.invMass));
  return PETSC_SUCCESS;
}

/// y = M^-1 (K_U R x + K_W (2 - R) x) (USL: K_U (2 - R) x) on the masked x (see the header): K_U
/// from the stress (internal force, and the penalty's change of F and traction term), K_W the
/// penalty springs on the particles' positions. With USL the stress part is on (2 - R) x as well.
template <int D> PetscErrorCode applyOperator(Mat A, Vec x, Vec y) {
  Shell<D> *s = nullptr;
  PetscCall(MatShellGetContext(A, &s));
  const OperatorInput<D> &in = s->in;
  const ParticleView<D> &p = *in.p;
  PetscCall(VecPointwiseMult(s->xm, x, in.mask));
  PetscCall(reproject(*s, s->xm, s->r));
  const bool positions = in.boundary && in.springs;
  PetscCall(VecAXPBYPCZ(s->w, 2.0, -1.0, 0.0, s->xm, s->r)); // (2 - R) x
  // The stress part: on R x (MUSL, USF) or on (2 - R) x (USL).
  PetscCall(in.grid->toWindow(in.stressOnUpdated ? s->w : s->r, s->uW));
  const PetscScalar *u = nullptr;
  PetscScalar *f = nullptr;
  PetscCall(VecGetArrayRead(s->uW, &u));
  transfer::velocityGradient<D>(*in.st, p.n, u, s->L.data());
  PetscCall(VecRestoreArrayRead(s->uW, &u));
  for (PetscInt k = 0; k < p.n; ++k) // the linear tangent: Hooke from zero stress
    tangentStress<D>(in.sc->materialOf(p.id[k]), s->L.data() + D * D * k,
                     s->ds.data() + kStress<D> * k);
  PetscCall(VecZeroEntries(s->fW));
  PetscCall(VecGetArray(s->fW, &f));
  transfer::internalForce<D>(*in.st, p.n, p.V, s->ds.data(), f);
  if (in.boundary)
    in.boundary->penaltyIncrement(*in.sc, *in.grid, *in.st, p, nullptr, s->L.data(), s->ds.data(),
                                  in.springs, f);
  PetscCall(VecRestoreArray(s->fW, &f));
  if (positions) { // the springs on the positions, on (2 - R) x
    PetscCall(in.grid->toWindow(s->w, s->uW));
    PetscCall(VecGetArrayRead(s->uW, &u));
    PetscCall(VecGetArray(s->fW, &f));
    in.boundary->penaltyIncrement(*in.sc, *in.grid, *in.st, p, u, nullptr, nullptr, true, f);
    PetscCall(VecRestoreArray(s->fW, &f));
    PetscCall(VecRestoreArrayRead(s->uW, &u));
  }
  PetscCall(VecZeroEntries(y));
  PetscCall(in.grid->addFromWindow(s->fW, y));
  PetscCall(VecPointwiseMult(y, y, in.invMass));
  PetscCall(VecScale(y, -1.0));
  if (s->rScale != 0) PetscCall(VecAXPBY(y, s->rScale, s->bScale, s->r));
  return PETSC_SUCCESS;
}

/// One eigenvalue of A by EPS (non-Hermitian), the `which` end of the spectrum.
/// Without `converged` a failure to converge is an InputError; with it, it is reported there.
PetscErrorCode solveOne(MPI_Comm comm, Mat A, EPSWhich which, const char *what, double &re,
                        double &im, PetscInt &its, bool *converged = nullptr) {
  EPS eps = nullptr;
  PetscCall(EPSCreate(comm, &eps));
  PetscCall(EPSSetOperators(eps, A, nullptr));
  PetscCall(EPSSetProblemType(eps, EPS_NHEP));
  PetscCall(EPSSetWhichEigenpairs(eps, which));
  PetscCall(EPSSetDimensions(eps, 1, PETSC_DEFAULT, PETSC_DEFAULT));
  PetscCall(EPSSetTolerances(eps, 1e-8, 5000));
  PetscCall(EPSSetOptionsPrefix(eps, "gimp_stability_"));
  PetscCall(EPSSetFromOptions(eps));
  PetscCall(EPSSolve(eps));
  PetscInt nconv = 0, maxIt = 0;
  PetscReal tol = 0;
  PetscCall(EPSGetConverged(eps, &nconv));
  PetscCall(EPSGetIterationNumber(eps, &its));
  PetscCall(EPSGetTolerances(eps, &tol, &maxIt));
  PetscScalar kr = 0, ki = 0;
  if (nconv > 0) PetscCall(EPSGetEigenpair(eps, 0, &kr, &ki, nullptr, nullptr));
  PetscCall(EPSDestroy(&eps));
  if (converged) *converged = nconv > 0;
  if (nconv < 1 && !converged)
    throw InputError("option -gimp_stability_check: the eigen-solver found no " +
                     std::string(what) + " eigenvalue of B in " + std::to_string(maxIt) +
                     " iterations (tolerance " + formatNumber(tol) +
                     "); raise -gimp_stability_eps_max_it or -gimp_stability_eps_ncv");
  if (nconv < 1) kr = ki = 0;
  re = PetscRealPart(kr);
  im = PetscRealPart(ki);
  return PETSC_SUCCESS;
}

} // namespace

/// The critical step with the damping d of Eq. 16. The damping acts on the projected momentum, so
/// like the force it reaches a mode through R: mode by mode central differences are stable for
/// omega_m^2 dt^2 + 2 r_m d dt < 4 (r_m R's eigenvalue on the mode), and with large d the low
/// modes (r_m near 1) bound dt before the highest one. dt_critical is where the largest eigenvalue
/// of dt^2 B + 2 d dt R reaches 4, found by bisection between (2 / omega)(sqrt(1 + xi^2) - xi),
/// xi = d / (2 omega) (every r_m taken as 1: below every mode's bound) and min(2 / omega, 2 / d).
/// The lower end of the last bracket is returned (stable side).
template <int D>
PetscErrorCode dampedStep(MPI_Comm comm, Mat A, Shell<D> &s, double omega, double d, double &dt,
                          PetscInt &its) {
  double lo = criticalStep(omega, d), hi = std::min(2.0 / omega, 2.0 / d);
  for (int k = 0; k < 14 && hi > lo * (1.0 + 1e-4); ++k) {
    const double mid = 0.5 * (lo + hi);
    double re = 0, im = 0;
    PetscInt n = 0;
    s.bScale = mid * mid;
    s.rScale = 2.0 * d * mid;
    PetscCall(solveOne(comm, A, EPS_LARGEST_MAGNITUDE, "damped largest", re, im, n));
    its += n;
    (re < 4.0 ? lo : hi) = mid;
  }
  s.bScale = 1;
  s.rScale = 0;
  dt = lo;
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode estimate(MPI_Comm comm, const OperatorInput<D> &in, bool smallest, Estimate &e) {
  Shell<D> s;
  s.in = in;
  const size_t n = static_cast<size_t>(in.p->n);
  s.L.assign(D * D * n, 0.0);
  s.ds.assign(kStress<D> * n, 0.0);
  s.vp.assign(D * n, 0.0);
  s.xp.assign(D * n, 0.0);
  if (in.centres) {
    s.B.assign(D * D * n, 0.0);
    s.C.assign(D * D * n, 0.0);
  }
  PetscCall(DMCreateGlobalVector(in.grid->dm, &s.xm));
  PetscCall(VecDuplicate(s.xm, &s.r));
  PetscCall(VecDuplicate(s.xm, &s.w));
  PetscCall(in.grid->createWindowVec(&s.uW));
  PetscCall(in.grid->createWindowVec(&s.fW));
  PetscInt nLocal = 0, nGlobal = 0;
  PetscCall(VecGetLocalSize(s.xm, &nLocal));
  PetscCall(VecGetSize(s.xm, &nGlobal));
  Mat A = nullptr;
  PetscCall(MatCreateShell(comm, nLocal, nLocal, nGlobal, nGlobal, &s, &A));
  PetscCall(
      MatShellSetOperation(A, MATOP_MULT, reinterpret_cast<void (*)(void)>(applyOperator<D>)));
  PetscCall(MatShellSetVecType(A, VECSTANDARD));
  try {
    PetscCall(
        solveOne(comm, A, EPS_LARGEST_MAGNITUDE, "largest", e.lambdaRe, e.lambdaIm, e.iterations));
    e.omega = std::sqrt(std::max(e.lambdaRe, 0.0));
    e.dtCritical = criticalStep(e.omega, in.sc->damping);
    if (in.sc->damping > 0 && e.omega > 0)
      PetscCall(dampedStep(comm, A, s, e.omega, in.sc->damping, e.dtCritical, e.dampedIterations));
    e.hasSmallest = smallest;
    if (smallest) {
      PetscCall(solveOne(comm, A, EPS_SMALLEST_REAL, "smallest real", e.smallestRe, e.smallestIm,
                         e.smallestIterations));
      PetscCall(solveOne(comm, A, EPS_LARGEST_IMAGINARY, "largest imaginary", e.complexRe,
                         e.complexIm, e.complexIterations, &e.complexConverged));
    }
  } catch (...) {
    (void)MatDestroy(&A);
    (void)VecDestroy(&s.fW);
    (void)VecDestroy(&s.uW);
    (void)VecDestroy(&s.xm);
    (void)VecDestroy(&s.r);
    (void)VecDestroy(&s.w);
    throw;
  }
  PetscCall(MatDestroy(&A));
  PetscCall(VecDestroy(&s.fW));
  PetscCall(VecDestroy(&s.uW));
  PetscCall(VecDestroy(&s.xm));
  PetscCall(VecDestroy(&s.r));
  PetscCall(VecDestroy(&s.w));
  return PETSC_SUCCESS;
}

template PetscErrorCode estimate<2>(MPI_Comm, const OperatorInput<2> &, bool, Estimate &);
template PetscErrorCode estimate<3>(MPI_Comm, const OperatorInput<3> &, bool, Estimate &);

SlepcSession::~SlepcSession() {
  if (started_) (void)SlepcFinalize();
}

PetscErrorCode SlepcSession::start() {
  PetscBool on = PETSC_FALSE;
  PetscCall(SlepcInitialized(&on));
  if (on) return PETSC_SUCCESS;
  PetscCall(SlepcInitializeNoArguments());
  started_ = true;
  return PETSC_SUCCESS;
}

#else // without SLEPc the option is refused when the scene is read

template <int D> PetscErrorCode estimate(MPI_Comm, const OperatorInput<D> &, bool, Estimate &) {
  throw InputError("option -gimp_stability_check true: needs gimp built with SLEPc");
}
template PetscErrorCode estimate<2>(MPI_Comm, const OperatorInput<2> &, bool, Estimate &);
template PetscErrorCode estimate<3>(MPI_Comm, const OperatorInput<3> &, bool, Estimate &);

SlepcSession::~SlepcSession() = default;

PetscErrorCode SlepcSession::start() {
  return PETSC_SUCCESS;
}

#endif

} // namespace gimp::stability
