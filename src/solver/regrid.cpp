// Levels that follow a point (-gimp_levelK_follow; docs/method.md, *Levels that follow a point*):
// after a step, each following box whose point (a 2D crack tip, the centre of a 3D crack's front,
// or a probe's particle) came within its margin of a face moves by whole cells of its parent
// (grid/follow.hpp), and the run goes on
// on the rebuilt grid, the particles that a finer box newly holds split to its particle size
// (particles/split.hpp). Nothing nodal carries over a step (P2G rebuilds the momenta), so the
// rebuild is the setup's grid part again: the grid and its window, the nodal Vecs, the node
// constraints, the crack fields and contact directions, TS with its step, time and dt.
#include "gimp/grid/follow.hpp"
#include "gimp/physics/constraints.hpp"
#include "gimp/solver/solver.hpp"

namespace gimp {

namespace {

/// Where the point a level follows is now (every rank alike); `found` false when no particle has
/// the probe's id (the box then stays).
template <int D>
PetscErrorCode followedPoint(const RunState<D> &s, const std::vector<PetscInt64> &probeIds,
                             const LevelFollow &f, double *x, bool &found) {
  found = true;
  if (f.kind == LevelFollow::Kind::CrackTip) {
    if constexpr (D == 2) {
      const Crack &c = s.sc.cracks[static_cast<size_t>(f.index)];
      const std::array<double, 2> &tip = f.end == 0 ? c.points.front() : c.points.back();
      x[0] = tip[0];
      x[1] = tip[1];
    }
    return PETSC_SUCCESS;
  }
  if (f.kind == LevelFollow::Kind::CrackFront) { // the middle of its front points' bounding box
    if constexpr (D == 3) {
      const std::vector<cracks::FrontPoint> pts =
          cracks::frontPoints(s.sc.cracks[static_cast<size_t>(f.index)], frontSpacing(s.sc));
      for (int a = 0; a < 3; ++a) {
        double lo = pts.front().x[a], hi = lo;
        for (const cracks::FrontPoint &q : pts) {
          lo = std::min(lo, q.x[a]);
          hi = std::max(hi, q.x[a]);
        }
        x[a] = 0.5 * (lo + hi);
      }
    }
    return PETSC_SUCCESS;
  }
  // The probe's particle: its owner's position, summed over the ranks (one holds it).
  ParticleView<D> p;
  PetscCall(p.get(s.sw));
  double mine[D + 1] = {};
  const PetscInt64 id = probeIds[static_cast<size_t>(f.index)];
  for (PetscInt k = 0; k < p.n; ++k)
    if (p.id[k] == id) {
      for (int a = 0; a < D; ++a)
        mine[a] = p.x[D * k + a];
      mine[D] = 1;
    }
  PetscCall(p.restore(s.sw));
  double all[D + 1];
  PetscCallMPI(MPI_Allreduce(mine, all, D + 1, MPI_DOUBLE, MPI_SUM, s.comm));
  found = all[D] > 0;
  for (int a = 0; a < D; ++a)
    x[a] = found ? all[a] / all[D] : 0.0;
  return PETSC_SUCCESS;
}

/// The particles' conserved sums (collective).
template <int D> PetscErrorCode conservedOf(const RunState<D> &s, Conserved &c) {
  ParticleView<D> p;
  PetscCall(p.get(s.sw));
  double sums[7] = {}; // mass, momentum (3), angular momentum (3)
  for (PetscInt k = 0; k < p.n; ++k) {
    const double m = p.m[k], *x = p.x + D * k, *v = p.v + D * k;
    sums[0] += m;
    for (int a = 0; a < D; ++a)
      sums[1 + a] += m * v[a];
    double L[3] = {0, 0, x[0] * v[1] - x[1] * v[0]};
    if constexpr (D == 3) {
      L[0] = x[1] * v[2] - x[2] * v[1];
      L[1] = x[2] * v[0] - x[0] * v[2];
    }
    if (p.B) { // ε:Bᵀ: the affine field's spin (row-major B)
      const double *B = p.B + D * D * k;
      if constexpr (D == 3) {
        L[0] += B[7] - B[5];
        L[1] += B[2] - B[6];
        L[2] += B[3] - B[1];
      } else {
        L[2] += B[2] - B[1];
      }
    }
    for (int a = 0; a < 3; ++a)
      sums[4 + a] += m * L[a];
  }
  PetscCall(p.restore(s.sw));
  double all[7];
  PetscCallMPI(MPI_Allreduce(sums, all, 7, MPI_DOUBLE, MPI_SUM, s.comm));
  c.mass = all[0];
  std::copy(all + 1, all + 4, c.momentum);
  std::copy(all + 4, all + 7, c.angular);
  Energies e;
  PetscCall(particleEnergies<D>(s.comm, s.sc, s.sw, s.work, e));
  c.energy = e.kinetic + e.strain;
  return PETSC_SUCCESS;
}

} // namespace

template <int D> PetscErrorCode Solver<D>::followLevels(PetscInt step, double t) {
  RunState<D> &s = s_;
  if (!s.sc.follows() || s.status.failed) return PETSC_SUCCESS;
  const Lattice<D> &g = s.grid;
  const int K = static_cast<int>(g.levels.size());
  std::vector<LatticeBox<D>> boxes(static_cast<size_t>(K));
  for (int k = 0; k < K; ++k)
    boxes[k] = {g.levels[k].lo, g.levels[k].hi};
  std::vector<int> moved;
  for (int k = 1; k < K; ++k) {
    const LevelFollow &f = s.sc.follow[static_cast<size_t>(k)];
    if (f.kind == LevelFollow::Kind::None) continue;
    double x[D];
    bool found = false;
    PetscCall(followedPoint(s, reporter_.probeIds(), f, x, found));
    if (!found) continue;
    for (int a = 0; a < D; ++a) // in lattice units
      x[a] = (x[a] - g.origin[a]) / g.unit;
    const LatticeBox<D> b =
        followBox<D>(boxes[k], boxes[k - 1], g.levels[k - 1].step, x, f.margin / g.unit);
    if (b != boxes[k]) moved.push_back(k);
    boxes[k] = b;
  }
  if (moved.empty()) return PETSC_SUCCESS;
  const std::vector<LevelBox<D>> was = s.sc.levelBoxes();
  std::vector<LevelBox<D>> next = was;
  for (int k = 1; k < K; ++k)
    for (int a = 0; a < D; ++a) {
      next[k].box[a] = g.origin[a] + static_cast<double>(boxes[k].lo[a]) * g.unit;
      next[k].box[D + a] = g.origin[a] + static_cast<double>(boxes[k].hi[a]) * g.unit;
    }
  if (s.splitIds.seeded == 0) s.splitIds.seeded = s.nParticles;
  PetscInt64 added = 0;
  Conserved before, after;
  PetscCall(conservedOf(s, before));
  PetscCall(regrid(next, true, added));
  PetscCall(conservedOf(s, after));
  for (int k : moved) {
    RegridRecord r;
    r.before = before;
    r.after = after;
    r.t = t;
    r.step = step;
    r.level = k;
    std::copy(next[k].box.begin(), next[k].box.end(), r.box.begin());
    std::copy(was[k].box.begin(), was[k].box.end(), r.previous.begin());
    r.added = added;
    s.measures.regrids.push_back(r);
    std::string box;
    for (int d = 0; d < 2 * D; ++d)
      box += (d ? "," : "") + formatNumber(next[k].box[d]);
    PetscCall(PetscInfo(nullptr,
                        "step %" PetscInt_FMT ": level %d moves to %s, %lld particles added\n",
                        step, k, box.c_str(), static_cast<long long>(added)));
  }
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Solver<D>::regrid(const std::vector<LevelBox<D>> &boxes, bool split,
                                 PetscInt64 &added) {
  RunState<D> &s = s_;
  PetscCall(PetscLogStagePush(s.stages.regrid));
  PetscInt step = 0;
  PetscReal t = 0, dt = 0;
  PetscCall(TSGetStepNumber(s.ts, &step));
  PetscCall(TSGetTime(s.ts, &t));
  PetscCall(TSGetTimeStep(s.ts, &dt));
  for (size_t k = 1; k < boxes.size(); ++k)
    s.sc.levels[k].box = boxes[k].box;
  s.st.release();
  PetscCall(TSDestroy(&s.ts));
  s.nodal.destroy();
  s.grid.clear();
  PetscCall(s.grid.create(s.comm, s.sc.h, s.sc.levelBoxes(), s.sc.cracks));
  PetscCall(s.nodal.create(s.grid, s.sc.hasExternalForces(), !s.sc.cracks.empty(),
                           s.sc.transfer == Transfer::Xpic));
  step_.gridChanged();
  setupContact(t);
  PetscCall(physics::nodeConstraints<D>(s.sc, s.grid, s.nodal.bcMask));
  PetscCall(createTimeStepper());
  PetscCall(TSSetStepNumber(s.ts, step));
  PetscCall(TSSetTime(s.ts, t));
  PetscCall(TSSetTimeStep(s.ts, dt));
  added = 0;
  if (split) {
    PetscCall(splitParticles<D>(s.comm, s.sc, s.sw, s.splitIds, added));
    if (s.sc.followMerge) {
      PetscInt64 removed = 0;
      PetscCall(mergeParticles<D>(s.comm, s.sc, s.sw, reporter_.probeIds(), removed));
      added -= removed;
    }
    if (added) {
      const double n = static_cast<double>(s.nParticles);
      s.nParticles += added;
      s.meanParticleMass *= n / static_cast<double>(s.nParticles);
    }
  }
  if (!s.sc.cracks.empty()) { // their radii follow the cells at the tips and fronts
    if constexpr (D == 2)
      updateJDomains(s.sc);
    else
      updateFrontDomains(s.sc);
  }
  s.status.leaving = -1; // the ranks' cells may have moved: the next step migrates
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template PetscErrorCode Solver<2>::followLevels(PetscInt, double);
template PetscErrorCode Solver<3>::followLevels(PetscInt, double);
template PetscErrorCode Solver<2>::regrid(const std::vector<LevelBox<2>> &, bool, PetscInt64 &);
template PetscErrorCode Solver<3>::regrid(const std::vector<LevelBox<3>> &, bool, PetscInt64 &);

} // namespace gimp
