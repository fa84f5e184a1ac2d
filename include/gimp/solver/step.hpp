// One explicit GIMP step as a short list of named phases (solver/step.cpp), the same in 2D and
// 3D:
//
//   migrate -> stencils (+ crack fields) -> P2G [+ crack faces, contact on P] -> [stress, USF]
//   -> forces -> grid update (TSStep) -> [crack contact] -> G2P (+ re-projection, corners)
//   -> work -> [stress, USL/MUSL] -> checks
//
// Nodal momentum is the TS solution (a DMComposite global Vec). TS type euler advances it with
// RHS = kick * mask * (f_int + f_ext - d p) (Eq. 8 and Eq. 16); the forces are computed by the
// forces phase before TSStep, so the RHS callback does no particle work and throws nothing.
// State that one phase hands to a later one is passed as a value (StepClock, StartPower). The
// multi-rate step (solver/multirate.hpp) and the stability check call the same phases.
#pragma once

#include "gimp/cracks/fields.hpp"
#include "gimp/particles/swarm.hpp"
#include "gimp/physics/tracking.hpp"
#include "gimp/solver/state.hpp"

#include <array>
#include <vector>

namespace gimp {

/// Power of the external and damping forces at the start of a step, for the step's work.
struct StartPower {
  double external = 0, damping = 0;
};

template <int D> class Step {
public:
  explicit Step(RunState<D> &s) : s_(s) {}
  Step(const Step &) = delete;
  Step &operator=(const Step &) = delete;

  /// One single-rate step, up to its checks (the run reports after it); `done` is the step and
  /// time it reached.
  PetscErrorCode run(StepClock &done);
  /// TS's right-hand side: kick * mask * (f - d p); ctx is the RunState.
  static PetscErrorCode rhs(TS ts, PetscReal t, Vec X, Vec F, void *ctx);

  // The phases (solver/step.cpp, transfers.cpp, contact.cpp, checks.cpp).
  PetscErrorCode migrate();
  /// Order this rank's particles by level-0 cell, then id (every -gimp_sort_interval steps);
  /// with rate classes `cls` (permuted along) by class first, and without `byCell` by class only.
  PetscErrorCode sortParticles(std::vector<int> *cls = nullptr, bool byCell = true);
  /// Make the rate classes `cls` contiguous and in order by moving only the particles outside
  /// their class's range (sortParticles without byCell).
  PetscErrorCode partitionClasses(std::vector<int> &cls);
  /// With the classes `cls` contiguous and in order: each class's range ordered by level-0 cell,
  /// then id, moving only the particles out of place (sortParticles with byCell).
  PetscErrorCode sortClassRanges(const std::vector<int> &cls);
  PetscErrorCode buildStencils(const ParticleView<D> &p, const double *centres);
  /// Where the stencils are centred: the positions, or (2D) tracking::domainCentres, copied when
  /// the affine transfer needs the centres after G2P has moved the particles.
  const double *stencilCentres(const ParticleView<D> &p);
  /// The centres of APIC's moments once the stencils are built: the stencils' centres, or with
  /// cpdi2 the weights' centroid sum_i S_ip x_i (the quadrilateral's, not the material point's).
  const double *affineCentres(const ParticleView<D> &p, const double *centres);
  /// The window coordinates of every slot (D per slot), built once.
  const double *slotCoordinates();
  /// Momentum of the particles' velocities (with APIC their affine fields) into the window
  /// array mom, and the mass into mass when it is not null.
  void projectMomentum(const Stencils<D> &st, const ParticleView<D> &p, const double *centres,
                       double *mom, double *mass);
  PetscErrorCode particlesToGrid(const ParticleView<D> &p, const double *centres);
  /// The internal force of the n particles (volumes V, stresses s) into the window array f
  /// (accumulated), in lanes where they run.
  void internalForce(const Stencils<D> &st, PetscInt n, const double *V, const double *s,
                     double *f) const;
  /// G2P of one rate class of a per-level step (transfer::gridToParticlesAffineRated with APIC,
  /// gridToParticlesRated otherwise), in lanes where they run.
  void gridToParticlesRated(const Stencils<D> &st, ParticleView<D> &q, const double *ug,
                            const double *wg, double dt, double flip, double *mom);
  PetscErrorCode forces(const ParticleView<D> &p, const StepClock &c, StartPower &power);
  /// The power of the damping and, with `external`, of nodal.fext at the step's start.
  PetscErrorCode startPower(StartPower &power, bool external);
  /// TSStep, the nodal velocity and acceleration (when the transfer reads it), the velocity (and
  /// acceleration) on the window.
  PetscErrorCode gridUpdate(bool accOnWindow = true);
  PetscErrorCode gridToParticles(ParticleView<D> &p, const StepClock &c, const double *centres);
  /// The step's work: damping, and the external forces unless `external` is false (the
  /// multi-rate step takes each class's external work over its own step). `dampingDots`, when
  /// given, holds the damping's sums P . v and rhs . v over every rank (the multi-rate step
  /// forms them on the values that can be nonzero); else they are VecDots here.
  PetscErrorCode work(const StepClock &c, const StartPower &power, bool external = true,
                      const std::array<PetscScalar, 2> *dampingDots = nullptr);
  /// The particles' test of checks() over a range: the first failing particle (or -1) and the
  /// particles leaving their rank's cells, summed over the ranges tested.
  struct CheckTally {
    PetscInt bad = -1;
    PetscInt64 leaving = 0;
  };
  /// The velocity gradient and the update of F, volume, stress and domain; with `tally`, each
  /// chunk of particles is then tested as checks() would test it, while it is in cache (the
  /// step's last change to the particles must be this update).
  PetscErrorCode stress(const Stencils<D> &st, ParticleView<D> &p, Vec velocityWindow, double dt,
                        double *strainBefore = nullptr, CheckTally *tally = nullptr);
  /// After the step: a particle that went bad stops the run on every rank; with it, in one
  /// reduction, the particles leaving their rank and SIGINT/SIGTERM. `tested` is the particles'
  /// test already made over all of them (by stress), or null.
  PetscErrorCode checks(const ParticleView<D> &p, PetscInt step, double t,
                        const CheckTally *tested = nullptr);
  // 2D cracks (contact.cpp): each field's face once per step, contact between the two fields.
  PetscErrorCode crackFaces(const ParticleView<D> &p, const std::vector<Vec> *classFaces);
  PetscErrorCode contactOnMomentum(const StepClock &c);
  /// Contact on a grid velocity (window velW, global vel) and, when accW is given, the same
  /// change / dt on the acceleration (window accW, global acc).
  PetscErrorCode crackContact(const StepClock &c, Vec velW, Vec vel, Vec accW, Vec acc);
  cracks::Contact<D> &contact() { return contact_; }
  /// The grid was rebuilt (levels that follow a point): what the step keeps of it is dropped.
  void gridChanged() { slotX_.clear(); }

private:
  /// XPIC(m): v* = sum_{k<m} (I - M^-1 S^T M_p S)^k v^n into nodal.vstarW.
  PetscErrorCode xpicFilter(const ParticleView<D> &p, const StepClock &c);
  /// MUSL's and the corners' re-projection; with `projected` G2P has put the particles' new
  /// momenta on the window already (nodal.sumW).
  PetscErrorCode reproject(ParticleView<D> &p, const StepClock &c, const double *centres,
                           bool projected);
  /// The G2P kernel of the scheme and transfer; `fused` re-projects each particle's momentum
  /// onto mom in the same pass.
  void gridToParticlesKernel(ParticleView<D> &p, const StepClock &c, const double *centres,
                             const double *vg, const double *ag, bool fused, double *mom);
  /// The first failing particle of this rank among k0 .. k1-1 (or -1) and, added to leaving,
  /// those leaving its cells.
  PetscInt firstBadParticle(const ParticleView<D> &p, PetscInt k0, PetscInt k1,
                            PetscInt64 &leaving) const;
  /// What of particle k grew beyond anything physical (speed, volume ratio), or "".
  std::string grewOf(const ParticleView<D> &p, PetscInt k) const;
  /// Why particle k failed, in one line.
  std::string failureOf(const ParticleView<D> &p, PetscInt k, PetscInt step, double t) const;

  RunState<D> &s_;
  std::vector<double> L_;             // velocity gradients of a chunk of particles (stress)
  std::vector<double> centres_;       // weight centres with corner tracking (cpdi2 with APIC)
  std::vector<double> slotX_;         // window coordinates of every slot (affine transfers)
  std::vector<double> xpicVp_;        // XPIC's interpolated field per particle (D each)
  std::vector<double> cpdiCorners_;   // the cpdi parallelograms (parallelepipeds) of this step
  tracking::CornerMotion<D> corners_; // corner tracking's motion of the corners
  cracks::Contact<D> contact_;        // contact between the two fields at cracked nodes
};

} // namespace gimp
