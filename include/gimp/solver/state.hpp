// What the parts of a run share (docs/architecture.md, "One solver"): the scene, the grid, the
// particles, the nodal vectors, the stencils, the scheme, the boundary terms, the work done so
// far and how the run stands. The step (Step), the multi-rate step (MultiRate), the reports
// (Reporter), checkpoints (Checkpoint) and the stability check (StabilityCheck) each hold a
// reference to it and keep their own scratch.
#pragma once

#include "gimp/diagnostics/energies.hpp"
#include "gimp/diagnostics/measures.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/particles/split.hpp"
#include "gimp/physics/boundary.hpp"
#include "gimp/solver/clock.hpp"
#include "gimp/solver/nodal.hpp"
#include "gimp/solver/scheme.hpp"

#include <petscts.h>

#include <cstdio>
#include <string>

namespace gimp {

/// How the run stands: a failure, an interrupt, the rest criterion.
struct RunStatus {
  bool failed = false;      // stopped: it went unstable (a particle, the energy balance)
  int interrupt = 0;        // SIGINT or SIGTERM received on some rank, agreed by the checks
  std::string localFailure; // a failure found on this rank inside the step, for the checks
  std::string failure;      // the first failing rank's line (summary.json)
  PetscInt64 leaving = -1;  // particles outside their rank's cells after the last check
  bool atRest = false;      // stopped by the rest criterion (-gimp_static_tol)
  int restRows = 0;         // consecutive history rows that meet it
  double restStrain = 0;    // strain energy at the first of them
};

template <int D> struct RunState {
  RunState() = default;
  RunState(const RunState &) = delete;
  RunState &operator=(const RunState &) = delete;
  ~RunState() {
    if (ts) (void)TSDestroy(&ts);
    if (sw) (void)DMDestroy(&sw);
  }
  /// "dt X s = R h_min / c_p (h_min / c_p = Y s)": the time step against the CFL estimate of
  /// the finest cells, for the line of a run that went unstable.
  std::string stepAgainstCfl() const {
    PetscReal dt = 0;
    if (!ts || TSGetTimeStep(ts, &dt)) return "dt unknown";
    const double cfl = grid.hMin() / sc.maxWaveSpeed();
    char b[160];
    std::snprintf(b, sizeof(b), "dt %.6g s = %.3g h_min / c_p (h_min / c_p = %.6g s)", dt, dt / cfl,
                  cfl);
    return b;
  }
  /// Fine steps per step: R = h_0 / h_min with -gimp_multirate, else 1.
  PetscInt stride() const { return sc.multirate ? grid.levels[0].step : 1; }

  MPI_Comm comm = MPI_COMM_NULL;
  PetscMPIInt rank = 0, size = 1;
  Scene<D> sc;
  Scheme scheme{};
  Grid<D> grid;
  DM sw = nullptr; // the particles (DMSwarm)
  TS ts = nullptr; // explicit Euler on the nodal momentum
  Nodal nodal;
  Stencils<D> st;                // particle -> node weights, rebuilt each step
  physics::Boundary<D> boundary; // external forces and penalty conditions
  bool lanes = false;            // block kernels in AVX2 lanes (2D: four particles; 3D: x, y, z)
  PetscInt64 nParticles = 0;
  double meanParticleMass = 0;
  WorkLedger work;      // work of the external and damping forces
  RunMeasures measures; // what the run keeps of its measures (and dt_critical)
  /// The crack measures of the last history row and its step (-1: none yet): a growth check
  /// after the same step takes them instead of measuring the same particles again.
  struct {
    PetscInt step = -1;
    std::vector<cracks::TipMeasure> tips;
    std::vector<cracks::FrontMeasure> front;
  } lastCrackRow;
  SplitIds splitIds; // the ids particles split by moving level boxes have taken
  RunStatus status;
  StepStages stages;
};

} // namespace gimp
