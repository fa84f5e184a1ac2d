// The multi-rate step of -gimp_multirate (docs/method.md, "Multi-rate time steps per level").
//
// One call advances R = levels[0].step fine steps of dt (one TSStep each, on the same composite
// momentum as the single-rate step). A particle is in class c, the finest level its stencil can
// reach within the coarse step; class c starts at the sub-steps j with j mod m_c = 0 (m_c =
// levels[c].step): its stencils, its P2G onto the nodes, its forces times m_c as one impulse.
// It ends at the sub-steps with (j + 1) mod m_c = 0: G2P from what the nodes did since its start
// (the summed velocity increments, the end velocity, the mean velocity that moves it), its stress
// over m_c dt, and the removal of the momentum its particles took. Between its start and end its
// mass and momentum ride on the nodes with every other class's, so mass and momentum are exact.
#include "gimp/physics/constraints.hpp"
#include "gimp/physics/internal_force.hpp"
#include "gimp/solver/solver.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/transfer.hpp"

#include <algorithm>

namespace gimp {

RateClasses::~RateClasses() {
  for (std::vector<Vec> *vs : {&mass, &mom, &inc, &vsum, &fext})
    for (Vec &v : *vs)
      (void)VecDestroy(&v);
  for (Vec *v : {&taken, &field, &corr, &corrSum, &fieldW, &meanW, &forceW})
    (void)VecDestroy(v);
}

PetscErrorCode RateClasses::create(const Grid &grid, Vec like, bool external) {
  n = static_cast<int>(grid.levels.size());
  every.resize(n);
  for (int c = 0; c < n; ++c)
    every[c] = static_cast<PetscInt>(grid.levels[c].step);
  begin.assign(n + 1, 0);
  size.assign(n, 0);
  switched.assign(n, 0);
  st.resize(n);
  for (std::vector<Vec> *vs : {&mass, &mom, &inc, &vsum}) {
    vs->assign(n, nullptr);
    for (Vec &v : *vs)
      PetscCall(VecDuplicate(like, &v));
  }
  if (external) {
    fext.assign(n, nullptr);
    for (Vec &v : fext)
      PetscCall(VecDuplicate(like, &v));
  }
  startPower.assign(n, 0.0);
  kick.assign(n, 1.0);
  PetscCall(VecDuplicate(like, &taken));
  PetscCall(VecDuplicate(like, &field));
  PetscCall(VecDuplicate(like, &corr));
  PetscCall(VecDuplicate(like, &corrSum));
  for (Vec *v : {&fieldW, &meanW, &forceW})
    PetscCall(grid.createWindowVec(v));
  return PETSC_SUCCESS;
}

namespace {

/// The class of a particle at x with half-sizes l: the finest level c whose box, widened by the
/// reach of its transition nodes (the coarser cell h_{c-1}), the particle's half-size and one
/// finest cell of motion within the coarse step, it overlaps. A particle with a penalty edge is
/// in the finest class: the penalty's stability bound is the finest step's.
int classOf(const Grid &g, const double *x, const double *l, bool penalty) {
  const int top = static_cast<int>(g.levels.size()) - 1;
  if (penalty) return top;
  for (int c = top; c > 0; --c) {
    const Box &b = g.levels[c].box;
    const double wx = l[0] + g.levels[c - 1].h + g.hMin(), wy = l[1] + g.levels[c - 1].h + g.hMin();
    if (x[0] + wx > b[0] && x[0] - wx < b[2] && x[1] + wy > b[1] && x[1] - wy < b[3]) return c;
  }
  return 0;
}

/// The largest window slot particle k's stencil reaches (levels are concatenated in the window,
/// coarse to fine, so this tells the finest level it reaches).
PetscInt maxSlot(const Stencils<kDim> &st, PetscInt k) {
  if (st.isBlock(k)) {
    const Block<kDim> &b = st.block(k);
    return b.base + 2 * b.stride[0] + 2;
  }
  PetscInt s = -1;
  for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e)
    s = std::max(s, st.node[e]);
  return s;
}

/// taken += what the particles of each class in `classes` take from the nodes at their G2P:
/// flip (p_c + m_c inc_c) + (1 - flip) m_c v, with p_c and m_c the class's momentum and mass at
/// its start, inc_c the grid velocity increments since and v the grid velocity now (APIC: flip 0).
PetscErrorCode addTaken(const RateClasses &r, const std::vector<int> &classes, double flip, Vec vel,
                        Vec taken) {
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(taken, &nloc));
  const PetscScalar *v = nullptr;
  PetscScalar *t = nullptr;
  PetscCall(VecGetArrayRead(vel, &v));
  PetscCall(VecGetArray(taken, &t));
  for (int c : classes) {
    const PetscScalar *m = nullptr, *p = nullptr, *d = nullptr;
    PetscCall(VecGetArrayRead(r.mass[c], &m));
    PetscCall(VecGetArrayRead(r.mom[c], &p));
    PetscCall(VecGetArrayRead(r.inc[c], &d));
    for (PetscInt i = 0; i < nloc; i += 2)
      for (int a = 0; a < 2; ++a)
        t[i + a] += flip * (p[i + a] + m[i] * d[i + a]) + (1.0 - flip) * m[i] * v[i + a];
    PetscCall(VecRestoreArrayRead(r.inc[c], &d));
    PetscCall(VecRestoreArrayRead(r.mom[c], &p));
    PetscCall(VecRestoreArrayRead(r.mass[c], &m));
  }
  PetscCall(VecRestoreArray(taken, &t));
  PetscCall(VecRestoreArrayRead(vel, &v));
  return PETSC_SUCCESS;
}

} // namespace

PetscErrorCode Solver::coarseStep() {
  StepClock c0;
  PetscCall(clockOf(ts_, sc_, c0));
  const PetscInt R = stride();
  PetscCall(PetscLogStagePush(stages_.p2g));
  PetscCall(migrate());
  PetscCall(rateClasses(c0.step));
  PetscCall(PetscLogStagePop());
  ParticleView p;
  PetscCall(p.get(sw_));
  PetscCall(VecZeroEntries(nodal_.P)); // every class starts at sub-step 0
  for (PetscInt j = 0; j < R; ++j) {
    StepClock c;
    PetscCall(clockOf(ts_, sc_, c));
    PetscCall(startClasses(p, c, j));
    StartPower power;
    PetscCall(classForces(p, c, j, power));
    PetscCall(gridUpdate());
    for (int k = 0; k < rate_.n; ++k) // each class's sums since its start
      if (rate_.size[k] > 0) {
        PetscCall(VecAXPY(rate_.inc[k], c.dt, nodal_.acc));
        PetscCall(VecAXPY(rate_.vsum[k], 1.0, nodal_.vel));
      }
    PetscCall(endClasses(p, c, j, power));
  }
  StepClock end;
  PetscCall(clockOf(ts_, sc_, end));
  PetscCall(checks(p, end.step, end.t));
  PetscCall(p.restore(sw_));
  PetscCall(report(end.step, end.t));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::rateClasses(PetscInt step) {
  ParticleView p;
  PetscCall(p.get(sw_));
  std::vector<int> cls(p.n);
  for (PetscInt k = 0; k < p.n; ++k) {
    const bool penalty = p.dbc && (p.dbc[2 * k] >= 0 || p.dbc[2 * k + 1] >= 0);
    cls[k] = classOf(grid_, p.x + 2 * k, p.l + 2 * k, penalty);
  }
  PetscCall(p.restore(sw_));
  // Classes contiguous every coarse step; ordered by cell within a class when a sort is due.
  PetscCall(sortParticles(&cls, dueIn(step, step + stride(), sc_.sortInterval)));
  RateClasses &r = rate_;
  PetscCall(p.get(sw_));
  std::vector<PetscInt64> count(r.n, 0);
  for (PetscInt k = 0; k < p.n; ++k)
    ++count[cls[k]];
  for (int c = 0; c < r.n; ++c)
    r.begin[c + 1] = r.begin[c] + static_cast<PetscInt>(count[c]);
  PetscCallMPI(MPI_Allreduce(count.data(), r.size.data(), r.n, MPI_INT64_T, MPI_SUM, comm_));
  // A particle that changes class gets the mean of its old and new steps as its first kick (the
  // variable-step leapfrog): its velocity stands half its old step before and half its new step
  // after the sync point.
  r.kickScale.assign(p.n, 1.0);
  r.switched.assign(r.n, 0);
  for (PetscInt k = 0; k < p.n; ++k) {
    const PetscInt was = p.rate[k], now = cls[k];
    if (was >= 0 && was != now) {
      r.kickScale[k] = 0.5 * static_cast<double>(r.every[was] + r.every[now]) /
                       static_cast<double>(r.every[now]);
      ++r.switched[now];
    }
    p.rate[k] = now;
  }
  PetscCall(p.restore(sw_));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::startClasses(ParticleView &p, const StepClock &c, PetscInt j) {
  PetscCall(PetscLogStagePush(stages_.p2g));
  RateClasses &r = rate_;
  for (int k = 0; k < r.n; ++k) {
    if (r.size[k] == 0 || j % r.every[k] != 0) continue;
    const ParticleView q = p.slice(r.begin[k], r.begin[k + 1]);
    if (!grid_.buildStencils(q.n, q.x, q.l, r.st[k], true))
      localFailure_ = "a particle is larger than a level-0 cell (its half-size exceeds -gimp_h)";
    if (k + 1 < r.n) // the class's margin kept it off the finer levels' nodes
      for (PetscInt i = 0; i < q.n; ++i)
        if (maxSlot(r.st[k], i) >= grid_.levels[k + 1].offset) {
          localFailure_ = "a particle of level " + std::to_string(k) +
                          "'s rate class reached level " + std::to_string(k + 1) +
                          "'s nodes within a coarse step (it moved more than one finest cell; "
                          "reduce -ts_dt)";
          break;
        }
    PetscScalar *mom = nullptr, *mass = nullptr;
    PetscCall(VecZeroEntries(nodal_.sumW));
    PetscCall(VecZeroEntries(nodal_.massW));
    PetscCall(VecGetArray(nodal_.sumW, &mom));
    PetscCall(VecGetArray(nodal_.massW, &mass));
    projectMomentum(r.st[k], q, q.x, mom, mass);
    PetscCall(VecRestoreArray(nodal_.massW, &mass));
    PetscCall(VecRestoreArray(nodal_.sumW, &mom));
    PetscCall(VecZeroEntries(r.mom[k]));
    PetscCall(grid_.addFromWindow(nodal_.sumW, r.mom[k]));
    PetscCall(VecZeroEntries(r.mass[k]));
    PetscCall(grid_.addFromWindow(nodal_.massW, r.mass[k]));
    PetscCall(VecAXPY(nodal_.P, 1.0, r.mom[k]));
    PetscCall(VecZeroEntries(r.inc[k]));
    PetscCall(VecZeroEntries(r.vsum[k]));
  }
  // The mass of every class (each from its last start), the masks and the velocity.
  PetscCall(VecZeroEntries(nodal_.mass));
  for (int k = 0; k < r.n; ++k)
    if (r.size[k] > 0) PetscCall(VecAXPY(nodal_.mass, 1.0, r.mass[k]));
  PetscCall(physics::massMask(nodal_.mass, nodal_.bcMask, sc_.massCutoff * meanParticleMass_,
                              nodal_.mask, nodal_.invMass));
  PetscCall(VecPointwiseMult(nodal_.P, nodal_.P, nodal_.mask));
  PetscCall(VecPointwiseMult(nodal_.vel, nodal_.P, nodal_.invMass));
  PetscCall(PetscLogStagePop());
  if (scheme_.stressBeforeGridUpdate) { // USF: each starting class over its own step
    PetscCall(grid_.toWindow(nodal_.vel, nodal_.velW));
    for (int k = 0; k < r.n; ++k) {
      if (r.size[k] == 0 || j % r.every[k] != 0) continue;
      ParticleView q = p.slice(r.begin[k], r.begin[k + 1]);
      PetscCall(stress(r.st[k], q, nodal_.velW, static_cast<double>(r.every[k]) * c.dt));
    }
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::classForces(const ParticleView &p, const StepClock &c, PetscInt j,
                                   StartPower &power) {
  // Each starting class's forces as one impulse over its step: m_c times its force.
  PetscCall(PetscLogStagePush(stages_.forces));
  RateClasses &r = rate_;
  PetscCall(VecZeroEntries(nodal_.sumW));
  if (boundary_.active()) PetscCall(VecZeroEntries(nodal_.extW));
  std::vector<double> V, m; // the volumes and masses of a class with particles that switched
  for (int k = 0; k < r.n; ++k) {
    if (r.size[k] == 0 || j % r.every[k] != 0) continue;
    ParticleView q = p.slice(r.begin[k], r.begin[k + 1]);
    if (j == 0 && r.switched[k] > 0) { // their first kick: the mean of the old and new steps
      V.assign(q.V, q.V + q.n);
      m.assign(q.m, q.m + q.n);
      for (PetscInt i = 0; i < q.n; ++i) {
        V[i] *= r.kickScale[r.begin[k] + i];
        m[i] *= r.kickScale[r.begin[k] + i];
      }
      q.V = V.data();
      q.m = m.data();
    }
    const double w = static_cast<double>(r.every[k]);
    PetscScalar *f = nullptr;
    PetscCall(VecZeroEntries(r.forceW));
    PetscCall(VecGetArray(r.forceW, &f));
    physics::internalForce<kDim>(r.st[k], q.n, q.V, q.s, f);
    PetscCall(VecRestoreArray(r.forceW, &f));
    PetscCall(VecAXPY(nodal_.sumW, w, r.forceW));
    if (boundary_.active()) {
      PetscCall(VecZeroEntries(r.forceW));
      PetscCall(VecGetArray(r.forceW, &f));
      boundary_.externalForces(sc_, grid_, r.st[k], q, c.t, f);
      PetscCall(VecRestoreArray(r.forceW, &f));
      PetscCall(VecAXPY(nodal_.extW, w, r.forceW));
      PetscCall(VecAXPY(nodal_.sumW, w, r.forceW));
      // Its power at the start, for its work at its end (Solver::endClasses).
      PetscCall(VecZeroEntries(r.fext[k]));
      PetscCall(grid_.addFromWindow(r.forceW, r.fext[k]));
      PetscCall(VecDot(r.fext[k], nodal_.vel, &r.startPower[k]));
      r.kick[k] = c.kick;
    }
  }
  PetscCall(globalForces(power));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::endClasses(ParticleView &p, const StepClock &c, PetscInt j,
                                  const StartPower &power) {
  RateClasses &r = rate_;
  const bool apic = sc_.transfer == Transfer::Apic;
  const double flip = apic ? 0.0 : sc_.flip;
  const bool musl = scheme_.stressFromReprojection;
  std::vector<int> ending, present;
  for (int k = 0; k < r.n; ++k)
    if (r.size[k] > 0) {
      present.push_back(k);
      if ((j + 1) % r.every[k] == 0) ending.push_back(k);
    }
  PetscCall(PetscLogStagePush(stages_.g2p));
  if (ending.size() == present.size() && present.size() > 1 && flip > 0 && flip < 1) {
    // Every class ends: with a FLIP/PIC blend the nodes may keep momentum K that no particle
    // took (the blend's share of the velocity jumps where classes re-entered). It goes to the
    // particles in proportion to their mass, through the FLIP increments: nothing is carried.
    PetscCall(VecZeroEntries(r.taken));
    PetscCall(addTaken(r, ending, flip, nodal_.vel, r.taken));
    PetscCall(VecWAXPY(r.field, -1.0, r.taken, nodal_.P));
    PetscCall(VecPointwiseMult(r.field, r.field, nodal_.invMass));
    for (int k : ending)
      PetscCall(VecAXPY(r.inc[k], 1.0 / flip, r.field));
  }
  PetscCall(VecZeroEntries(r.taken));
  if (musl) PetscCall(VecZeroEntries(r.corrSum));
  for (int k : ending) {
    ParticleView q = p.slice(r.begin[k], r.begin[k + 1]);
    const double every = static_cast<double>(r.every[k]);
    Vec u = nodal_.velW, w = nodal_.velW;
    if (!apic) { // the velocity update field flip inc + (1 - flip) v
      PetscCall(VecCopy(nodal_.vel, r.field));
      PetscCall(VecAXPBY(r.field, flip, 1.0 - flip, r.inc[k]));
      PetscCall(grid_.toWindow(r.field, r.fieldW));
      u = r.fieldW;
    }
    if (r.every[k] > 1) { // the mean grid velocity over the class's step
      PetscCall(VecCopy(r.vsum[k], r.field));
      PetscCall(VecScale(r.field, 1.0 / every));
      PetscCall(grid_.toWindow(r.field, r.meanW));
      w = r.meanW;
    }
    PetscScalar *mom = nullptr;
    if (musl) {
      PetscCall(VecZeroEntries(nodal_.sumW));
      PetscCall(VecGetArray(nodal_.sumW, &mom));
    }
    const PetscScalar *ug = nullptr, *wg = nullptr;
    PetscCall(VecGetArrayRead(u, &ug));
    PetscCall(VecGetArrayRead(w, &wg));
    if (apic)
      transfer::gridToParticlesAffineRated<kDim>(r.st[k], q.n, ug, wg, slotCoordinates(),
                                                 every * c.dt, q.m, q.v, q.B, q.x, mom);
    else
      transfer::gridToParticlesRated<kDim>(r.st[k], q.n, ug, wg, every * c.dt, flip, q.m, q.v, q.x,
                                           mom);
    PetscCall(VecRestoreArrayRead(w, &wg));
    PetscCall(VecRestoreArrayRead(u, &ug));
    // What the class took from the nodes.
    PetscCall(VecZeroEntries(r.field));
    PetscCall(addTaken(r, {k}, flip, nodal_.vel, r.field));
    PetscCall(VecAXPY(r.taken, 1.0, r.field));
    if (scheme_.stressBeforeGridUpdate) continue;
    // The stress from the mean grid velocity over the class's step (what moved it); with MUSL
    // plus the class's own re-projection correction (its new momenta minus what it took, over
    // the nodal mass): with one class MUSL's velocity, with several each class's share of it.
    if (musl) {
      PetscCall(VecRestoreArray(nodal_.sumW, &mom));
      PetscCall(VecZeroEntries(r.corr));
      PetscCall(grid_.addFromWindow(nodal_.sumW, r.corr));
      PetscCall(VecAXPY(r.corr, -1.0, r.field));
      PetscCall(VecPointwiseMult(r.corr, r.corr, nodal_.invMass));
      PetscCall(VecAXPY(r.corrSum, 1.0, r.corr));
    }
    PetscCall(VecCopy(r.vsum[k], r.field));
    if (r.every[k] > 1) PetscCall(VecScale(r.field, 1.0 / every));
    if (musl) PetscCall(VecAXPY(r.field, 1.0, r.corr));
    PetscCall(grid_.toWindow(r.field, r.meanW));
    PetscCall(stress(r.st[k], q, r.meanW, every * c.dt));
  }
  PetscCall(PetscLogStagePop());
  // The work's end velocity: with one rate (R = 1) MUSL's re-projection, as in step(); with
  // several the grid velocity (the classes' stress reads their mean grid velocities).
  if (musl && stride() == 1) PetscCall(VecAXPY(nodal_.vel, 1.0, r.corrSum));
  // Work: damping every sub-step; a class's external impulse m_c dt f_c over its own step, with
  // the velocities at its start and at its end (as the single-rate step does over dt).
  PetscCall(work(c, power, false));
  if (boundary_.active())
    for (int k : ending) {
      PetscScalar fv = 0;
      PetscCall(VecDot(r.fext[k], nodal_.vel, &fv));
      work_.external +=
          0.5 * r.kick[k] * static_cast<double>(r.every[k]) * c.dt * (r.startPower[k] + fv);
    }
  if (musl && stride() > 1) PetscCall(VecAXPY(nodal_.vel, 1.0, r.corrSum)); // as reported
  PetscCall(VecAXPY(nodal_.P, -1.0, r.taken)); // the ending classes leave the nodes
  return PETSC_SUCCESS;
}

} // namespace gimp
