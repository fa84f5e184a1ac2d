// One explicit GIMP run in D = 2 or 3 dimensions (docs/architecture.md, "One solver"): setup
// (scene, grid, particles, nodal vectors, TS, boundary terms, outputs) and the run loop. The
// parts hold what they work on: RunState (what the step sees), Step (the phases), MultiRate (a
// time step per level), Reporter (history, frames, summary), Checkpoint (checkpoint and restart)
// and StabilityCheck (the critical time step). main() runs Solver<2> or Solver<3> by -gimp_dim.
#pragma once

#include "gimp/solver/checkpoint.hpp"
#include "gimp/solver/multirate.hpp"
#include "gimp/solver/reporter.hpp"
#include "gimp/solver/stability_check.hpp"
#include "gimp/solver/step.hpp"

#include <memory>

namespace gimp {

template <int D> class Solver {
public:
  explicit Solver(MPI_Comm comm);
  Solver(const Solver &) = delete;
  Solver &operator=(const Solver &) = delete;

  /// Read the scene, build grid, particles and TS; validate everything (collective).
  PetscErrorCode setup();
  /// Step until TS's step or time limit, the rest criterion, a failure or an interrupt; final
  /// outputs.
  PetscErrorCode run();

  const Scene<D> &scene() const { return s_.sc; }
  /// True when the run stopped early because it went unstable.
  bool failed() const { return s_.status.failed; }
  /// The stop signal (SIGINT or SIGTERM) that ended the run, agreed over the ranks; 0 if none.
  int interrupted() const { return s_.status.interrupt; }

private:
  /// setup's work, in the Setup stage; wall0 its start.
  PetscErrorCode setupInStage(PetscLogDouble wall0);
  PetscErrorCode createGrid();
  PetscErrorCode createParticles();
  /// The manufactured solution's initial state, and the neo-Hookean stress of the seeded F.
  PetscErrorCode initialState(ParticleView<D> &p);
  PetscErrorCode writeGridDump(); // -gimp_grid_dump, collective
  PetscErrorCode createTimeStepper();
  /// -gimp_multirate: the step limit and a time limit met exactly fall on a coarse-step end.
  PetscErrorCode coarseStepLimits();
  /// The output, fresh or continued from a checkpoint.
  PetscErrorCode openOutput();
  /// One (coarse) step and its reports.
  PetscErrorCode advance();
  /// 2D crack growth (-gimp_crack_growth mts): the grid's second fields where the tips may grow
  /// (before the grid is built), and after a restart the things that follow the grown cracks.
  void reserveCrackGrowth();
  PetscErrorCode followCracks(double t);
  /// The contact directions of the cracked nodes, and the increments being released at time t.
  void setupContact(double t);
  /// One growth check after `step` at t, when due: tips measured, grown, and what follows them
  /// updated (collective; every rank decides alike from the reduced measures).
  PetscErrorCode growCracks(PetscInt step, double t);
  /// Levels that follow a point (-gimp_levelK_follow; regrid.cpp): after `step` at t, the boxes
  /// whose point came within their margin move, and the run goes on on the new grid (collective;
  /// every rank decides alike).
  PetscErrorCode followLevels(PetscInt step, double t);
  /// The grid rebuilt from the level boxes `boxes` (the scene's levels take them), with everything
  /// built on it: nodal Vecs, node constraints, crack fields and contact, TS (its step, time and
  /// dt kept); with `split` the particles the finer boxes newly hold are split (splitParticles).
  PetscErrorCode regrid(const std::vector<LevelBox<D>> &boxes, bool split, PetscInt64 &added);

  stability::SlepcSession slepc_; // first member: finalised after every other one
  RunState<D> s_;
  Step<D> step_;
  std::unique_ptr<MultiRate<D>> multirate_; // with -gimp_multirate
  Reporter<D> reporter_;
  StabilityCheck<D> stability_;
  Checkpoint<D> checkpoint_;
};

} // namespace gimp
