// The critical time step from the eigenvalues of the lumped-mass-scaled stiffness of the current
// configuration (SLEPc EPS on a shell matrix).
//
// K is applied with the step's own kernels on the step's stencils: a nodal displacement du
// becomes a particle strain by transfer::velocityGradient (du read as a velocity over dt = 1), a
// stress increment by the linear tangent (material::jaumannUpdate from zero stress: Hooke with
// lambda*, mu; the small-strain tangent for neo-Hookean; no geometric stiffness), nodal forces
// by transfer::internalForce, plus the change of the penalty forces of Eq. 9
// (physics::Boundary::penaltyIncrement). The result is masked (constrained and empty nodes) and
// divided by the lumped nodal mass of P2G. The traction term of Eq. 9 makes K non-symmetric.
//
// The update the step makes is central differences on two displacements. With FLIP the grid
// velocity projected from the particles (MUSL's re-projection, and every scheme's next P2G)
// advances as V^n+1 = V^n + dt R a^n with R = M^-1 M_c (M_c = S^T M_p S, the consistent mass).
// The stress (and F) follows it with MUSL (re-projected velocity) and USF (P2G velocity); with
// USL it follows the updated velocity V^n + dt a^n, as the particles' positions, which the
// penalty springs read, do: there (2 - R) stands for R. With a = -M^-1 (K_U U + K_W W) (K_U:
// internal force, the penalty's change of F and traction term; K_W: the springs on the positions),
// a period-2 mode z = -1 first appears when dt^2 reaches 4 / lambda_max of
//     B = M^-1 (K_U R + K_W (2 - R)),
// with USL K_U (2 - R) for K_U R. dt_critical = 2 / omega_max with
// omega_max^2 = lambda_max(B); with the damping d of Eq. 16 the bound is
// (2 / omega)(sqrt(1 + xi^2) - xi), xi = d / (2 omega), for one mode. The damping acts on the
// projected momentum and so reaches a mode through R as the force does: mode by mode the bound is
// omega_m^2 dt^2 + 2 r_m d dt < 4, and dt_critical is where the largest eigenvalue of
// dt^2 B + 2 d dt R reaches 4 (a bisection between that formula and min(2 / omega, 2 / d)).
#pragma once

#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"
#include "gimp/physics/boundary.hpp"

#include <petscvec.h>

namespace gimp::stability {

/// The critical step of central differences for the circular frequency omega with the damping
/// d of Eq. 16 [1/s]: (2 / omega)(sqrt(1 + xi^2) - xi), xi = d / (2 omega).
double criticalStep(double omega, double damping);

/// What the operator reads: the configuration the step would see, and the masks of P2G.
template <int D> struct OperatorInput {
  const Scene<D> *sc = nullptr;
  const Grid<D> *grid = nullptr;
  const Stencils<D> *st = nullptr;
  const ParticleView<D> *p = nullptr;
  const physics::Boundary<D> *boundary = nullptr; // null: no penalty conditions
  bool springs = true;                            // false: the penalty springs left out
  bool stressOnUpdated = false;          // USL: the stress follows V^n + dt a^n, (2 - R) x, not R x
  Vec mask = nullptr, invMass = nullptr; // global, from P2G
  // APIC: R is the affine re-projection, about the stencils' centres with the slots' coordinates
  // (D per particle and per slot); null: the FLIP/PIC re-projection.
  const double *centres = nullptr, *slotX = nullptr;
};

/// The eigenvalues that bound the step.
struct Estimate {
  double lambdaRe = 0, lambdaIm = 0; // largest magnitude eigenvalue of B [1/s^2]
  double omega = 0;                  // sqrt(max(lambdaRe, 0)) [rad/s]
  double dtCritical = 0; // 2 / omega; with damping d where lambda_max(dt^2 B + 2 d dt R) = 4 [s]
  PetscInt dampedIterations = 0; // the eigen-solver's iterations of that search
  PetscInt iterations = 0;
  bool hasSmallest = false; // the smallest real part was computed (traction term)
  double smallestRe = 0, smallestIm = 0;
  PetscInt smallestIterations = 0;
  // With `smallest` also the eigenvalue of largest imaginary part: central differences grow at
  // the rate Im sqrt(lambda) on a complex eigenvalue whatever the step.
  double complexRe = 0, complexIm = 0;
  PetscInt complexIterations = 0;
  bool complexConverged = false;
};

/// Largest magnitude eigenvalue of B and, when `smallest`, the ones of smallest real part and
/// largest imaginary part (collective). Throws an InputError on every rank when the eigen-solver
/// does not converge.
template <int D>
PetscErrorCode estimate(MPI_Comm comm, const OperatorInput<D> &in, bool smallest, Estimate &e);

/// SLEPc started after PETSc for the solver's lifetime (no-op without SLEPc).
class SlepcSession {
public:
  SlepcSession() = default;
  SlepcSession(const SlepcSession &) = delete;
  SlepcSession &operator=(const SlepcSession &) = delete;
  ~SlepcSession();
  PetscErrorCode start();

private:
  bool started_ = false;
};

} // namespace gimp::stability
