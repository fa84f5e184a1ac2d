// The run loop, the checks after each step and the reports (history, rest criterion, fields,
// monitor lines, summary).
#include "gimp/core/interrupt.hpp"
#include "gimp/core/pair.hpp"
#include "gimp/solver/solver.hpp"
#include "gimp/transfer/lanes2.hpp"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <sys/resource.h>

namespace gimp {

PetscErrorCode Solver::run() {
  if (sc_.help) return PETSC_SUCCESS;
  if (sc_.restart.empty()) { // a restart continues the outputs of its checkpoint
    PetscCall(PetscLogStagePush(stages_.output));
    PetscCall(out_->writeFields(0, 0.0, sw_, nodal_.vel, nodal_.mass));
    HistoryRow row;
    PetscCall(historyRow(0, 0.0, row));
    PetscCall(out_->writeHistory(row));
    energyCheck(0, 0.0, row.energy); // the reference of the energy balance
    PetscCall(PetscLogStagePop());
  }
  PetscInt steps = 0, maxSteps = 0;
  PetscReal t = 0, maxTime = 0;
  PetscCall(TSGetStepNumber(ts_, &steps));
  PetscCall(TSGetTime(ts_, &t));
  PetscCall(TSGetMaxSteps(ts_, &maxSteps));
  PetscCall(TSGetMaxTime(ts_, &maxTime));
  PetscCall(TSMonitor(ts_, steps, t, nodal_.P));
  while (steps < maxSteps && t < maxTime && !failed_ && !atRest_ && !interrupt_) {
    if (sc_.stabilityInterval > 0 && steps > 0 && steps % sc_.stabilityInterval == 0) {
      PetscCall(stabilityRecheck(steps, t));
      if (failed_) break;
    }
    PetscCall(step());
    PetscCall(TSGetStepNumber(ts_, &steps));
    PetscCall(TSGetTime(ts_, &t));
    // The state after the step's report: a restart from it continues with the next step.
    const bool due = dueIn(steps - stride() + 1, steps + 1, sc_.checkpointInterval);
    if (!failed_ && (due || interrupt_)) PetscCall(writeCheckpoint(steps, t));
  }
  // A signal during the last step: the run is complete (its checkpoint stays as written).
  if (steps >= maxSteps || t >= maxTime) interrupt_ = 0;
  if (interrupt_ && !failed_)
    PetscCall(PetscPrintf(comm_,
                          "gimp: interrupted by %s at step %" PetscInt_FMT " t %.9g s: "
                          "checkpoint %s/checkpoint.h5 written\n",
                          interrupt_ == SIGINT ? "SIGINT" : "SIGTERM", steps, t,
                          sc_.outputDir.c_str()));
  PetscCall(TSViewFromOptions(ts_, nullptr, "-ts_view"));
  PetscCall(finish(steps, t));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::checks(const ParticleView<2> &p, PetscInt step, double t) {
  // A particle that is not finite, left the grid, or is inverted or larger than a level-0 cell
  // stops the run on every rank; the first such particle of each rank is named.
  const double *d = sc_.domain.data();
  const double h0 = grid_.h0();
  PetscInt bad = -1;
  // With several ranks, also the particles outside this rank's cells: the next step's migration.
  PetscInt64 leaving = 0;
  double box[4] = {-INFINITY, -INFINITY, INFINITY, INFINITY};
  if (size_ > 1) grid_.ownedBox(rank_, box);
  // Both axes at once.
  using simd::Pair;
  // A body flush with the domain's edge (on a symmetry roller, say) moves its edge particles'
  // domains past it by round-off (1e-18 m): a margin of 1e-8 h0 tells that from leaving.
  const double margin = 1e-8 * h0;
  const Pair lo = {d[0] - margin, d[1] - margin}, hi = {d[2] + margin, d[3] + margin},
             own0 = {box[0], box[1]}, own1 = {box[2], box[3]}, hmax = simd::splat(h0),
             zero = {0, 0};
  PetscInt k0 = 0; // the first particles in lanes of four (the same test)
  if (lanes_) {
    const double lo2[2] = {lo[0], lo[1]}, hi2[2] = {hi[0], hi[1]};
    k0 = transfer::lanes2::checkParticles(p.n, p.x, p.l, p.s, p.V, lo2, hi2, h0, box, box + 2,
                                          size_ > 1, bad, leaving);
  }
  for (PetscInt k = k0; k < p.n; ++k) {
    const Pair X = simd::load(p.x + 2 * k), l = simd::load(p.l + 2 * k);
    if (size_ > 1) leaving += !(simd::bothLe(own0, X) && simd::bothLt(X, own1));
    if (bad >= 0) continue;
    const double s = p.s[4 * k] + p.s[4 * k + 3] + p.s[4 * k + 1];
    // NaN fails every comparison: the test is written so that it lands in the bad branch.
    const bool ok = std::isfinite(X[0] + X[1] + s) && p.V[k] > 0 && simd::bothLe(lo, X - l) &&
                    simd::bothLe(X + l, hi) && simd::bothLt(zero, l) && simd::bothLe(l, hmax);
    if (!ok) bad = k;
  }
  if (bad >= 0) {
    const PetscInt k = bad;
    const double x = p.x[2 * k], y = p.x[2 * k + 1], lx = p.l[2 * k], ly = p.l[2 * k + 1];
    std::string why;
    if (!std::isfinite(x) || !std::isfinite(y) || !tensorAt<2>(p.s, k).allFinite())
      why = "its position or stress is not finite: the run went unstable (reduce -ts_dt)";
    else if (!(p.V[k] > 0))
      why = "its volume " + formatNumber(p.V[k]) +
            " m^2 is not positive: the particle is inverted (det F <= 0): the run went unstable "
            "(reduce -ts_dt)";
    else if (x - lx < d[0] - margin || x + lx > d[2] + margin || y - ly < d[1] - margin ||
             y + ly > d[3] + margin)
      why = "it left the grid domain (enlarge -gimp_domain or -gimp_pad: a body on the domain's "
            "edge deforms past it)";
    else
      why = "its half-size (" + formatNumber(lx) + ", " + formatNumber(ly) +
            ") is not in (0, h0]: the particle is inverted or stretched beyond one level-0 cell";
    failed_ = true;
    // The level whose leaf cell holds the particle (none when it is not finite or outside).
    const bool inside = x >= d[0] && x <= d[2] && y >= d[1] && y <= d[3];
    const std::string level = inside ? std::to_string(grid_.leafLevelAt(x, y)) : "none";
    PetscCall(PetscSynchronizedFPrintf(comm_, PETSC_STDERR,
                                       "gimp: error: step %" PetscInt_FMT
                                       " t %.9g s: particle %" PetscInt64_FMT
                                       " at (%.9g, %.9g) on level %s: %s\n",
                                       step, t, p.id[k], x, y, level.c_str(), why.c_str()));
  }
  if (!localFailure_.empty()) {
    failed_ = true;
    PetscCall(PetscSynchronizedFPrintf(comm_, PETSC_STDERR,
                                       "gimp: error: step %" PetscInt_FMT " t %.9g s: %s\n", step,
                                       t, localFailure_.c_str()));
    localFailure_.clear();
  }
  // One reduction for all: ranks that failed, got SIGINT, got SIGTERM, and the particles that
  // leave their rank (the step's only collective call besides the scatters).
  const int sig = interruptSignal();
  const PetscInt64 mine[4] = {failed_ ? 1 : 0, sig == SIGINT ? 1 : 0, sig == SIGTERM ? 1 : 0,
                              leaving};
  PetscInt64 any[4] = {0, 0, 0, 0};
  PetscCallMPI(MPI_Allreduce(mine, any, 4, MPI_INT64_T, MPI_SUM, comm_));
  failed_ = any[0] > 0;
  interrupt_ = any[2] ? SIGTERM : any[1] ? SIGINT : 0;
  leaving_ = any[3];
  // The failing ranks' lines (collective, so only when some rank failed).
  if (failed_) PetscCall(PetscSynchronizedFlush(comm_, PETSC_STDERR));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::report(PetscInt step, double t) {
  if (failed_) return PETSC_SUCCESS;
  PetscCall(PetscLogStagePush(stages_.output));
  // Due when a multiple of the interval fell within the step (R fine steps with -gimp_multirate).
  const PetscInt from = step - stride() + 1;
  if (dueIn(from, step + 1, sc_.historyInterval)) {
    HistoryRow row;
    PetscCall(historyRow(step, t, row));
    PetscCall(out_->writeHistory(row));
    if (sc_.staticTol > 0 && t >= sc_.staticTime) PetscCall(restCriterion(step, t, row.energy));
    energyCheck(step, t, row.energy);
    if (failed_) { // the row that shows it is written; finish() writes the frame
      PetscCall(PetscLogStagePop());
      return PETSC_SUCCESS;
    }
  }
  if (dueIn(from, step + 1, sc_.outputInterval)) {
    st_.release(); // not needed until the next step: the frame's buffers take its place
    for (Stencils<kDim> &st : rate_.st) // (every class ended with the coarse step)
      st.release();
    PetscCall(out_->writeFields(step, t, sw_, nodal_.vel, nodal_.mass));
  }
  if (dueIn(from, step + 1, sc_.monitorInterval)) PetscCall(monitorLine(step, t));
  PetscCall(TSMonitor(ts_, step, t, nodal_.P));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::historyRow(PetscInt step, double t, HistoryRow &row) {
  row.step = step;
  row.t = t;
  PetscCall(particleEnergies(comm_, sc_, sw_, work_, row.energy));
  PetscCall(probeStates(comm_, sw_, probeIds_, row.probes));
  PetscCall(mmsErrors(comm_, sc_, sw_, t, row.mmsLinf, row.mmsRms));
  measures_.mmsLinf = std::max(measures_.mmsLinf, row.mmsLinf);
  measures_.mmsRms = std::max(measures_.mmsRms, row.mmsRms);
  PetscCall(boundary_.reactions(comm_, row.reactions, row.gaps));
  PetscCall(separation(comm_, grid_, sw_, sc_.cracks, row.separation, row.strainX));
  PetscCall(crackTips(row.tips));
  measures_.maxStrain = std::max(measures_.maxStrain, row.strainX);
  measures_.maxSeparation = std::max(measures_.maxSeparation, row.separation);
  if (row.separation > sc_.separationThreshold && std::isnan(measures_.separationStrain)) {
    measures_.separationStrain = row.strainX;
    PetscCall(PetscPrintf(comm_,
                          "gimp: warning: step %" PetscInt_FMT " t %.6g s: particles separated: "
                          "a gap of %.3g particle sizes between former neighbours (threshold "
                          "%.3g) at engineering strain %.4g\n",
                          step, t, row.separation, sc_.separationThreshold, row.strainX));
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::crackTips(std::vector<cracks::TipMeasure> &tips) {
  tips.clear();
  if (sc_.cracks.empty()) return PETSC_SUCCESS;
  ParticleView<2> p;
  PetscCall(p.get(sw_));
  PetscCall(cracks::measureTips(comm_, sc_, grid_, p, sc_.crackJRadius, tips));
  PetscCall(p.restore(sw_));
  return PETSC_SUCCESS;
}

void Solver::energyCheck(PetscInt step, double t, const Energies &e) {
  // The balance watched for growth (diagnostics/energy_watch.hpp), on sums over all ranks.
  if (!energyWatch_.rose(step, e.kinetic, e.strain, e.externalWork, e.damping,
                         meanParticleMass_ * static_cast<double>(nParticles_), sc_.maxWaveSpeed()))
    return;
  failed_ = true;
  PetscCallVoid(PetscFPrintf(comm_, PETSC_STDERR,
                             "gimp: error: step %" PetscInt_FMT " t %.9g s: %s\n", step, t,
                             energyWatch_.why().c_str()));
}

PetscErrorCode Solver::restCriterion(PetscInt step, double t, const Energies &e) {
  // Energy-based rest criterion for runs damped to a static state, on the history rows'
  // energies. One row is not enough: the kinetic energy of a vibration passes through zero twice
  // a period. The body is at rest when kRestRows consecutive rows have kinetic / strain energy
  // below the tolerance and the strain energy changed by less than 10 tolerance of itself
  // over them (a body creeping to rest with little kinetic energy is not yet there).
  constexpr int kRestRows = 3;
  if (!(e.strain > 0 && e.kinetic < sc_.staticTol * e.strain)) {
    restRows_ = 0;
    return PETSC_SUCCESS;
  }
  if (restRows_++ == 0) restStrain_ = e.strain;
  if (std::fabs(e.strain - restStrain_) >= 10.0 * sc_.staticTol * e.strain) {
    restRows_ = 1; // still creeping: count again from this row
    restStrain_ = e.strain;
  }
  if (restRows_ < kRestRows) return PETSC_SUCCESS;
  atRest_ = true;
  PetscCall(PetscPrintf(comm_,
                        "gimp: at rest at step %" PetscInt_FMT " t %.6g s: kinetic / strain "
                        "energy %.3g < %.3g on %d history rows\n",
                        step, t, e.kinetic / e.strain, sc_.staticTol, kRestRows));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::monitorLine(PetscInt step, double t) {
  Energies e;
  PetscCall(particleEnergies(comm_, sc_, sw_, work_, e));
  PetscCall(PetscPrintf(comm_,
                        "%6" PetscInt_FMT " t %.6e  KE %.6e  SE %.6e  Wext %.6e  Wdamp %.6e  "
                        "E %.6e  p (%.6e, %.6e)\n",
                        step, t, e.kinetic, e.strain, e.externalWork, e.damping, e.total(),
                        e.momentum[0], e.momentum[1]));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::finish(PetscInt steps, double t) {
  // The last frame and history row (if the intervals did not just write them), the particle
  // dump and the summary. An unstable run keeps what it had written and adds the frame of the
  // state it failed in, to look at (report() wrote nothing of that step).
  PetscCall(PetscLogStagePush(stages_.output));
  st_.release(); // the run is over: the frame's buffers take the stencils' place
  for (Stencils<kDim> &st : rate_.st)
    st.release();
  // (A re-check of the critical step stops the run before a step whose frame may be written.)
  const bool written = !out_->frames().empty() && out_->frames().back().step == steps;
  // (what report() wrote after the last step: a multiple of the interval within it)
  const PetscInt from = steps - stride() + 1;
  if ((failed_ && !written) || !dueIn(from, steps + 1, sc_.outputInterval))
    PetscCall(out_->writeFields(steps, t, sw_, nodal_.vel, nodal_.mass));
  if (!failed_) {
    if (!dueIn(from, steps + 1, sc_.historyInterval)) {
      HistoryRow row;
      PetscCall(historyRow(steps, t, row));
      PetscCall(out_->writeHistory(row));
    }
  }
  if (!sc_.particleDump.empty()) PetscCall(writeParticleDump(comm_, sw_, sc_.particleDump));
  SummaryReport r;
  HoleMeasure hole;
  if (sc_.holeMeasure) {
    PetscCall(holeMeasure(comm_, sc_, sw_, hole));
    PetscCall(out_->writeHoop(hole));
    r.hole = &hole;
  }
  r.status = failed_ ? "unstable" : interrupt_ ? "interrupted" : atRest_ ? "at_rest" : "completed";
  r.ranks = size_;
  r.steps = steps;
  r.t = t;
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(ts_, &dt));
  r.dt = dt;
  PetscCall(particleEnergies(comm_, sc_, sw_, work_, r.energy));
  PetscCall(probeStates(comm_, sw_, probeIds_, r.probes));
  PetscInt nloc = 0;
  PetscCall(DMSwarmGetLocalSize(sw_, &nloc));
  PetscInt64 mine = nloc;
  PetscCallMPI(MPI_Allreduce(&mine, &r.particles, 1, MPI_INT64_T, MPI_SUM, comm_));
  PetscCall(boundary_.reactions(comm_, r.reactions, r.gaps));
  r.maxGaps = boundary_.maxGap();
  r.penalty = boundary_.alpha();
  r.dtCritical = dtCritical_;
  r.measures = measures_;
  PetscCall(crackTips(r.tips));
  PetscLogDouble wall1 = 0;
  PetscCall(PetscTime(&wall1));
  r.wallSeconds = wall1 - wall0_;
  // CPU time of the process (all ranks summed): unlike the wall time, it does not grow when
  // other work shares the machine.
  // (PetscGetCPUTime reads a clock that does not count this process's time on every system.)
  rusage use{};
  double mineCpu = 0; // 0 where the system cannot tell
  if (getrusage(RUSAGE_SELF, &use) == 0)
    mineCpu = static_cast<double>(use.ru_utime.tv_sec + use.ru_stime.tv_sec) +
              1e-6 * static_cast<double>(use.ru_utime.tv_usec + use.ru_stime.tv_usec);
  PetscCallMPI(MPI_Allreduce(&mineCpu, &r.cpuSeconds, 1, MPI_DOUBLE, MPI_SUM, comm_));
  PetscCall(out_->writeSummary(r));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

} // namespace gimp
