// What a run reports (solver/reporter.cpp): history rows with the energy balance watched for
// growth and the rest criterion, field frames, monitor lines, and at the end the last frame, the
// particle dump, the hole measure and summary.json, all through the writers of io/output.hpp.
#pragma once

#include "gimp/diagnostics/energy_watch.hpp"
#include "gimp/io/output.hpp"
#include "gimp/solver/state.hpp"

#include <functional>
#include <memory>
#include <vector>

namespace gimp {

template <int D> class Reporter {
public:
  explicit Reporter(RunState<D> &s) : s_(s) {}
  Reporter(const Reporter &) = delete;
  Reporter &operator=(const Reporter &) = delete;

  /// The probes' particles, and the writers (collective); `release` gives the stencils' memory
  /// back before a frame is written (the next step rebuilds them).
  PetscErrorCode setup(PetscLogDouble wall0, std::function<void()> release);
  /// Prepare the output directory: a fresh run's, or (resume) a restart's.
  PetscErrorCode open(const OutputResume *resume);
  /// A fresh run's first frame and history row, the reference of the energy balance.
  PetscErrorCode start();
  /// Before the (coarse) step from `step`, t: whether a report with energies may follow it (a
  /// history or monitor row, a checkpoint, the run's step or time limit).
  PetscErrorCode energiesDue(PetscInt step, double t, bool &due) const;
  /// After a (coarse) step ending at `step`, t: the reports due within it.
  PetscErrorCode report(PetscInt step, double t);
  /// The last frame and history row (if the intervals did not just write them), the particle
  /// dump, the hole measure and the summary. An unstable run keeps what it had written and adds
  /// the frame of the state it failed in, to look at.
  PetscErrorCode finish(PetscInt steps, double t);
  const Output<D> &output() const { return *out_; }
  /// The setup's end: summary.json's setup_seconds is the wall time from setup's start to here.
  PetscErrorCode markSetupEnd() {
    PetscLogDouble now = 0;
    PetscCall(PetscTime(&now));
    setupSeconds_ = now - wall0_;
    return PETSC_SUCCESS;
  }

  /// The ids of the probes' particles (fixed at setup; a split particle's first part keeps it).
  const std::vector<PetscInt64> &probeIds() const { return probeIds_; }

private:
  PetscErrorCode historyRow(PetscInt step, double t, HistoryRow &row);
  /// The separation measure (2D) into the row and the run's measures.
  PetscErrorCode separationMeasure(PetscInt step, double t, HistoryRow &row);
  PetscErrorCode restCriterion(PetscInt step, double t, const Energies &e);
  void energyCheck(PetscInt step, double t, const Energies &e);
  PetscErrorCode monitorLine(PetscInt step, double t);
  /// The crack measures: every tip's (2D), every front point's (3D). Collective.
  PetscErrorCode crackTips(std::vector<cracks::TipMeasure> &tips,
                           std::vector<cracks::FrontMeasure> &front);
  PetscErrorCode summary(PetscInt steps, double t);

  RunState<D> &s_;
  std::unique_ptr<Output<D>> out_;
  std::vector<PetscInt64> probeIds_;
  EnergyWatch energyWatch_; // the energy balance at the history rows (energyCheck)
  std::function<void()> release_;
  PetscLogDouble wall0_ = 0;
  double setupSeconds_ = 0; // wall time of Solver::setup (markSetupEnd)
};

} // namespace gimp
