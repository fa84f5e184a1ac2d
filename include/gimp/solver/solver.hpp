// One explicit GIMP run: the scene, the grid, the particles and PETSc's TS, and the time step as
// a short list of named phases (solver/step.cpp):
//
//   migrate -> stencils -> P2G -> [stress, USF] -> forces -> grid update (TSStep) ->
//   [crack contact] -> G2P (+ re-projection, corners) -> work -> [stress, USL/MUSL] -> checks
//   -> report
//
// Nodal momentum is the TS solution (a DMComposite global Vec). TS type euler advances it with
// RHS = kick * mask * (f_int + f_ext - d p) (Eq. 8 and Eq. 16); the forces are computed by the
// forces phase before TSStep, so the RHS callback does no particle work and throws nothing.
// State that one phase hands to a later one is passed as a value (StepClock, StartPower).
#pragma once

#include "gimp/cracks/fields.hpp"
#include "gimp/diagnostics/energies.hpp"
#include "gimp/diagnostics/energy_watch.hpp"
#include "gimp/diagnostics/measures.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/io/output.hpp"
#include "gimp/particles/swarm.hpp"
#include "gimp/physics/boundary.hpp"
#include "gimp/physics/tracking.hpp"
#include "gimp/solver/nodal.hpp"
#include "gimp/solver/rate_classes.hpp"
#include "gimp/solver/scheme.hpp"
#include "gimp/solver/step_common.hpp"
#include "gimp/stability/stability.hpp"

#include <petscts.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace gimp {

/// Power of the external and damping forces at the start of a step, for the step's work.
struct StartPower {
  double external = 0, damping = 0;
};

class Solver {
public:
  explicit Solver(MPI_Comm comm);
  ~Solver();
  Solver(const Solver &) = delete;
  Solver &operator=(const Solver &) = delete;

  /// Read the scene, build grid, particles and TS; validate everything (collective).
  PetscErrorCode setup();
  /// Step until TS's step or time limit, the rest criterion or a failure; final outputs.
  PetscErrorCode run();

  const Scene<2> &scene() const { return sc_; }
  /// True when the run stopped early because it went unstable.
  bool failed() const { return failed_; }
  /// The stop signal (SIGINT or SIGTERM) that ended the run, agreed over the ranks; 0 if none.
  int interrupted() const { return interrupt_; }

private:
  // setup (solver/setup.cpp)
  PetscErrorCode createParticles();
  PetscErrorCode writeGridDump(); // -gimp_grid_dump, collective
  PetscErrorCode createTimeStepper();
  /// -gimp_multirate: a time limit met exactly must fall on a coarse-step end.
  PetscErrorCode checkCoarseTimeLimit();
  static PetscErrorCode rhs(TS ts, PetscReal t, Vec X, Vec F, void *ctx);

  // the step and its phases (solver/step.cpp)
  static PetscErrorCode clockOf(TS ts, const Scene<2> &sc, StepClock &c);
  PetscErrorCode step();
  PetscErrorCode migrate();
  /// Order this rank's particles by level-0 cell, then id (every -gimp_sort_interval steps);
  /// with rate classes `cls` (permuted along) by class first, and without `byCell` by class only.
  PetscErrorCode sortParticles(std::vector<int> *cls = nullptr, bool byCell = true);
  PetscErrorCode buildStencils(const ParticleView<2> &p, const double *centres);
  // the transfers (solver/transfers.cpp)
  /// Where the stencils are centred: tracking::domainCentres, copied when the affine transfer
  /// needs the centres after G2P has moved the particles.
  const double *stencilCentres(const ParticleView<2> &p);
  /// The centres of APIC's moments once the stencils are built: the stencils' centres, or with
  /// cpdi2 the weights' centroid sum_i S_ip x_i (the quadrilateral's, not the material point's).
  const double *affineCentres(const ParticleView<2> &p, const double *centres);
  /// The window coordinates of every slot (D per slot), built once.
  const double *slotCoordinates();
  /// Momentum of the particles' velocities (with APIC their affine fields) into the window
  /// array mom, and the mass into mass when it is not null.
  void projectMomentum(const Stencils<kDim> &st, const ParticleView<2> &p, const double *centres,
                       double *mom, double *mass);
  PetscErrorCode particlesToGrid(const ParticleView<2> &p, const double *centres);
  /// XPIC(m): v* = sum_{k<m} (I - M^-1 S^T M_p S)^k v^n into nodal_.vstarW.
  PetscErrorCode xpicFilter(const ParticleView<2> &p, const StepClock &c);
  /// MUSL's and the corners' re-projection; with `projected` G2P has put the particles' new
  /// momenta on the window already (nodal_.sumW).
  PetscErrorCode reproject(ParticleView<2> &p, const StepClock &c, const double *centres,
                           bool projected);
  PetscErrorCode forces(const ParticleView<2> &p, const StepClock &c, StartPower &power);
  /// TSStep, the nodal velocity and acceleration, the velocity (and acceleration) on the window.
  PetscErrorCode gridUpdate(bool accOnWindow = true);
  /// Each crack field's nodal displacement along the contact normal at the cracked nodes (into
  /// nodal_.faceW), once per step.
  PetscErrorCode crackFaces(const ParticleView<2> &p);
  PetscErrorCode contactOnMomentum(const StepClock &c);
  /// Contact on a grid velocity (window velW, global vel) and, when accW is given, the same
  /// change / dt on the acceleration (window accW, global acc).
  PetscErrorCode crackContact(const StepClock &c, Vec velW, Vec vel, Vec accW, Vec acc);
  PetscErrorCode gridToParticles(ParticleView<2> &p, const StepClock &c, const double *centres);
  /// The step's work: damping, and the external forces unless `external` is false (the
  /// multi-rate step takes each class's external work over its own step).
  PetscErrorCode work(const StepClock &c, const StartPower &power, bool external = true);
  /// The window's forces into nodal_.f and, with `external`, nodal_.fext (all ranks); the start
  /// power.
  PetscErrorCode globalForces(StartPower &power, bool external = true);
  PetscErrorCode stress(const Stencils<kDim> &st, ParticleView<2> &p, Vec velocityWindow,
                        double dt);

  // the multi-rate step (solver/multirate.cpp): R = levels[0].step fine sub-steps, particles in
  // rate classes by the finest level their stencil touches, class c stepping every
  // levels[c].step sub-steps
  PetscErrorCode coarseStep();
  /// Each particle's class, the swarm ordered by class, the slices and the kick weights.
  PetscErrorCode rateClasses(PetscInt step);
  /// Sub-step j: the classes that start (stencils, P2G), the total mass and mask.
  PetscErrorCode startClasses(ParticleView<2> &p, PetscInt j);
  /// The starting classes' forces, each times its step in sub-steps, into nodal_.f.
  PetscErrorCode classForces(const ParticleView<2> &p, const StepClock &c, PetscInt j,
                             StartPower &power);
  /// After the grid update of sub-step j: each class's sums since its start.
  PetscErrorCode accumulate(const StepClock &c, PetscInt j);
  /// What class k's particles take from the nodes at their G2P, into (or added to) out.
  PetscErrorCode takenBy(int k, double flip, double dt, Vec out, bool add);
  /// After the grid update of sub-step j: the ending classes' G2P, stress and momentum removal.
  PetscErrorCode endClasses(ParticleView<2> &p, const StepClock &c, PetscInt j,
                            const StartPower &power);
  /// A multiple of `interval` in [a, b): the reports due within a (coarse) step.
  static bool dueIn(PetscInt a, PetscInt b, PetscInt interval) {
    return interval > 0 && (b - 1) / interval * interval >= a;
  }
  /// Fine steps per step() call: R with -gimp_multirate, else 1.
  PetscInt stride() const { return sc_.multirate ? grid_.levels[0].step : 1; }
  PetscErrorCode checks(const ParticleView<2> &p, PetscInt step, double t);
  PetscErrorCode report(PetscInt step, double t);

  // the critical time step (solver/stability_check.cpp)
  /// Stencils and P2G of the current particles, then the eigenvalues of M^-1 K.
  PetscErrorCode stabilityEstimate(bool springs, bool smallest, stability::Estimate &e);
  /// At setup: dt_critical, the refusals of -ts_dt and -gimp_penalty, the step without -ts_dt.
  PetscErrorCode stabilityAtStart();
  /// Every -gimp_stability_interval steps: the run stops when dt exceeds the new dt_critical.
  PetscErrorCode stabilityRecheck(PetscInt step, double t);

  // the run loop, checks and reports (solver/run.cpp)
  PetscErrorCode historyRow(PetscInt step, double t, HistoryRow &row);
  PetscErrorCode finish(PetscInt steps, double t);
  PetscErrorCode restCriterion(PetscInt step, double t, const Energies &e);
  void energyCheck(PetscInt step, double t, const Energies &e);
  PetscErrorCode monitorLine(PetscInt step, double t);
  PetscErrorCode crackTips(std::vector<cracks::TipMeasure> &tips);

  // checkpoint and restart (solver/checkpoint.cpp)
  PetscErrorCode writeCheckpoint(PetscInt step, double t);
  PetscErrorCode writeCheckpointFile(PetscInt step, double t); // the HDF5 file, unchecked
  PetscErrorCode loadCheckpoint(Output::Resume &resume);
  PetscErrorCode checkCheckpoint(PetscViewer v, const std::vector<double> &scalars);

  stability::SlepcSession slepc_; // first member: finalised after every other one
  MPI_Comm comm_;
  PetscMPIInt rank_ = 0, size_ = 1;
  Scene<2> sc_;
  Scheme scheme_{};
  Grid<2> grid_;
  DM sw_ = nullptr;
  TS ts_ = nullptr;
  Nodal nodal_;
  Stencils<kDim> st_;           // particle -> node weights, rebuilt each step
  std::vector<double> L_;       // velocity gradients of a chunk of particles (stress)
  std::vector<double> centres_; // weight centres with corner tracking (cpdi2 with APIC: centroids)
  std::vector<double> slotX_;   // window coordinates of every slot (affine transfers)
  std::vector<double> xpicVp_;  // XPIC's interpolated field per particle (D each)
  std::vector<double> cpdiCorners_; // the cpdi parallelograms of this step
  RateClasses rate_;                // -gimp_multirate: the classes, their stencils and nodal sums
  physics::Boundary boundary_;      // external forces and penalty conditions
  tracking::CornerMotion corners_;  // corner tracking's motion of the corners
  cracks::Contact contact_;         // contact between the two fields at cracked nodes
  WorkLedger work_;
  RunMeasures measures_;
  std::vector<PetscInt64> probeIds_;
  PetscInt64 nParticles_ = 0;
  double meanParticleMass_ = 0;
  std::unique_ptr<Output> out_;
  StepStages stages_;
  PetscLogDouble wall0_ = 0;
  bool failed_ = false;
  bool lanes_ = false;       // -gimp_lanes on a processor with AVX2 (transfer/lanes2.hpp)
  double dtCritical_ = NAN;  // smallest critical step computed (-gimp_stability_check)
  int interrupt_ = 0;        // SIGINT or SIGTERM received on some rank, agreed by checks()
  std::string localFailure_; // a failure found on this rank inside the step, reported by checks()
  PetscInt64 leaving_ =
      -1;                 // particles outside their rank's cells after the last check (-1: unknown)
  bool atRest_ = false;   // stopped by the rest criterion (-gimp_static_tol)
  int restRows_ = 0;      // consecutive history rows that meet it
  double restStrain_ = 0; // strain energy at the first of them
  EnergyWatch energyWatch_; // the energy balance at the history rows (energyCheck)
};

} // namespace gimp
