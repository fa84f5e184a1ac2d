// Checkpoint and restart (docs/output.md, checkpoint.h5): the whole state a step hands to the
// next, through PETSc's HDF5 viewer. Particles: every field of the swarm's field table, each
// rank's part in its order, and the ranks' local sizes, so that a restart on as many ranks
// continues bit for bit. State: TS's step, time and dt, the work ledger, the run measures, the
// rest criterion's counters, the penalty conditions' largest violations, the frames written and
// history.csv's bytes. The nodal momenta carry nothing across steps (P2G rebuilds them), nor does
// crack contact (its contact set is decided each step).
#pragma once

#include "gimp/io/output.hpp"
#include "gimp/solver/reporter.hpp"
#include "gimp/solver/step.hpp"

#include <functional>
#include <string>
#include <vector>

namespace gimp {

template <int D> class Checkpoint {
public:
  Checkpoint(RunState<D> &s, Step<D> &step, Reporter<D> &reporter)
      : s_(s), step_(step), reporter_(reporter) {}
  /// checkpoint.h5 of the state after `step` (collective; a failure is one line on every rank,
  /// the previous checkpoint kept whole).
  PetscErrorCode write(PetscInt step, double t);
  /// After setup seeded the scene: the checkpoint's particles and state replace the seeded ones;
  /// where the output continues (collective).
  /// With levels that follow a point, `regrid` rebuilds the grid on the checkpoint's level boxes
  /// before its particles are read.
  PetscErrorCode
  load(OutputResume &resume,
       const std::function<PetscErrorCode(const std::vector<LevelBox<D>> &)> &regrid);

private:
  PetscErrorCode writeFile(PetscInt step, double t); // the HDF5 file, unchecked
  /// The checkpoint must come from this scene (destroys v when it throws).
  PetscErrorCode check(PetscViewer v, const std::vector<double> &scalars);
  /// Levels that follow a point: the checkpoint's level boxes (its /state/grid) and split ids
  /// back into the run (collective).
  PetscErrorCode
  loadFollow(PetscViewer v,
             const std::function<PetscErrorCode(const std::vector<LevelBox<D>> &)> &regrid);
  /// The scalars of /state back into the run.
  PetscErrorCode restoreState(const std::vector<double> &s);

  RunState<D> &s_;
  Step<D> &step_;
  Reporter<D> &reporter_;
  std::string record_; // rank 0: the scene's state-defining options (input/scene_record.hpp)
};

} // namespace gimp
