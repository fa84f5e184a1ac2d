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
#include "gimp/cracks/fields.hpp"
#include "gimp/physics/constraints.hpp"
#include "gimp/physics/internal_force.hpp"
#include "gimp/solver/solver.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/transfer.hpp"

#include <algorithm>
#include <array>
#include <string>

namespace gimp {

RateClasses::~RateClasses() {
  for (std::vector<Vec> *vs : {&mass, &mom, &inc, &vsum, &force, &base, &fext, &baseExt, &faces})
    for (Vec &v : *vs)
      (void)VecDestroy(&v);
  for (Vec *v : {&nodeRate, &taken, &field, &corr, &corrSum, &fieldW, &meanW, &forceW})
    (void)VecDestroy(v);
}

PetscErrorCode RateClasses::create(const Grid<2> &grid, Vec like, bool external, bool nodeRule) {
  n = static_cast<int>(grid.levels.size());
  every.resize(n);
  for (int c = 0; c < n; ++c)
    every[c] = static_cast<PetscInt>(grid.levels[c].step);
  begin.assign(n + 1, 0);
  size.assign(n, 0);
  switched.assign(n, 0);
  st.resize(n);
  start.assign(n, 0);
  live.assign(n, 0);
  std::vector<std::vector<Vec> *> perClass = {&mass, &mom, &inc, &vsum};
  if (nodeRule) { // the node rule's forces, bases and rates (the impulse rule sums on the window)
    perClass.insert(perClass.end(), {&force, &base});
    if (external) perClass.insert(perClass.end(), {&fext, &baseExt});
    PetscCall(VecDuplicate(like, &nodeRate));
  }
  for (std::vector<Vec> *vs : perClass) {
    vs->assign(n, nullptr);
    for (Vec &v : *vs)
      PetscCall(VecDuplicate(like, &v));
  }
  PetscCall(VecDuplicate(like, &taken));
  PetscCall(VecDuplicate(like, &field));
  PetscCall(VecDuplicate(like, &corr));
  PetscCall(VecDuplicate(like, &corrSum));
  for (Vec *v : {&fieldW, &meanW, &forceW})
    PetscCall(grid.createWindowVec(v));
  return PETSC_SUCCESS;
}

namespace {

/// How far outside each side of level c's box (x0, y0, x1, y1) its nodes reach: the zone of its
/// boundary nodes, the cell of the first coarser level whose box side does not coincide with
/// that side (a box sharing an edge with its parent borders the grandparent's cells there).
std::array<double, 4> outwardZones(const Grid<2> &g, int c) {
  std::array<double, 4> z{};
  for (int side = 0; side < 4; ++side) {
    int q = c - 1;
    while (q > 0 && g.levels[q].box[side] == g.levels[c].box[side])
      --q;
    z[side] = g.levels[q].h;
  }
  return z;
}

/// The class of a particle at x with half-sizes l: the finest level c whose box, widened by the
/// reach of its boundary nodes (zones), the particle's half-size and one finest cell of motion
/// within the coarse step, it overlaps. A particle with a penalty edge is in the finest class:
/// the penalty's stability bound is the finest step's.
int classOf(const Grid<2> &g, const std::vector<std::array<double, 4>> &zones, const double *x,
            const double *l, bool penalty) {
  const int top = static_cast<int>(g.levels.size()) - 1;
  if (penalty) return top;
  const double m = g.hMin();
  for (int c = top; c > 0; --c) {
    const BoxOf<2> &b = g.levels[c].box;
    const std::array<double, 4> &z = zones[c];
    if (x[0] + l[0] + z[0] + m > b[0] && x[0] - l[0] - z[2] - m < b[2] &&
        x[1] + l[1] + z[1] + m > b[1] && x[1] - l[1] - z[3] - m < b[3])
      return c;
  }
  return 0;
}

/// The largest window node particle k's stencil reaches (levels are concatenated in the window,
/// coarse to fine, so this tells the finest level it reaches); a crack's second-field slot counts
/// as its node.
PetscInt maxSlot(const Grid<2> &g, const Stencils<kDim> &st, PetscInt k) {
  if (st.isBlock(k)) {
    const Block<kDim> &b = st.block(k);
    return b.base + 2 * b.stride[0] + 2;
  }
  if (st.isBlock4(k)) {
    const Block<kDim, 4> &b = st.block4(k);
    return b.base + 3 * b.stride[0] + 3;
  }
  PetscInt s = -1;
  for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e)
    s = std::max(s, g.slotNode[st.node[e]]);
  return s;
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
  ParticleView<2> p;
  PetscCall(p.get(sw_));
  PetscCall(VecZeroEntries(nodal_.P)); // every class starts at sub-step 0
  for (PetscInt j = 0; j < R; ++j) {
    StepClock c;
    PetscCall(clockOf(ts_, sc_, c));
    PetscCall(startClasses(p, j));
    if (!sc_.cracks.empty()) { // the classes' crack faces, contact on the momentum
      PetscCall(crackFaces(p));
      PetscCall(contactOnMomentum(c));
    }
    StartPower power;
    PetscCall(classForces(p, c, j, power));
    PetscCall(gridUpdate(!sc_.cracks.empty()));
    if (!sc_.cracks.empty()) { // contact on the new velocities; the momentum follows them
      PetscCall(VecCopy(nodal_.vel, rate_.field));
      PetscCall(crackContact(c, nodal_.velW, nodal_.vel, nodal_.accW, nodal_.acc));
      PetscInt nloc = 0;
      PetscCall(VecGetLocalSize(nodal_.P, &nloc));
      const PetscScalar *m = nullptr, *v = nullptr, *was = nullptr;
      PetscScalar *P = nullptr;
      PetscCall(VecGetArrayRead(nodal_.mass, &m));
      PetscCall(VecGetArrayRead(nodal_.vel, &v));
      PetscCall(VecGetArrayRead(rate_.field, &was));
      PetscCall(VecGetArray(nodal_.P, &P));
      for (PetscInt i = 0; i < nloc; i += kDim)
        for (int d = 0; d < kDim; ++d)
          P[i + d] += m[i] * (v[i + d] - was[i + d]);
      PetscCall(VecRestoreArray(nodal_.P, &P));
      PetscCall(VecRestoreArrayRead(rate_.field, &was));
      PetscCall(VecRestoreArrayRead(nodal_.vel, &v));
      PetscCall(VecRestoreArrayRead(nodal_.mass, &m));
    }
    PetscCall(accumulate(c, j));
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
  ParticleView<2> p;
  PetscCall(p.get(sw_));
  std::vector<int> cls(p.n);
  std::vector<std::array<double, 4>> zones(grid_.levels.size());
  for (size_t c = 1; c < zones.size(); ++c)
    zones[c] = outwardZones(grid_, static_cast<int>(c));
  for (PetscInt k = 0; k < p.n; ++k) {
    const bool penalty = p.dbc && (p.dbc[2 * k] >= 0 || p.dbc[2 * k + 1] >= 0);
    cls[k] = classOf(grid_, zones, p.x + 2 * k, p.l + 2 * k, penalty);
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
  std::string sizes;
  for (int c = 0; c < r.n; ++c)
    sizes += " " + std::to_string(r.size[c]) + " (every " + std::to_string(r.every[c]) + ")";
  PetscCall(PetscInfo(nullptr, "step %" PetscInt_FMT ": particles per rate class:%s\n", step,
                      sizes.c_str()));
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

PetscErrorCode Solver::startClasses(ParticleView<2> &p, PetscInt j) {
  PetscCall(PetscLogStagePush(stages_.p2g));
  RateClasses &r = rate_;
  for (int k = 0; k < r.n; ++k) {
    if (r.size[k] == 0 || j % r.every[k] != 0) continue;
    const ParticleView<2> q = p.slice(r.begin[k], r.begin[k + 1]);
    if (!grid_.buildStencils(q.n, q.x, q.l, r.st[k], sc_.cracks.empty(), lanes_)) {
      // (a particle that went bad inside the coarse step: the check at its end reports it; the
      // class reaches no node until then)
      localFailure_ = "a particle is larger than a level-0 cell (its half-size exceeds -gimp_h)";
      r.st[k].compact = false;
      r.st[k].start.assign(static_cast<size_t>(q.n) + 1, 0);
    }
    cracks::assignFields(grid_, sc_.cracks, q.n, q.x, r.st[k]); // (no-op without cracks)
    if (k + 1 < r.n) // the class's margin kept it off the finer levels' nodes
      for (PetscInt i = 0; i < q.n; ++i)
        if (maxSlot(grid_, r.st[k], i) >= grid_.levels[k + 1].offset) {
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
    if (!sc_.cracks.empty()) { // the class's crack faces, until its end
      if (r.faces.empty()) r.faces.assign(r.n, nullptr);
      if (!r.faces[k]) PetscCall(grid_.createWindowVec(&r.faces[k]));
      PetscScalar *f = nullptr;
      PetscCall(VecGetArray(r.faces[k], &f));
      contact_.faces(grid_, r.st[k], q.n, q.x, q.X0, q.m, f);
      PetscCall(VecRestoreArray(r.faces[k], &f));
    }
    r.start[k] = j;
    r.live[k] = 0;
  }
  bool started = false;
  for (int k = 0; k < r.n; ++k)
    started = started || (r.size[k] > 0 && j % r.every[k] == 0);
  // The mass of every class (each from its last start), the masks and the velocity (unchanged
  // when no class starts: the nodes kept them). With the node rule also each node's rate: the
  // step of the slowest class whose mass is on it now (its anchor; 1 on an empty node). The
  // anchor stays on the node through its own step, so the changes of the faster classes' forces
  // (Solver::classForces) always find mass there.
  if (started) {
    PetscInt nloc = 0;
    PetscCall(VecGetLocalSize(nodal_.mass, &nloc));
    PetscScalar *m = nullptr, *rate = nullptr;
    PetscCall(VecGetArray(nodal_.mass, &m));
    std::fill(m, m + nloc, 0.0);
    if (sc_.multirateNodeRule) {
      PetscCall(VecGetArray(r.nodeRate, &rate));
      std::fill(rate, rate + nloc, 1.0);
    }
    for (int k = 0; k < r.n; ++k) {
      if (r.size[k] == 0) continue;
      const PetscScalar *mk = nullptr;
      PetscCall(VecGetArrayRead(r.mass[k], &mk));
      const double every = static_cast<double>(r.every[k]);
      for (PetscInt i = 0; i < nloc; i += kDim) {
        m[i] += mk[i];
        if (rate && mk[i] > 0)
          for (int d = 0; d < kDim; ++d)
            rate[i + d] = std::max(rate[i + d], every);
      }
      PetscCall(VecRestoreArrayRead(r.mass[k], &mk));
    }
    if (rate) PetscCall(VecRestoreArray(r.nodeRate, &rate));
    PetscCall(VecRestoreArray(nodal_.mass, &m));
  }
  if (started)
    PetscCall(physics::massMask(nodal_.mass, nodal_.bcMask, sc_.massCutoff * meanParticleMass_,
                                nodal_.mask, nodal_.invMass));
  {
    PetscInt nloc = 0;
    PetscCall(VecGetLocalSize(nodal_.P, &nloc));
    PetscScalar *P = nullptr, *v = nullptr;
    const PetscScalar *mk = nullptr, *im = nullptr;
    PetscCall(VecGetArray(nodal_.P, &P));
    PetscCall(VecGetArray(nodal_.vel, &v));
    PetscCall(VecGetArrayRead(nodal_.mask, &mk));
    PetscCall(VecGetArrayRead(nodal_.invMass, &im));
    for (PetscInt i = 0; i < nloc; ++i) {
      P[i] *= mk[i];
      v[i] = P[i] * im[i];
    }
    PetscCall(VecRestoreArrayRead(nodal_.invMass, &im));
    PetscCall(VecRestoreArrayRead(nodal_.mask, &mk));
    PetscCall(VecRestoreArray(nodal_.vel, &v));
    PetscCall(VecRestoreArray(nodal_.P, &P));
  }
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::classForces(const ParticleView<2> &p, const StepClock &c, PetscInt j,
                                   StartPower &power) {
  // Each starting class's force f_c (internal and external), and the sub-step's nodal force
  // from it by the rule of -gimp_multirate_forces (docs/method.md). Impulse: m_c f_c at the
  // class's start. Node: a node of rate m_i (its anchor's step, Solver::startClasses) takes, at the
  // start of each of its own steps, m_i times the force of every class that reaches it; at a later
  // start of a faster class c inside that step, m_c times the change of c's force since. Either way
  // each node gets exactly m_c dt f_c over a class's step; with the node rule, where the classes'
  // forces balance at the start of a node's step, no node moves.
  PetscCall(PetscLogStagePush(stages_.forces));
  RateClasses &r = rate_;
  const bool external = boundary_.active();
  std::vector<double> V; // the volumes of a class with particles that switched class
  // (Boundary keeps the penalty reactions of its last call: the penalty particles are all in the
  // finest class, which comes last here, and it starts at every sub-step.)
  const bool nodeRule = sc_.multirateNodeRule;
  PetscCall(VecZeroEntries(nodal_.f));
  if (external) PetscCall(VecZeroEntries(nodal_.fext));
  if (!nodeRule) PetscCall(VecZeroEntries(nodal_.sumW));
  if (!nodeRule && external) PetscCall(VecZeroEntries(nodal_.extW));
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(nodal_.P, &nloc));
  for (int k = 0; k < r.n; ++k) {
    if (r.size[k] == 0 || j % r.every[k] != 0) continue;
    ParticleView<2> q = p.slice(r.begin[k], r.begin[k + 1]);
    const double *scale = nullptr;
    if (j == 0 && r.switched[k] > 0) { // their first kick: the mean of the old and new steps
      V.assign(q.V, q.V + q.n);
      for (PetscInt i = 0; i < q.n; ++i)
        V[i] *= r.kickScale[r.begin[k] + i];
      q.V = V.data();
      scale = r.kickScale.data() + r.begin[k];
    }
    const double mk = static_cast<double>(r.every[k]);
    PetscScalar *w = nullptr;
    PetscCall(VecZeroEntries(r.forceW));
    PetscCall(VecGetArray(r.forceW, &w));
    physics::internalForce<kDim>(r.st[k], q.n, q.V, q.s, w);
    PetscCall(VecRestoreArray(r.forceW, &w));
    if (!nodeRule) { // the impulse m_c f_c, summed on the window
      PetscCall(VecAXPY(nodal_.sumW, mk, r.forceW));
      if (external) {
        PetscCall(VecZeroEntries(r.forceW));
        PetscCall(VecGetArray(r.forceW, &w));
        boundary_.externalForces(sc_, grid_, r.st[k], q, c.t, w, scale);
        PetscCall(VecRestoreArray(r.forceW, &w));
        PetscCall(VecAXPY(nodal_.sumW, mk, r.forceW));
        PetscCall(VecAXPY(nodal_.extW, mk, r.forceW));
      }
      continue;
    }
    PetscCall(VecZeroEntries(r.force[k]));
    PetscCall(grid_.addFromWindow(r.forceW, r.force[k]));
    if (external) {
      PetscCall(VecZeroEntries(r.forceW));
      PetscCall(VecGetArray(r.forceW, &w));
      boundary_.externalForces(sc_, grid_, r.st[k], q, c.t, w, scale);
      PetscCall(VecRestoreArray(r.forceW, &w));
      PetscCall(VecZeroEntries(r.fext[k]));
      PetscCall(grid_.addFromWindow(r.forceW, r.fext[k]));
      PetscCall(VecAXPY(r.force[k], 1.0, r.fext[k]));
    }
    // The node rule. The forces carry this step's kick weight (the half step that starts a run
    // lasts a whole class step for a slow class); the RHS multiplies by the sub-step's kick, so
    // the sum is divided by it below.
    const double toKick = c.kick;
    const PetscScalar *rate = nullptr;
    PetscScalar *fk = nullptr, *bk = nullptr, *f = nullptr;
    PetscCall(VecGetArrayRead(r.nodeRate, &rate));
    PetscCall(VecGetArray(r.force[k], &fk));
    PetscCall(VecGetArray(r.base[k], &bk));
    PetscCall(VecGetArray(nodal_.f, &f));
    auto deliver = [&](PetscScalar *fc, PetscScalar *bc, PetscScalar *out) {
      for (PetscInt i = 0; i < nloc; ++i) {
        fc[i] *= toKick; // (exact: the kick weight is 1 or 1/2)
        if (j % static_cast<PetscInt>(rate[i]) == 0) {
          out[i] += rate[i] * fc[i];
          bc[i] = fc[i];
        } else {
          out[i] += mk * (fc[i] - bc[i]);
        }
      }
    };
    deliver(fk, bk, f);
    if (external) {
      PetscScalar *ek = nullptr, *be = nullptr, *fe = nullptr;
      PetscCall(VecGetArray(r.fext[k], &ek));
      PetscCall(VecGetArray(r.baseExt[k], &be));
      PetscCall(VecGetArray(nodal_.fext, &fe));
      deliver(ek, be, fe);
      PetscCall(VecRestoreArray(nodal_.fext, &fe));
      PetscCall(VecRestoreArray(r.baseExt[k], &be));
      PetscCall(VecRestoreArray(r.fext[k], &ek));
    }
    PetscCall(VecRestoreArray(nodal_.f, &f));
    PetscCall(VecRestoreArray(r.base[k], &bk));
    PetscCall(VecRestoreArray(r.force[k], &fk));
    PetscCall(VecRestoreArrayRead(r.nodeRate, &rate));
  }
  if (!nodeRule) {
    PetscCall(grid_.addFromWindow(nodal_.sumW, nodal_.f));
    if (external) PetscCall(grid_.addFromWindow(nodal_.extW, nodal_.fext));
  } else if (c.kick != 1.0) { // the RHS applies the sub-step's kick weight again: undo it here
    PetscCall(VecScale(nodal_.f, 1.0 / c.kick));
    if (external) PetscCall(VecScale(nodal_.fext, 1.0 / c.kick));
  }
  // The power of the damping and of the delivered external force at the sub-step's start.
  if (sc_.damping > 0) {
    PetscScalar pv = 0;
    PetscCall(VecDot(nodal_.P, nodal_.vel, &pv));
    power.damping = sc_.damping * pv;
  }
  if (external) PetscCall(VecDot(nodal_.fext, nodal_.vel, &power.external));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::accumulate(const StepClock &c, PetscInt j) {
  // A class that steps over several sub-steps sums the grid velocity increments and the grid
  // velocities since its start; one that steps every sub-step reads them as they are.
  PetscCall(PetscLogStagePush(stages_.grid));
  RateClasses &r = rate_;
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(nodal_.P, &nloc));
  const PetscScalar *a = nullptr, *v = nullptr;
  PetscCall(VecGetArrayRead(nodal_.acc, &a));
  PetscCall(VecGetArrayRead(nodal_.vel, &v));
  // The increments only where a FLIP fraction reads them (not APIC, not PIC).
  const bool increments = sc_.transfer != Transfer::Apic && sc_.flip > 0;
  for (int k = 0; k < r.n; ++k) {
    if (r.size[k] == 0 || r.every[k] == 1) continue;
    PetscScalar *d = nullptr, *w = nullptr;
    PetscCall(VecGetArray(r.vsum[k], &w));
    if (r.start[k] == j)
      std::copy(v, v + nloc, w);
    else
      for (PetscInt i = 0; i < nloc; ++i)
        w[i] += v[i];
    PetscCall(VecRestoreArray(r.vsum[k], &w));
    if (!increments) continue;
    PetscCall(VecGetArray(r.inc[k], &d));
    if (r.start[k] == j)
      for (PetscInt i = 0; i < nloc; ++i)
        d[i] = c.dt * a[i];
    else
      for (PetscInt i = 0; i < nloc; ++i)
        d[i] += c.dt * a[i];
    PetscCall(VecRestoreArray(r.inc[k], &d));
  }
  PetscCall(VecRestoreArrayRead(nodal_.vel, &v));
  PetscCall(VecRestoreArrayRead(nodal_.acc, &a));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::takenBy(int k, double flip, double dt, Vec out, bool add) {
  // What the particles of class k take from the nodes at their G2P: flip (p_k + m_k inc_k) +
  // (1 - flip) m_k v, with p_k and m_k the class's momentum and mass at its start, inc_k the grid
  // velocity increments since (dt a for a class stepping every sub-step, unless materialised)
  // and v the grid velocity now (APIC: flip 0).
  RateClasses &r = rate_;
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(out, &nloc));
  const bool summed = r.every[k] > 1 || r.live[k];
  const PetscScalar *v = nullptr, *m = nullptr, *p = nullptr, *d = nullptr;
  PetscScalar *t = nullptr;
  PetscCall(VecGetArrayRead(nodal_.vel, &v));
  PetscCall(VecGetArrayRead(r.mass[k], &m));
  PetscCall(VecGetArrayRead(r.mom[k], &p));
  PetscCall(VecGetArrayRead(summed ? r.inc[k] : nodal_.acc, &d));
  PetscCall(VecGetArray(out, &t));
  const double ds = summed ? 1.0 : dt;
  for (PetscInt i = 0; i < nloc; i += 2)
    for (int q = 0; q < 2; ++q) {
      // (with flip 0 the increments are not summed: not read)
      const double took =
          flip > 0 ? flip * (p[i + q] + m[i] * ds * d[i + q]) + (1.0 - flip) * m[i] * v[i + q]
                   : m[i] * v[i + q];
      t[i + q] = add ? t[i + q] + took : took;
    }
  PetscCall(VecRestoreArray(out, &t));
  PetscCall(VecRestoreArrayRead(summed ? r.inc[k] : nodal_.acc, &d));
  PetscCall(VecRestoreArrayRead(r.mom[k], &p));
  PetscCall(VecRestoreArrayRead(r.mass[k], &m));
  PetscCall(VecRestoreArrayRead(nodal_.vel, &v));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::endClasses(ParticleView<2> &p, const StepClock &c, PetscInt j,
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
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(nodal_.P, &nloc));
  PetscCall(PetscLogStagePush(stages_.g2p));
  if (ending.size() == present.size() && present.size() > 1 && flip > 0 && flip < 1) {
    // Every class ends: with a FLIP/PIC blend the nodes may keep momentum K that no particle
    // took (the blend's share of the velocity jumps where classes re-entered). It goes to the
    // particles in proportion to their mass, through the FLIP increments: nothing is carried.
    for (int k : ending)
      if (r.every[k] == 1) { // its increments as a vector of their own
        PetscCall(VecAXPBY(r.inc[k], c.dt, 0.0, nodal_.acc));
        r.live[k] = 1;
      }
    for (size_t e = 0; e < ending.size(); ++e)
      PetscCall(takenBy(ending[e], flip, c.dt, r.taken, e > 0));
    PetscCall(VecWAXPY(r.field, -1.0, r.taken, nodal_.P));
    PetscCall(VecPointwiseMult(r.field, r.field, nodal_.invMass));
    for (int k : ending)
      PetscCall(VecAXPY(r.inc[k], 1.0 / flip, r.field));
  }
  for (size_t e = 0; e < ending.size(); ++e) {
    const int k = ending[e];
    ParticleView<2> q = p.slice(r.begin[k], r.begin[k + 1]);
    const double every = static_cast<double>(r.every[k]);
    const bool summed = r.every[k] > 1 || r.live[k];
    // The velocity update field flip inc + (1 - flip) v (APIC: v) and the mean grid velocity
    // over the class's step (a class stepping every sub-step: v), on the window.
    Vec u = nodal_.velW, w = nodal_.velW;
    if (!apic || r.every[k] > 1) {
      const PetscScalar *v = nullptr, *d = nullptr, *vs = nullptr;
      PetscScalar *uf = nullptr, *wf = nullptr;
      PetscCall(VecGetArrayRead(nodal_.vel, &v));
      PetscCall(VecGetArrayRead(summed ? r.inc[k] : nodal_.acc, &d));
      PetscCall(VecGetArrayRead(r.every[k] > 1 ? r.vsum[k] : nodal_.vel, &vs));
      PetscCall(VecGetArray(r.field, &uf));
      PetscCall(VecGetArray(r.corr, &wf)); // (free until the re-projection)
      const double ds = summed ? 1.0 : c.dt;
      for (PetscInt i = 0; i < nloc; ++i) {
        uf[i] = flip > 0 ? flip * ds * d[i] + (1.0 - flip) * v[i] : v[i];
        wf[i] = vs[i] / every;
      }
      PetscCall(VecRestoreArray(r.corr, &wf));
      PetscCall(VecRestoreArray(r.field, &uf));
      PetscCall(VecRestoreArrayRead(r.every[k] > 1 ? r.vsum[k] : nodal_.vel, &vs));
      PetscCall(VecRestoreArrayRead(summed ? r.inc[k] : nodal_.acc, &d));
      PetscCall(VecRestoreArrayRead(nodal_.vel, &v));
      if (!apic) {
        PetscCall(grid_.toWindow(r.field, r.fieldW));
        u = r.fieldW;
      }
      if (r.every[k] > 1) {
        PetscCall(grid_.toWindow(r.corr, r.meanW));
        w = r.meanW;
      }
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
    // What the class took from the nodes (into r.field), summed over the ending classes.
    PetscCall(takenBy(k, flip, c.dt, r.field, false));
    if (e == 0)
      PetscCall(VecCopy(r.field, r.taken));
    else
      PetscCall(VecAXPY(r.taken, 1.0, r.field));
    // The stress from the mean grid velocity over the class's step (what moved it); with MUSL
    // plus the class's own re-projection correction (its new momenta minus what it took, over
    // the nodal mass): with one class MUSL's velocity, with several each class's share of it.
    if (musl) {
      PetscCall(VecRestoreArray(nodal_.sumW, &mom));
      PetscCall(VecZeroEntries(r.corr));
      PetscCall(grid_.addFromWindow(nodal_.sumW, r.corr));
      const PetscScalar *t = nullptr, *im = nullptr, *vs = nullptr;
      PetscScalar *cr = nullptr, *cs = nullptr, *sf = nullptr;
      PetscCall(VecGetArrayRead(r.field, &t));
      PetscCall(VecGetArrayRead(nodal_.invMass, &im));
      PetscCall(VecGetArrayRead(r.every[k] > 1 ? r.vsum[k] : nodal_.vel, &vs));
      PetscCall(VecGetArray(r.corr, &cr));
      PetscCall(VecGetArray(r.corrSum, &cs));
      PetscCall(VecGetArray(nodal_.f, &sf)); // (free after the grid update)
      for (PetscInt i = 0; i < nloc; ++i) {
        cr[i] = (cr[i] - t[i]) * im[i];
        cs[i] = e == 0 ? cr[i] : cs[i] + cr[i];
        sf[i] = vs[i] / every + cr[i];
      }
      PetscCall(VecRestoreArray(nodal_.f, &sf));
      PetscCall(VecRestoreArray(r.corrSum, &cs));
      PetscCall(VecRestoreArray(r.corr, &cr));
      PetscCall(VecRestoreArrayRead(r.every[k] > 1 ? r.vsum[k] : nodal_.vel, &vs));
      PetscCall(VecRestoreArrayRead(nodal_.invMass, &im));
      PetscCall(VecRestoreArrayRead(r.field, &t));
      PetscCall(grid_.toWindow(nodal_.f, r.meanW));
      // The re-projected fields of a cracked node may approach each other again: the same
      // contact as the single-rate step's (Solver::reproject), or the strain would see the faces
      // interpenetrate.
      if (!sc_.cracks.empty()) PetscCall(crackContact(c, r.meanW, nodal_.f, nullptr, nullptr));
      w = r.meanW;
    }
    PetscCall(stress(r.st[k], q, w, every * c.dt));
  }
  PetscCall(PetscLogStagePop());
  // Work of the damping and of the delivered external force every sub-step, with MUSL's
  // velocity at the end (the grid velocity plus the ending classes' corrections), as in step().
  const bool corrected = musl && !ending.empty(); // (USF is refused with -gimp_multirate)
  if (corrected) PetscCall(VecAXPY(nodal_.vel, 1.0, r.corrSum));
  PetscCall(work(c, power));
  // The ending classes leave the nodes; at the coarse end every class does and the next coarse
  // step starts from P = 0, so P keeps the nodal momentum for the monitor and the frames.
  if (!ending.empty() && j + 1 < stride()) PetscCall(VecAXPY(nodal_.P, -1.0, r.taken));
  return PETSC_SUCCESS;
}

} // namespace gimp
