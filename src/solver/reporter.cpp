// The reports of a run: history rows (with the energy balance watched for growth and the rest
// criterion), field frames, monitor lines, and the last frame, the dumps and the summary.
#include "gimp/solver/reporter.hpp"

#include "gimp/cracks/tips.hpp"

#include <algorithm>
#include <cmath>
#include <sys/resource.h>

namespace gimp {

template <int D>
PetscErrorCode Reporter<D>::setup(PetscLogDouble wall0, std::function<void()> release) {
  wall0_ = wall0;
  release_ = std::move(release);
  PetscCall(findProbes<D>(s_.comm, s_.sc, s_.sw, probeIds_));
  out_ = std::make_unique<Output<D>>(s_.comm, s_.sc, s_.grid, s_.measures.regrids);
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Reporter<D>::open(const OutputResume *resume) {
  return out_->open(resume);
}

template <int D> PetscErrorCode Reporter<D>::start() {
  PetscCall(PetscLogStagePush(s_.stages.output));
  PetscCall(out_->writeFields(0, 0.0, s_.sw, s_.nodal.vel, s_.nodal.mass));
  HistoryRow row;
  PetscCall(historyRow(0, 0.0, row));
  PetscCall(out_->writeHistory(row));
  energyCheck(0, 0.0, row.energy); // the reference of the energy balance
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Reporter<D>::report(PetscInt step, double t) {
  RunState<D> &s = s_;
  if (s.status.failed) return PETSC_SUCCESS;
  PetscCall(PetscLogStagePush(s.stages.output));
  // Due when a multiple of the interval fell within the step (R fine steps with -gimp_multirate).
  const PetscInt from = step - s.stride() + 1;
  if (dueIn(from, step + 1, s.sc.historyInterval)) {
    HistoryRow row;
    PetscCall(historyRow(step, t, row));
    PetscCall(out_->writeHistory(row));
    if (s.sc.staticTol > 0 && t >= s.sc.staticTime) PetscCall(restCriterion(step, t, row.energy));
    energyCheck(step, t, row.energy);
    if (s.status.failed) { // the row that shows it is written; finish() writes the frame
      PetscCall(PetscLogStagePop());
      return PETSC_SUCCESS;
    }
  }
  if (dueIn(from, step + 1, s.sc.outputInterval)) {
    release_(); // not needed until the next step: the frame's buffers take their place
    PetscCall(out_->writeFields(step, t, s.sw, s.nodal.vel, s.nodal.mass));
  }
  if (dueIn(from, step + 1, s.sc.monitorInterval)) PetscCall(monitorLine(step, t));
  PetscCall(TSMonitor(s.ts, step, t, s.nodal.P));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Reporter<D>::energiesDue(PetscInt step, double t, bool &due) const {
  const RunState<D> &s = s_;
  PetscInt maxSteps = 0;
  PetscReal maxTime = 0, dt = 0;
  PetscCall(TSGetMaxSteps(s.ts, &maxSteps));
  PetscCall(TSGetMaxTime(s.ts, &maxTime));
  PetscCall(TSGetTimeStep(s.ts, &dt));
  const PetscInt R = s.stride(), after = step + R;
  due = after >= maxSteps || t + static_cast<double>(R) * dt * (1 + 1e-9) >= maxTime;
  for (PetscInt interval : {s.sc.historyInterval, s.sc.monitorInterval, s.sc.checkpointInterval})
    due = due || dueIn(step + 1, after + 1, interval);
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Reporter<D>::historyRow(PetscInt step, double t, HistoryRow &row) {
  RunState<D> &s = s_;
  row.step = step;
  row.t = t;
  PetscCall(particleEnergies<D>(s.comm, s.sc, s.sw, s.work, row.energy));
  PetscCall(probeStates<D>(s.comm, s.sw, probeIds_, row.probes));
  PetscCall(mmsErrors<D>(s.comm, s.sc, s.sw, t, row.mmsLinf, row.mmsRms));
  s.measures.mmsLinf = std::max(s.measures.mmsLinf, row.mmsLinf);
  s.measures.mmsRms = std::max(s.measures.mmsRms, row.mmsRms);
  PetscCall(s.boundary.reactions(s.comm, row.reactions, row.gaps));
  PetscCall(separationMeasure(step, t, row));
  PetscCall(crackTips(row.tips, row.front));
  if (s.sc.growth != Growth::None) s.lastCrackRow = {step, row.tips, row.front};
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Reporter<D>::separationMeasure(PetscInt step, double t, HistoryRow &row) {
  RunState<D> &s = s_;
  RunMeasures &m = s.measures;
  PetscCall(separation<D>(s.comm, s.grid, s.sw, s.sc.cracks, row.separation, row.strainX));
  m.maxStrain = std::max(m.maxStrain, row.strainX);
  m.maxSeparation = std::max(m.maxSeparation, row.separation);
  if (row.separation > s.sc.separationThreshold && std::isnan(m.separationStrain)) {
    m.separationStrain = row.strainX;
    PetscCall(PetscPrintf(s.comm,
                          "gimp: warning: step %" PetscInt_FMT " t %.6g s: particles separated: "
                          "a gap of %.3g particle sizes between former neighbours (threshold "
                          "%.3g) at engineering strain %.4g\n",
                          step, t, row.separation, s.sc.separationThreshold, row.strainX));
  }
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Reporter<D>::crackTips(std::vector<cracks::TipMeasure> &tips,
                                      std::vector<cracks::FrontMeasure> &front) {
  tips.clear();
  front.clear();
  if (s_.sc.cracks.empty()) return PETSC_SUCCESS;
  ParticleView<D> p;
  PetscCall(p.get(s_.sw));
  if constexpr (D == 2) {
    PetscCall(cracks::measureTips(s_.comm, s_.sc, s_.grid, p, tips));
  } else {
    const Scene<3> &sc = s_.sc;
    const cracks::FrontDomain dom = cracks::frontDomain(sc);
    PetscCall(cracks::measureFronts(s_.comm, sc.cracks, sc.materialAt(dom.at.data()), p,
                                    dom.spacing, sc.jDomain, dom.R, dom.mirrors, front));
  }
  PetscCall(p.restore(s_.sw));
  return PETSC_SUCCESS;
}

template <int D> void Reporter<D>::energyCheck(PetscInt step, double t, const Energies &e) {
  // The balance watched for growth (diagnostics/energy_watch.hpp), on sums over all ranks.
  RunState<D> &s = s_;
  if (!energyWatch_.rose(step, e.kinetic, e.strain, e.externalWork, e.damping,
                         s.meanParticleMass * static_cast<double>(s.nParticles),
                         s.sc.maxWaveSpeed()))
    return;
  s.status.failed = true;
  char head[96];
  std::snprintf(head, sizeof(head), "step %lld t %.9g s: ", static_cast<long long>(step), t);
  s.status.failure = head + energyWatch_.why() + "; " + s.stepAgainstCfl();
  PetscCallVoid(PetscFPrintf(s.comm, PETSC_STDERR, "gimp: error: %s\n", s.status.failure.c_str()));
}

template <int D>
PetscErrorCode Reporter<D>::restCriterion(PetscInt step, double t, const Energies &e) {
  // Energy-based rest criterion for runs damped to a static state, on the history rows'
  // energies. One row is not enough: the kinetic energy of a vibration passes through zero twice
  // a period. The body is at rest when kRestRows consecutive rows have kinetic / strain energy
  // below the tolerance and the strain energy changed by less than 10 tolerance of itself
  // over them (a body creeping to rest with little kinetic energy is not yet there).
  constexpr int kRestRows = 3;
  RunStatus &st = s_.status;
  const double tol = s_.sc.staticTol;
  if (!(e.strain > 0 && e.kinetic < tol * e.strain)) {
    st.restRows = 0;
    return PETSC_SUCCESS;
  }
  if (st.restRows++ == 0) st.restStrain = e.strain;
  if (std::fabs(e.strain - st.restStrain) >= 10.0 * tol * e.strain) {
    st.restRows = 1; // still creeping: count again from this row
    st.restStrain = e.strain;
  }
  if (st.restRows < kRestRows) return PETSC_SUCCESS;
  st.atRest = true;
  PetscCall(PetscPrintf(s_.comm,
                        "gimp: at rest at step %" PetscInt_FMT " t %.6g s: kinetic / strain "
                        "energy %.3g < %.3g on %d history rows\n",
                        step, t, e.kinetic / e.strain, tol, kRestRows));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Reporter<D>::monitorLine(PetscInt step, double t) {
  Energies e;
  PetscCall(particleEnergies<D>(s_.comm, s_.sc, s_.sw, s_.work, e));
  std::string momentum;
  for (int a = 0; a < D; ++a) {
    char b[40];
    std::snprintf(b, sizeof(b), "%s%.6e", a ? ", " : "", e.momentum[a]);
    momentum += b;
  }
  PetscCall(PetscPrintf(s_.comm,
                        "%6" PetscInt_FMT " t %.6e  KE %.6e  SE %.6e  Wext %.6e  Wdamp %.6e  "
                        "E %.6e  p (%s)\n",
                        step, t, e.kinetic, e.strain, e.externalWork, e.damping, e.total(),
                        momentum.c_str()));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Reporter<D>::finish(PetscInt steps, double t) {
  RunState<D> &s = s_;
  PetscCall(PetscLogStagePush(s.stages.output));
  release_(); // the run is over: the frame's buffers take the stencils' place
  // (A re-check of the critical step stops the run before a step whose frame may be written.)
  const bool written = !out_->frames().empty() && out_->frames().back().step == steps;
  // (what report() wrote after the last step: a multiple of the interval within it)
  const PetscInt from = steps - s.stride() + 1;
  if ((s.status.failed && !written) || !dueIn(from, steps + 1, s.sc.outputInterval))
    PetscCall(out_->writeFields(steps, t, s.sw, s.nodal.vel, s.nodal.mass));
  if (!s.status.failed && !dueIn(from, steps + 1, s.sc.historyInterval)) {
    HistoryRow row;
    PetscCall(historyRow(steps, t, row));
    PetscCall(out_->writeHistory(row));
  }
  if (!s.sc.particleDump.empty()) PetscCall(writeParticleDump<D>(s.comm, s.sw, s.sc.particleDump));
  PetscCall(summary(steps, t));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Reporter<D>::summary(PetscInt steps, double t) {
  RunState<D> &s = s_;
  SummaryReport r;
  HoleMeasure hole;
  if (s.sc.holeMeasure) {
    PetscCall(holeMeasure<D>(s.comm, s.sc, s.sw, hole));
    PetscCall(out_->writeHoop(hole));
    r.hole = &hole;
  }
  const RunStatus &st = s.status;
  r.status = st.failed      ? "unstable"
             : st.interrupt ? "interrupted"
             : st.atRest    ? "at_rest"
                            : "completed";
  r.failure = st.failure;
  r.ranks = s.size;
  r.steps = steps;
  r.t = t;
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(s.ts, &dt));
  r.dt = dt;
  PetscCall(particleEnergies<D>(s.comm, s.sc, s.sw, s.work, r.energy));
  PetscCall(probeStates<D>(s.comm, s.sw, probeIds_, r.probes));
  PetscInt nloc = 0;
  PetscCall(DMSwarmGetLocalSize(s.sw, &nloc));
  PetscInt64 mine = nloc;
  PetscCallMPI(MPI_Allreduce(&mine, &r.particles, 1, MPI_INT64_T, MPI_SUM, s.comm));
  PetscCall(s.boundary.reactions(s.comm, r.reactions, r.gaps));
  r.maxGaps = s.boundary.maxGap();
  r.penalty = s.boundary.alpha();
  r.dtCritical = s.measures.dtCritical;
  r.measures = s.measures;
  PetscCall(crackTips(r.tips, r.front));
  PetscLogDouble wall1 = 0;
  PetscCall(PetscTime(&wall1));
  r.seconds.wall = wall1 - wall0_;
  r.seconds.setup = setupSeconds_;
  // CPU time of the process (all ranks summed): unlike the wall time, it does not grow when
  // other work shares the machine.
  // (PetscGetCPUTime reads a clock that does not count this process's time on every system.)
  rusage use{};
  double mineCpu = 0; // 0 where the system cannot tell
  if (getrusage(RUSAGE_SELF, &use) == 0)
    mineCpu = static_cast<double>(use.ru_utime.tv_sec + use.ru_stime.tv_sec) +
              1e-6 * static_cast<double>(use.ru_utime.tv_usec + use.ru_stime.tv_usec);
  PetscCallMPI(MPI_Allreduce(&mineCpu, &r.seconds.cpu, 1, MPI_DOUBLE, MPI_SUM, s.comm));
  return out_->writeSummary(r);
}

template class Reporter<2>;
template class Reporter<3>;

} // namespace gimp
