// Plain reports that the solver hands to the writers: everything a history row and the summary
// hold, already reduced over ranks. The writers know nothing of the solver.
#pragma once

#include "gimp/cracks/front.hpp"
#include "gimp/cracks/tips.hpp"
#include "gimp/diagnostics/energies.hpp"
#include "gimp/diagnostics/measures.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace gimp {

struct HistoryRow {
  PetscInt step = 0;
  double t = 0;
  Energies energy;
  double separation = 0, strainX = 0; // 2D: the separation measure
  std::vector<ProbeState> probes;
  std::vector<double> reactions, gaps; // per penalty condition: (fx, fy[, fz]) and |u - u_bar|
  double mmsLinf = 0, mmsRms = 0;
  std::vector<cracks::TipMeasure> tips;    // 2D, per crack tip: G and K by VCCT and by J
  std::vector<cracks::FrontMeasure> front; // 3D, per front point: G and K by domain integrals
};

struct SummaryReport {
  std::string status;  // completed, at_rest, interrupted or unstable
  std::string failure; // why an unstable run stopped: the first failing rank's line
  int ranks = 1;
  PetscInt steps = 0;
  double t = 0, dt = 0;
  /// The run's times [s]: wall (setup to the end), the setup's wall time, and the process CPU
  /// time summed over ranks.
  struct Seconds {
    double wall = 0, setup = 0, cpu = 0;
  } seconds;
  double dtCritical = NAN; // smallest critical step computed (-gimp_stability_check), else NaN
  PetscInt64 particles = 0;
  Energies energy;
  std::vector<ProbeState> probes;
  std::vector<double> reactions, gaps, maxGaps;
  double penalty = 0;
  RunMeasures measures;
  const HoleMeasure *hole = nullptr; // with -gimp_hole_measure
  std::vector<cracks::TipMeasure> tips;
  std::vector<cracks::FrontMeasure> front;
};

} // namespace gimp
