// One time step as named phases. Each phase is a call into the room of its concept: grid
// (stencils), transfer (P2G, G2P), physics (forces, deformation, tracking), TS (grid update).
// Values one phase hands to a later one are passed explicitly.
#include "gimp/solver/step.hpp"

#include "gimp/physics/deformation.hpp"
#include "gimp/transfer/internal_force.hpp"
#include "gimp/transfer/lane_loops.hpp"
#include "gimp/transfer/lane_loops3.hpp"
#include "gimp/transfer/transfer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace gimp {

template <int D> PetscErrorCode Step<D>::run(StepClock &done) {
  RunState<D> &s = s_;
  StepClock c;
  PetscCall(readStepClock(s.ts, s.sc.halfStepStart, c));
  ParticleView<D> p;
  PetscCall(PetscLogStagePush(s.stages.p2g));
  PetscCall(migrate());
  if (s.sc.sortInterval > 0 && c.step % s.sc.sortInterval == 0) PetscCall(sortParticles());
  PetscCall(p.get(s.sw));
  // Where each particle's weights are centred (the corner box with corner tracking), for the
  // stencils and the crack faces of this step.
  const double *centres = stencilCentres(p);
  PetscCall(buildStencils(p, centres));
  centres = affineCentres(p, centres);
  PetscCall(particlesToGrid(p, centres));
  PetscCall(PetscLogStagePop());
  const bool cracked = !s.sc.cracks.empty();
  if (cracked) {
    PetscCall(crackFaces(p, nullptr));
    PetscCall(contactOnMomentum(c));
  }
  // The strain energy before the update when a report follows (WorkLedger::strainBefore).
  std::vector<double> &before = s.work.strainBefore;
  before.assign(s.work.measureStrain ? 1 : 0, 0.0);
  double *sb = before.empty() ? nullptr : before.data();
  if (s.scheme.stressBeforeGridUpdate) PetscCall(stress(s.st, p, s.nodal.velW, c.dt, sb));
  StartPower power;
  PetscCall(forces(p, c, power));
  PetscCall(gridUpdate());
  if (cracked) PetscCall(crackContact(c, s.nodal.velW, s.nodal.vel, s.nodal.accW, s.nodal.acc));
  PetscCall(gridToParticles(p, c, centres));
  PetscCall(work(c, power));
  // When the stress update is the step's last change to the particles, it tests each chunk of
  // them for checks() as it leaves it (the fields are then in cache).
  CheckTally tally;
  const bool last = !s.scheme.stressBeforeGridUpdate;
  if (last) PetscCall(stress(s.st, p, s.nodal.velW, c.dt, sb, &tally));
  done = c;
  ++done.step;
  done.t = c.t + c.dt;
  PetscCall(checks(p, done.step, done.t, last ? &tally : nullptr));
  PetscCall(p.restore(s.sw));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Step<D>::rhs(TS ts, PetscReal, Vec X, Vec F, void *ctx) {
  // F = kick * mask * (f - d p): the forces of this step (computed by the forces phase), the
  // damping of Eq. 16, no force on constrained or empty nodes.
  const RunState<D> *s = static_cast<const RunState<D> *>(ctx);
  StepClock c;
  PetscCall(readStepClock(ts, s->sc.halfStepStart, c));
  if (s->sc.damping > 0) {
    PetscCall(VecCopy(s->nodal.f, F));
    PetscCall(VecAXPY(F, -s->sc.damping, X));
    PetscCall(VecPointwiseMult(F, F, s->nodal.mask));
  } else {
    PetscCall(VecPointwiseMult(F, s->nodal.f, s->nodal.mask));
  }
  if (c.kick != 1.0) PetscCall(VecScale(F, c.kick));
  PetscCall(VecCopy(F, s->nodal.rhs));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Step<D>::migrate() {
  // Particles go to the rank owning their level-0 cell. The previous step's check counted the
  // particles outside their rank's cells over all ranks (leaving): none, and nothing is done;
  // unknown (-1: the first step, after a restart), and this counts them itself.
  RunState<D> &s = s_;
  if (s.size == 1 || s.status.leaving == 0) return PETSC_SUCCESS;
  ParticleView<D> p;
  PetscCall(p.get(s.sw));
  PetscInt64 moved = 0, any = s.status.leaving;
  double box[2 * D];
  s.grid.ownedBox(s.rank, box);
  for (PetscInt k = 0; k < p.n; ++k) {
    const double *x = p.x + D * k;
    bool stays = true;
    for (int a = 0; a < D; ++a)
      stays = stays && x[a] >= box[a] && x[a] < box[D + a];
    if (stays) continue;
    const PetscMPIInt r = s.grid.ownerOf(x);
    p.rank[k] = r;
    if (r != s.rank) ++moved;
  }
  PetscCall(p.restore(s.sw));
  if (s.status.leaving < 0)
    PetscCallMPI(MPI_Allreduce(&moved, &any, 1, MPI_INT64_T, MPI_SUM, s.comm));
  if (any) PetscCall(DMSwarmMigrate(s.sw, PETSC_TRUE));
  s.measures.migrated += any;
  s.status.leaving = -1;
  return PETSC_SUCCESS;
}

namespace {

/// The index of the level-0 cell that holds x (x fastest): the particles' sort key.
template <int D> PetscInt64 cellIndex(const Level<D> &L, const double *x) {
  PetscInt64 cell = 0;
  for (int a = D - 1; a >= 0; --a)
    cell = cell * static_cast<PetscInt64>(L.n[a]) +
           static_cast<PetscInt64>(std::floor((x[a] - L.box[a]) * L.ih));
  return cell;
}

} // namespace

template <int D> PetscErrorCode Step<D>::sortParticles(std::vector<int> *cls, bool byCell) {
  // Each rank's particles in the order of their level-0 cell (x fastest), by id within a cell:
  // P2G and G2P then walk the nodal arrays in order, and the order depends on neither the
  // seeding nor the migrations. Every -gimp_sort_interval steps; nothing is allocated when the
  // particles are in order already. With rate classes (cls, permuted along) the class comes
  // first; without byCell only the classes are made contiguous (partitionClasses), with it each
  // class's range is then ordered (sortClassRanges).
  RunState<D> &s = s_;
  ParticleView<D> p;
  PetscCall(p.get(s.sw));
  const Level<D> &L = s.grid.levels[0];
  using Key = std::array<PetscInt64, 3>;
  auto keyOf = [&](PetscInt k) {
    const PetscInt64 c = cls ? (*cls)[k] : 0;
    if (!byCell) return Key{c, 0, k};
    return Key{c, cellIndex(L, p.x + D * k), p.id[k]};
  };
  bool sorted = true;
  if (cls && !byCell) // ((c, 0, k) increases exactly where the classes do not fall)
    sorted = std::is_sorted(cls->begin(), cls->end());
  else
    for (PetscInt k = 1; k < p.n && sorted; ++k)
      sorted = keyOf(k - 1) < keyOf(k);
  if (sorted) return p.restore(s.sw);
  if (cls) { // the particles that changed class move, then (byCell) those out of place
    PetscCall(p.restore(s.sw));
    // (without byCell the test above was this one)
    if (!byCell || !std::is_sorted(cls->begin(), cls->end())) PetscCall(partitionClasses(*cls));
    return byCell ? sortClassRanges(*cls) : PETSC_SUCCESS;
  }
  s.st.release(); // the last step's stencils: room for the keys and the permutation buffer
  std::vector<std::pair<Key, PetscInt>> key(static_cast<size_t>(p.n));
  for (PetscInt k = 0; k < p.n; ++k)
    key[k] = {keyOf(k), k};
  PetscCall(p.restore(s.sw));
  std::sort(key.begin(), key.end());
  std::vector<PetscInt> order(static_cast<size_t>(p.n));
  for (size_t k = 0; k < order.size(); ++k)
    order[k] = key[k].second;
  key = {};
  return permuteSwarm<D>(s.sw, order);
}

template <int D> PetscErrorCode Step<D>::sortClassRanges(const std::vector<int> &cls) {
  // The classes are contiguous and in order (cls sorted): each class's range in the order of
  // (cell, id) where it is not in it already. The particles end in the order of the sort by
  // (class, cell, id), the ids being unique, and only those out of place move: the classes that
  // kept their particles keep their order.
  RunState<D> &s = s_;
  ParticleView<D> p;
  PetscCall(p.get(s.sw));
  const Level<D> &L = s.grid.levels[0];
  using Key = std::array<PetscInt64, 2>;
  auto keyOf = [&](PetscInt k) { return Key{cellIndex(L, p.x + D * k), p.id[k]}; };
  std::vector<PetscInt> at, from;
  std::vector<std::pair<Key, PetscInt>> key;
  for (PetscInt b = 0, e = 0; b < p.n; b = e) {
    e = static_cast<PetscInt>(std::upper_bound(cls.begin() + b, cls.end(), cls[b]) - cls.begin());
    bool sorted = true;
    for (PetscInt k = b + 1; k < e && sorted; ++k)
      sorted = keyOf(k - 1) < keyOf(k);
    if (sorted) continue;
    key.resize(static_cast<size_t>(e - b));
    for (PetscInt k = b; k < e; ++k)
      key[k - b] = {keyOf(k), k};
    std::sort(key.begin(), key.end());
    for (PetscInt j = b; j < e; ++j)
      if (key[j - b].second != j) {
        at.push_back(j);
        from.push_back(key[j - b].second);
      }
  }
  PetscCall(p.restore(s.sw));
  return at.empty() ? PETSC_SUCCESS : permuteSwarmAt<D>(s.sw, at, from);
}

template <int D> PetscErrorCode Step<D>::partitionClasses(std::vector<int> &cls) {
  std::vector<PetscInt> at, from;
  classMoves(cls, at, from);
  PetscCall(permuteSwarmAt<D>(s_.sw, at, from));
  std::vector<int> moved(at.size()); // (the movers' classes, read before any is written)
  for (size_t j = 0; j < at.size(); ++j)
    moved[j] = cls[from[j]];
  for (size_t j = 0; j < at.size(); ++j)
    cls[at[j]] = moved[j];
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Step<D>::buildStencils(const ParticleView<D> &p, const double *centres) {
  // The checks after every step keep each particle within one level-0 cell, so this cannot
  // fail; if it does, the failure joins those checks (no extra collective in the step).
  RunState<D> &s = s_;
  if (usesCpdi(s.sc.tracking)) {
    const char *why =
        s.grid.buildCpdiStencils(p.n, tracking::cpdiCorners<D>(s.sc, p, cpdiCorners_), s.st);
    if (why) s.status.localFailure = why;
    cracks::assignFields<D>(s.grid, s.sc.cracks, p.n, centres, s.st);
    return PETSC_SUCCESS;
  }
  // Blocks for every particle that one level's regular nodes alone reach and no cracked node
  // (rows for the others, which assignFields re-addresses). Which cracked nodes a segment can
  // cross depends on the largest half-size: with the weights centred on x over [x - l, x + l]
  // (no corners) the marks follow it; a run with a step per level only widens them (its
  // classes build stencils at other times: MultiRate::startClass).
  if (!s.sc.cracks.empty() && !s.sc.multirate && !tracksCorners(s.sc.tracking) &&
      !usesCpdi(s.sc.tracking)) {
    double lmax = 0;
    for (PetscInt i = 0; i < D * p.n; ++i)
      lmax = std::max(lmax, p.l[i]);
    const double reach = s.grid.liveReachFor(lmax);
    if (reach != s.grid.liveReach()) s.grid.markLiveCracks(s.sc.cracks, reach);
  }
  if (!s.grid.buildStencils(p.n, centres, p.l, s.st, true, s.lanes))
    s.status.localFailure = "a particle is larger than a level-0 cell (its half-size exceeds "
                            "-gimp_h)";
  cracks::assignFields<D>(s.grid, s.sc.cracks, p.n, centres, s.st);
  return PETSC_SUCCESS;
}

template <int D>
void Step<D>::internalForce(const Stencils<D> &st, PetscInt n, const double *V, const double *s,
                            double *f) const {
  if (s_.lanes) return transfer::laneLoops::internalForce(st, n, V, s, f);
  transfer::internalForce<D>(st, n, V, s, f);
}

template <int D>
PetscErrorCode Step<D>::forces(const ParticleView<D> &p, const StepClock &c, StartPower &power) {
  // f = f_int + f_ext (Eq. 8, 9) into nodal.f; the RHS adds damping and masks it.
  RunState<D> &s = s_;
  Nodal &n = s.nodal;
  PetscCall(PetscLogStagePush(s.stages.forces));
  PetscScalar *f = nullptr;
  const bool external = s.boundary.active();
  Vec sum = nullptr, ext = nullptr;
  PetscCall(s.grid.startSum(n.sumW, n.f, &sum));
  PetscCall(VecGetArray(sum, &f));
  internalForce(s.st, p.n, p.V, p.s, f);
  if (external) {
    PetscScalar *fe = nullptr;
    PetscCall(s.grid.startSum(n.extW, n.fext, &ext));
    PetscCall(VecGetArray(ext, &fe));
    s.boundary.externalForces(s.sc, s.grid, s.st, p, c.t, fe);
    for (PetscInt i = 0; i < D * s.grid.nSlots; ++i)
      f[i] += fe[i];
    PetscCall(VecRestoreArray(ext, &fe));
  }
  PetscCall(VecRestoreArray(sum, &f));
  if (external) PetscCall(s.grid.endSum(n.extW, n.fext));
  PetscCall(s.grid.endSum(n.sumW, n.f));
  PetscCall(startPower(power, external));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Step<D>::startPower(StartPower &power, bool external) {
  // The power of the damping and, with `external`, of the external forces at the step's start.
  RunState<D> &s = s_;
  Nodal &n = s.nodal;
  if (s.sc.damping > 0) {
    PetscScalar pv = 0;
    PetscCall(VecDot(n.P, n.vel, &pv));
    power.damping = s.sc.damping * pv;
  }
  if (external) PetscCall(VecDot(n.fext, n.vel, &power.external));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Step<D>::gridUpdate(bool accOnWindow) {
  // TS euler: p <- p + dt * rhs (Step::rhs); then the nodal velocity and, where a transfer
  // reads it (not APIC), the acceleration.
  RunState<D> &s = s_;
  Nodal &n = s.nodal;
  PetscCall(PetscLogStagePush(s.stages.grid));
  PetscCall(TSStep(s.ts));
  const bool acc = s.sc.transfer != Transfer::Apic;
  PetscCall(VecPointwiseMult(n.vel, n.P, n.invMass));
  if (acc) PetscCall(VecPointwiseMult(n.acc, n.rhs, n.invMass));
  PetscCall(s.grid.toWindow(n.vel, n.velW));
  if (acc && accOnWindow) PetscCall(s.grid.toWindow(n.acc, n.accW));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Step<D>::work(const StepClock &c, const StartPower &power, bool external,
                             const std::array<PetscScalar, 2> *dampingDots) {
  // Work of the external and damping forces over the step: force times the mean of the grid
  // velocities at its start and end. With MUSL the end velocity is the re-projection of the
  // particles' velocities, so nodal force residuals that move no particle do no work.
  RunState<D> &s = s_;
  Nodal &n = s.nodal;
  if (s.boundary.active() && external) {
    PetscScalar fv = 0;
    PetscCall(VecDot(n.fext, n.vel, &fv));
    s.work.external += 0.5 * c.kick * c.dt * (power.external + fv);
  }
  if (s.sc.damping > 0) {
    // The damping force is -d p^n, and p^n = p^n+1 - dt F.
    PetscScalar pv = 0, fv = 0;
    if (dampingDots) {
      pv = (*dampingDots)[0];
      fv = (*dampingDots)[1];
    } else {
      PetscCall(VecDot(n.P, n.vel, &pv));
      PetscCall(VecDot(n.rhs, n.vel, &fv));
    }
    s.work.damping += 0.5 * c.kick * c.dt * (power.damping + s.sc.damping * (pv - c.dt * fv));
  }
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Step<D>::stress(const Stencils<D> &st, ParticleView<D> &p, Vec velocityWindow,
                               double dt, double *strainBefore, CheckTally *tally) {
  // Velocity gradient from the scheme's velocity field, then F, volume, stress and domain.
  RunState<D> &s = s_;
  PetscCall(PetscLogStagePush(s.stages.stress));
  if (strainBefore) *strainBefore = strainEnergySum<D>(s.sc, p); // (a report follows the step)
  // In chunks that stay in cache: the gradients of a chunk, then its particles' update.
  constexpr PetscInt kChunk = 256;
  L_.resize(D * D * static_cast<size_t>(kChunk));
  const PetscScalar *vg = nullptr;
  PetscCall(VecGetArrayRead(velocityWindow, &vg));
  for (PetscInt k0 = 0; k0 < p.n; k0 += kChunk) {
    const PetscInt k1 = std::min(p.n, k0 + kChunk);
    if (s.lanes) {
      transfer::laneLoops::velocityGradients(st, k0, k1, vg, L_.data());
      transfer::laneLoops::updateDeformation(s.sc, p, L_.data(), dt, k0, k1);
    } else {
      for (PetscInt k = k0; k < k1; ++k)
        tensorAt<D>(L_.data(), k - k0) = transfer::velocityGradientAt<D>(st, k, vg);
      physics::updateDeformation<D>(s.sc, p, L_.data(), dt, k0, k1);
    }
    if (tally) { // the first failing particle of all the chunks, and every one leaving
      const PetscInt bad = firstBadParticle(p, k0, k1, tally->leaving);
      if (tally->bad < 0) tally->bad = bad;
    }
  }
  // 2D cracks: the displacement that goes with F, integrated from the same velocity field (the
  // crack tips' opening reads it; with MUSL x moves with another one).
  if (p.us)
    for (PetscInt k = 0; k < p.n; ++k) {
      double vp[D];
      transfer::interpolateAt<D>(st, k, vg, vp);
      for (int c = 0; c < D; ++c)
        p.us[D * k + c] += dt * vp[c];
    }
  PetscCall(VecRestoreArrayRead(velocityWindow, &vg));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template PetscErrorCode Step<D>::run(StepClock &);                                               \
  template PetscErrorCode Step<D>::rhs(TS, PetscReal, Vec, Vec, void *);                           \
  template PetscErrorCode Step<D>::migrate();                                                      \
  template PetscErrorCode Step<D>::sortParticles(std::vector<int> *, bool);                        \
  template PetscErrorCode Step<D>::buildStencils(const ParticleView<D> &, const double *);         \
  template void Step<D>::internalForce(const Stencils<D> &, PetscInt, const double *,              \
                                       const double *, double *) const;                            \
  template PetscErrorCode Step<D>::forces(const ParticleView<D> &, const StepClock &,              \
                                          StartPower &);                                           \
  template PetscErrorCode Step<D>::startPower(StartPower &, bool);                                 \
  template PetscErrorCode Step<D>::gridUpdate(bool);                                               \
  template PetscErrorCode Step<D>::work(const StepClock &, const StartPower &, bool,               \
                                        const std::array<PetscScalar, 2> *);                       \
  template PetscErrorCode Step<D>::stress(const Stencils<D> &, ParticleView<D> &, Vec, double,     \
                                          double *, CheckTally *);
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
