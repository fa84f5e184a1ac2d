// The multi-rate step (solver/multirate.hpp): the starting classes' forces, the sums over a
// class's step, and the ending classes' G2P, stress and removal from the nodes.
#include "gimp/solver/multirate.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/internal_force.hpp"
#include "gimp/transfer/transfer.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace gimp {

namespace {

/// Division by a class's step count, value by value. A power of two (every ratio of 2 or 4)
/// divides exactly as a product by its reciprocal, the same double (x 2^-k is x / 2^k rounded
/// once either way), which does not wait on the divider; any other count divides.
struct DivideBy {
  double inverse;
  bool power2;
  explicit DivideBy(double divisor) : inverse(1.0 / divisor) {
    int e = 0;
    power2 = std::frexp(divisor, &e) == 0.5;
  }
};

} // namespace

template <int D>
PetscErrorCode MultiRate<D>::classForces(const ParticleView<D> &p, const StepClock &c, PetscInt j,
                                         StartPower &power) {
  // Each starting class's force f_c (internal and external), and the sub-step's nodal force
  // from it by the rule of -gimp_multirate_forces (docs/method.md). Impulse: m_c f_c at the
  // class's start. Node: a node of rate m_i (its anchor's step, MultiRate::startNodes) takes, at
  // the start of each of its own steps, m_i times the force of every class that reaches it; at a
  // later start of a faster class c inside that step, m_c times the change of c's force since.
  // Either way each node gets exactly m_c dt f_c over a class's step; with the node rule, where
  // the classes' forces balance at the start of a node's step, no node moves.
  RunState<D> &s = s_;
  RateClasses<D> &r = r_;
  Nodal &n = s.nodal;
  Vec w0 = scratch_.forceW;
  PetscCall(PetscLogStagePush(s.stages.forces));
  const bool external = s.boundary.active(), nodeRule = s.sc.multirateNodeRule;
  std::vector<double> V; // the volumes of a class with particles that switched class
  // (Boundary keeps the penalty reactions of its last call: the penalty particles are all in the
  // finest class, which comes last here, and it starts at every sub-step.)
  // The impulse rule sums on the values the starting classes reach, their external forces too
  // (body forces, tractions and penalties are spread through the class's stencils: on its
  // values); the node rule on every value.
  if (external && !nodeRule && j == 0) PetscCall(loadedClasses(p));
  const bool restricted = !nodeRule;
  int from = r.n - 1;
  for (int k = 0; k < r.n; ++k)
    if (r.size[k] > 0 && j % r.every[k] == 0) from = std::min(from, restricted ? r.from[k] : 0);
  PetscInt nw = 0;
  PetscCall(VecGetLocalSize(w0, &nw));
  // The values the starting classes' forces reach (MultiRate::gridUpdate).
  scratch_.forced.clear();
  for (int k = 0; k < r.n; ++k)
    if (r.size[k] > 0 && j % r.every[k] == 0)
      scratch_.forced =
          unite(scratch_.forced, restricted ? windowValues(k, nw) : Stretches{{0, nw}});
  // The impulse rule sums the classes' impulses into `sum` (Grid::startSum: the window, or
  // nodal.f itself on one rank); nodal.f is zero before the levels from. Where the grid update
  // reads the forced values alone, only they are zeroed, and of them not the first starting
  // class's values: its impulse is written there as 0 + m_c f_c, the sum on zero.
  Vec sum = nullptr;
  if (!nodeRule)
    PetscCall(s.grid.startSum(n.sumW, n.f, &sum, from, sparse_ ? nw : 0));
  else
    PetscCall(VecZeroEntries(n.f));
  int first = -1; // (the first starting class, sparse_: its sum writes)
  for (int k = 0; k < r.n && sparse_ && first < 0; ++k)
    if (r.size[k] > 0 && j % r.every[k] == 0) first = k;
  if (sparse_)
    PetscCall(zeroStretches(n.f, first < 0 ? scratch_.forced
                                           : minus(scratch_.forced, windowValues(first, nw))));
  // w0 takes each class's forces in turn: zero everywhere before (forceClean), and again after
  // each class's use of it.
  if (!scratch_.forceClean) PetscCall(VecZeroEntries(w0));
  scratch_.forceClean = true;
  // (the impulse rule books each class's external work from its own sums: no nodal.fext)
  if (external && nodeRule) PetscCall(VecZeroEntries(n.fext));
  for (int k = 0; k < r.n; ++k) {
    if (r.size[k] == 0 || j % r.every[k] != 0) continue;
    ParticleView<D> q = p.slice(r.begin[k], r.begin[k + 1]);
    const double *scale = nullptr;
    if (j == 0 && r.switched[k] > 0) { // their first kick: the mean of the old and new steps
      V.assign(q.V, q.V + q.n);
      for (PetscInt i = 0; i < q.n; ++i)
        V[i] *= r.kickScale[r.begin[k] + i];
      q.V = V.data();
      scale = r.kickScale.data() + r.begin[k];
    }
    const double mk = static_cast<double>(r.every[k]);
    const Stretches wk = restricted ? windowValues(k, nw) : Stretches{{0, nw}};
    PetscScalar *w = nullptr;
    PetscCall(VecGetArray(w0, &w));
    step_.internalForce(r.st[k], q.n, q.V, q.s, w); // (on wk: the class's values)
    PetscCall(VecRestoreArray(w0, &w));
    // the impulse m_c f_c, summed (m_c a power of 2: exact); w0 zeroed after
    if (!nodeRule) PetscCall(addOnAndZero(sum, mk, w0, wk, k == first));
    if (nodeRule) {
      PetscCall(VecZeroEntries(sums_.force[k]));
      PetscCall(s.grid.addFromWindow(w0, sums_.force[k]));
      PetscCall(zeroStretches(w0, wk));
    }
    if (external && !nodeRule && !r.loaded[k]) { // no external force: its impulse is zero
      if (!r.fextZero[k]) PetscCall(VecZeroEntries(sums_.fext[k]));
      r.fextZero[k] = 1;
      r.extScale[k] = mk * c.kick;
      r.extStart[k] = 0;
    } else if (external) { // (on w0, zero here, and zeroed after)
      PetscCall(VecGetArray(w0, &w));
      s.boundary.externalForces(s.sc, s.grid, r.st[k], q, c.t, w, scale);
      PetscCall(VecRestoreArray(w0, &w));
      if (!nodeRule) PetscCall(VecAXPY(sum, mk, w0));
      r.fextZero[k] = 0;
      PetscCall(VecZeroEntries(sums_.fext[k]));
      PetscCall(s.grid.addFromWindow(w0, sums_.fext[k]));
      PetscCall(VecZeroEntries(w0));
      if (nodeRule) PetscCall(VecAXPY(sums_.force[k], 1.0, sums_.fext[k]));
      // Impulse rule: its work is booked at its class's end (MultiRate::externalWork).
      r.extScale[k] = mk * c.kick;
      if (!nodeRule) PetscCall(VecDot(sums_.fext[k], n.vel, &r.extStart[k]));
    }
    if (nodeRule) PetscCall(deliverNodeRule(k, j, c.kick, external));
  }
  if (!nodeRule) {
    PetscCall(s.grid.endSum(n.sumW, n.f, from));
  } else if (c.kick != 1.0) { // the RHS applies the sub-step's kick weight again: undo it here
    PetscCall(VecScale(n.f, 1.0 / c.kick));
    if (external) PetscCall(VecScale(n.fext, 1.0 / c.kick));
  }
  // The power of the damping and, with the node rule, of the delivered external force at the
  // sub-step's start (the impulse rule books each class's external work itself).
  if (s.sc.damping > 0 && !sparse_) { // (else gridUpdate forms it in its pass)
    PetscScalar pv = 0;
    PetscCall(VecDot(n.P, n.vel, &pv));
    power.damping = s.sc.damping * pv;
  }
  if (external && nodeRule) PetscCall(VecDot(n.fext, n.vel, &power.external));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode MultiRate<D>::loadedClasses(const ParticleView<D> &p) {
  // A class is loaded when the scene has a body force or penalty conditions (the penalty
  // reactions are those of the last class's call: Boundary keeps them) or one of its particles
  // has a traction face; the same on every rank (its work is a collective sum).
  RateClasses<D> &r = r_;
  const Scene<D> &sc = s_.sc;
  bool everywhere = !sc.dbcs.empty() || sc.mms != Mms::None;
  for (int c = 0; c < D; ++c)
    everywhere = everywhere || sc.gravity[c] != 0;
  std::vector<int> mine(static_cast<size_t>(r.n), everywhere ? 1 : 0), all(mine.size());
  for (int k = 0; k < r.n && !everywhere && p.trac; ++k)
    for (PetscInt i = D * r.begin[k]; i < D * r.begin[k + 1] && !mine[k]; ++i)
      mine[k] = p.trac[i] >= 0;
  PetscCallMPI(MPI_Allreduce(mine.data(), all.data(), r.n, MPI_INT, MPI_LOR, s_.comm));
  r.loaded.assign(all.begin(), all.end());
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode MultiRate<D>::deliverNodeRule(int k, PetscInt j, double kick, bool external) {
  // The forces carry this step's kick weight (the half step that starts a run lasts a whole
  // class step for a slow class); the RHS multiplies by the sub-step's kick, so the sum is divided
  // by it in classForces.
  Nodal &n = s_.nodal;
  const double mk = static_cast<double>(r_.every[k]);
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(n.P, &nloc));
  const PetscScalar *rate = nullptr;
  PetscCall(VecGetArrayRead(sums_.nodeRate, &rate));
  auto deliver = [&](Vec fcv, Vec bcv, Vec outv) -> PetscErrorCode {
    PetscScalar *fc = nullptr, *bc = nullptr, *out = nullptr;
    PetscCall(VecGetArray(fcv, &fc));
    PetscCall(VecGetArray(bcv, &bc));
    PetscCall(VecGetArray(outv, &out));
    for (PetscInt i = 0; i < nloc; ++i) {
      fc[i] *= kick; // (exact: the kick weight is 1 or 1/2)
      if (j % static_cast<PetscInt>(rate[i]) == 0) {
        out[i] += rate[i] * fc[i];
        bc[i] = fc[i];
      } else {
        out[i] += mk * (fc[i] - bc[i]);
      }
    }
    PetscCall(VecRestoreArray(outv, &out));
    PetscCall(VecRestoreArray(bcv, &bc));
    PetscCall(VecRestoreArray(fcv, &fc));
    return PETSC_SUCCESS;
  };
  PetscCall(deliver(sums_.force[k], sums_.base[k], n.f));
  if (external) PetscCall(deliver(sums_.fext[k], sums_.baseExt[k], n.fext));
  PetscCall(VecRestoreArrayRead(sums_.nodeRate, &rate));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode MultiRate<D>::accumulate(const StepClock &c, PetscInt j) {
  // A class that steps over several sub-steps sums the grid velocity increments and the grid
  // velocities since its start; one that steps every sub-step reads them as they are.
  RunState<D> &s = s_;
  RateClasses<D> &r = r_;
  PetscCall(PetscLogStagePush(s.stages.grid));
  const PetscScalar *a = nullptr, *v = nullptr;
  PetscCall(VecGetArrayRead(s.nodal.acc, &a));
  PetscCall(VecGetArrayRead(s.nodal.vel, &v));
  // The increments only where a FLIP fraction reads them (not APIC, not PIC).
  const bool increments = s.sc.transfer != Transfer::Apic && s.sc.flip > 0;
  for (int k = 0; k < r.n; ++k) { // (on the values the class reaches: read there alone)
    if (r.size[k] == 0 || r.every[k] == 1) continue;
    PetscScalar *d = nullptr, *w = nullptr;
    PetscCall(VecGetArray(sums_.vsum[k], &w));
    for (const auto &t : r.values[k]) {
      if (r.start[k] == j)
        std::copy(v + t[0], v + t[1], w + t[0]);
      else
        for (PetscInt i = t[0]; i < t[1]; ++i)
          w[i] += v[i];
    }
    PetscCall(VecRestoreArray(sums_.vsum[k], &w));
    if (!increments) continue;
    PetscCall(VecGetArray(sums_.inc[k], &d));
    for (const auto &t : r.values[k]) {
      if (r.start[k] == j)
        for (PetscInt i = t[0]; i < t[1]; ++i)
          d[i] = c.dt * a[i];
      else
        for (PetscInt i = t[0]; i < t[1]; ++i)
          d[i] += c.dt * a[i];
    }
    PetscCall(VecRestoreArray(sums_.inc[k], &d));
  }
  PetscCall(VecRestoreArrayRead(s.nodal.vel, &v));
  PetscCall(VecRestoreArrayRead(s.nodal.acc, &a));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode MultiRate<D>::Taken::get(bool own) {
  PetscCall(VecGetArrayRead(vv, &v));
  if (own) {
    PetscCall(VecGetArray(mv, &mw));
    PetscCall(VecGetArray(pv, &pw));
    m = mw, p = pw;
  } else {
    PetscCall(VecGetArrayRead(mv, &m));
    PetscCall(VecGetArrayRead(pv, &p));
  }
  PetscCall(VecGetArrayRead(dv, &d));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode MultiRate<D>::Taken::restore() {
  PetscCall(VecRestoreArrayRead(dv, &d));
  if (mw) {
    PetscCall(VecRestoreArray(pv, &pw));
    PetscCall(VecRestoreArray(mv, &mw));
    m = p = nullptr;
  } else {
    PetscCall(VecRestoreArrayRead(pv, &p));
    PetscCall(VecRestoreArrayRead(mv, &m));
  }
  PetscCall(VecRestoreArrayRead(vv, &v));
  return PETSC_SUCCESS;
}

template <int D>
typename MultiRate<D>::Taken MultiRate<D>::taken(int k, double flip, double dt) const {
  // p_k and m_k: the class's momentum and mass at its start; inc_k the grid velocity increments
  // since (dt a for a class stepping every sub-step, unless materialised); v the grid velocity
  // now.
  const bool summed = r_.every[k] > 1 || r_.live[k];
  Taken t;
  t.vv = s_.nodal.vel;
  t.mv = sums_.mass[k];
  t.pv = sums_.mom[k];
  t.dv = summed ? sums_.inc[k] : s_.nodal.acc;
  t.flip = flip;
  t.ds = summed ? 1.0 : dt;
  return t;
}

template <int D>
PetscErrorCode MultiRate<D>::takenBy(int k, double flip, double dt, Vec out, bool add, bool zero) {
  // What the particles of class k take from the nodes at their G2P (Taken), on the values the
  // class reaches (out is left as it is elsewhere: the class takes nothing there).
  Taken tk = taken(k, flip, dt);
  PetscScalar *t = nullptr;
  PetscCall(tk.get(zero));
  PetscCall(VecGetArray(out, &t));
  const auto pass = [&](auto flipOn, auto addOn) { // (the branches as constants: one loop)
    for (const auto &st : r_.values[k])
      for (PetscInt i = st[0]; i < st[1]; i += D) {
        for (int q = 0; q < D; ++q) {
          const double took = tk.template at<decltype(flipOn)::value>(i, q);
          t[i + q] = decltype(addOn)::value ? t[i + q] + took : took;
        }
        if (zero) tk.zero(i);
      }
  };
  const std::true_type on;
  const std::false_type off;
  if (tk.flip > 0)
    add ? pass(on, on) : pass(on, off);
  else
    add ? pass(off, on) : pass(off, off);
  PetscCall(VecRestoreArray(out, &t));
  PetscCall(tk.restore());
  if (zero) sums_.clean[k] = 1;
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode MultiRate<D>::endClasses(ParticleView<D> &p, const StepClock &c, PetscInt j,
                                        const StartPower &power,
                                        typename Step<D>::CheckTally *tally) {
  RunState<D> &s = s_;
  RateClasses<D> &r = r_;
  const double flip = s.sc.transfer == Transfer::Apic ? 0.0 : s.sc.flip;
  const bool musl = s.scheme.stressFromReprojection;
  std::vector<int> ending, present;
  for (int k = 0; k < r.n; ++k)
    if (r.size[k] > 0) {
      present.push_back(k);
      if ((j + 1) % r.every[k] == 0) ending.push_back(k);
    }
  PetscCall(PetscLogStagePush(s.stages.g2p));
  if (ending.size() == present.size() && present.size() > 1 && flip > 0 && flip < 1)
    PetscCall(spreadRemainder(ending, c, flip));
  // What the ending classes take and their MUSL corrections: on the values they reach (at), zero
  // elsewhere. The first ending class writes them on its values (endClass), the others add; both
  // are zero outside `dirty` (the passes that read them last zeroed them where they did, but at a
  // coarse step's end), so they are zeroed there alone, but for the first class's values.
  Stretches at;
  for (int k : ending)
    at = unite(at, r.values[k]);
  const Stretches zero =
      minus(scratch_.dirty, ending.empty() ? Stretches{} : r.values[ending.front()]);
  PetscCall(zeroStretches(scratch_.taken, zero));
  if (musl) PetscCall(zeroStretches(scratch_.corrSum, zero));
  scratch_.dirty = at;
  // One ending class (no cracks: their contact follows the correction): its correction moves
  // the grid velocity itself where nothing reads it before the end (no external force: its work
  // reads the velocity before the correction and corrSum), and takes its momentum from P where
  // P is not kept (not the coarse step's end) and not read (no damping). The same sums: vel + 1.0
  // c is vel + c, P + (-1.0) t is P - t.
  const bool alone = musl && ending.size() == 1 && s.sc.cracks.empty();
  scratch_.velInCorrection = alone && !s.boundary.active();
  scratch_.momentumInCorrection = alone && j + 1 < s.stride() && !(s.sc.damping > 0);
  for (size_t e = 0; e < ending.size(); ++e)
    PetscCall(endClass(p, c, ending[e], e, flip, tally));
  const bool velDone = scratch_.velInCorrection, momentumDone = scratch_.momentumInCorrection;
  scratch_.velInCorrection = scratch_.momentumInCorrection = false;
  PetscCall(PetscLogStagePop());
  // The work of the external impulses (classForces): a class's impulse m_c dt f_c times the mean
  // of the grid velocity before and after it (its start sub-step), the latter with the MUSL
  // correction its class's end brings (the corrections of the classes ending there); with one
  // class the single-rate ledger.
  // The node rule (USL only) delivers the forces at other sub-steps: their work per sub-step.
  const bool nodeRule = s.sc.multirateNodeRule;
  if (s.boundary.active() && !nodeRule) PetscCall(externalWork(c, j, ending));
  // Damping per sub-step, with MUSL's velocity at the end (the grid velocity plus the ending
  // classes' corrections), as in the single-rate step.
  const bool corrected = musl && !ending.empty(); // (USF is refused with -gimp_multirate)
  if (corrected && !velDone) PetscCall(addOnAndZero(s.nodal.vel, 1.0, scratch_.corrSum, at));
  if (sparse_ && s.sc.damping > 0) { // (the sums on the values the damping moved: gridUpdate's,
    // or with the correction on the velocity, formed again)
    if (corrected)
      PetscCall(dotsOn(s.nodal.P, s.nodal.rhs, s.nodal.vel, scratch_.massive,
                       scratch_.dampingDots.data()));
    PetscCall(step_.work(c, power, nodeRule, &scratch_.dampingDots));
  } else {
    PetscCall(step_.work(c, power, nodeRule));
  }
  // The ending classes leave the nodes; at the coarse end every class does and the next coarse
  // step starts from P = 0, so P keeps the nodal momentum for the monitor and the frames.
  // (after momentumDone taken keeps what it held on the class's values, which stay dirty)
  if (!ending.empty() && j + 1 < s.stride() && !momentumDone) {
    PetscCall(addOnAndZero(s.nodal.P, -1.0, scratch_.taken, at));
    scratch_.dirty.clear(); // (corrSum too: zeroed above with the correction)
  }
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode MultiRate<D>::externalWork(const StepClock &c, PetscInt j,
                                          const std::vector<int> &ending) {
  RateClasses<D> &r = r_;
  const bool musl = s_.scheme.stressFromReprojection;
  for (int k = 0; k < r.n; ++k) // the classes that started at this sub-step: after the impulse
    if (r.size[k] > 0 && r.start[k] == j && !r.fextZero[k]) {
      PetscScalar fv = 0;
      PetscCall(VecDot(sums_.fext[k], s_.nodal.vel, &fv));
      r.extStart[k] += fv;
    }
  for (int k : ending) {
    PetscScalar fc = 0;
    if (musl && !r.fextZero[k]) PetscCall(VecDot(sums_.fext[k], scratch_.corrSum, &fc));
    s_.work.external += 0.5 * c.dt * r.extScale[k] * (r.extStart[k] + fc);
  }
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode MultiRate<D>::spreadRemainder(const std::vector<int> &ending, const StepClock &c,
                                             double flip) {
  // Every class ends: with a FLIP/PIC blend the nodes may keep momentum K that no particle
  // took (the blend's share of the velocity jumps where classes re-entered). It goes to the
  // particles in proportion to their mass, through the FLIP increments: nothing is carried.
  Nodal &n = s_.nodal;
  for (int k : ending)
    if (r_.every[k] == 1) { // its increments as a vector of their own
      PetscCall(VecAXPBY(sums_.inc[k], c.dt, 0.0, n.acc));
      r_.live[k] = 1;
    }
  PetscCall(VecZeroEntries(scratch_.taken));
  for (int k : ending) {
    PetscCall(takenBy(k, flip, c.dt, scratch_.taken, true));
    scratch_.dirty = unite(scratch_.dirty, r_.values[k]);
  }
  PetscCall(VecWAXPY(scratch_.field, -1.0, scratch_.taken, n.P));
  PetscCall(VecPointwiseMult(scratch_.field, scratch_.field, n.invMass));
  for (int k : ending)
    PetscCall(VecAXPY(sums_.inc[k], 1.0 / flip, scratch_.field));
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode MultiRate<D>::endClass(ParticleView<D> &p, const StepClock &c, int k, size_t e,
                                      double flip, typename Step<D>::CheckTally *tally) {
  RunState<D> &s = s_;
  RateClasses<D> &r = r_;
  RateScratch &w0 = scratch_;
  Nodal &n = s.nodal;
  const bool apic = s.sc.transfer == Transfer::Apic, musl = s.scheme.stressFromReprojection;
  ParticleView<D> q = p.slice(r.begin[k], r.begin[k + 1]);
  const double every = static_cast<double>(r.every[k]);
  const bool summed = r.every[k] > 1 || r.live[k];
  // The velocity update field flip inc + (1 - flip) v (APIC: v) and the mean grid velocity over
  // the class's step (a class stepping every sub-step: v), on the window: formed on this rank's
  // global values and moved there, or formed there where the window is the global array.
  Vec u = n.velW, w = n.velW;
  const int from = r.from[k];
  const Stretches &at = r.values[k];
  const bool direct = s.grid.windowIsLocal();
  if (!apic || r.every[k] > 1) {
    Vec dv = summed ? sums_.inc[k] : n.acc, vs = r.every[k] > 1 ? sums_.vsum[k] : n.vel;
    const PetscScalar *v = nullptr, *d = nullptr, *vsum = nullptr;
    PetscScalar *uf = nullptr, *wf = nullptr;
    PetscCall(VecGetArrayRead(n.vel, &v));
    PetscCall(VecGetArrayRead(dv, &d));
    PetscCall(VecGetArrayRead(vs, &vsum));
    // (corr is free until the MUSL momenta)
    Vec uv = direct ? w0.fieldW : w0.field, wv = direct ? w0.meanW : w0.corr;
    PetscCall(VecGetArray(uv, &uf));
    PetscCall(VecGetArray(wv, &wf));
    const double ds = summed ? 1.0 : c.dt;
    const DivideBy by(every);
    for (const auto &t : at) {
      if (!apic) // (APIC moves with the grid velocity: no update field)
        for (PetscInt i = t[0]; i < t[1]; ++i)
          uf[i] = flip > 0 ? flip * ds * d[i] + (1.0 - flip) * v[i] : v[i];
      if (r.every[k] > 1) {
        if (by.power2)
          for (PetscInt i = t[0]; i < t[1]; ++i)
            wf[i] = vsum[i] * by.inverse;
        else
          for (PetscInt i = t[0]; i < t[1]; ++i)
            wf[i] = vsum[i] / every;
      }
    }
    PetscCall(VecRestoreArray(wv, &wf));
    PetscCall(VecRestoreArray(uv, &uf));
    PetscCall(VecRestoreArrayRead(vs, &vsum));
    PetscCall(VecRestoreArrayRead(dv, &d));
    PetscCall(VecRestoreArrayRead(n.vel, &v));
    if (!apic) {
      if (!direct) PetscCall(s.grid.toWindow(w0.field, w0.fieldW, from));
      u = w0.fieldW;
    }
    if (r.every[k] > 1) {
      if (!direct) PetscCall(s.grid.toWindow(w0.corr, w0.meanW, from));
      w = w0.meanW;
    }
  }
  // MUSL: the class's new momenta, summed into w0.corr (Grid::startSum; its mean velocity is on
  // meanW now) for its correction.
  PetscScalar *mom = nullptr;
  Vec sum = nullptr;
  if (musl) { // (corr zero everywhere where the correction zeroed it after use: corrClean)
    PetscInt nloc = 0;
    PetscCall(VecGetLocalSize(n.P, &nloc));
    if (!direct) // (it held the mean velocity)
      PetscCall(zeroStretches(w0.corr, at));
    else if (!w0.corrClean)
      PetscCall(VecZeroEntries(w0.corr));
    w0.corrClean = direct;
    PetscCall(s.grid.startSum(n.sumW, w0.corr, &sum, from, nloc));
    PetscCall(VecGetArray(sum, &mom));
  }
  const PetscScalar *ug = nullptr, *wg = nullptr;
  PetscCall(VecGetArrayRead(u, &ug));
  PetscCall(VecGetArrayRead(w, &wg));
  step_.gridToParticlesRated(r.st[k], q, ug, wg, every * c.dt, flip, mom);
  PetscCall(VecRestoreArrayRead(w, &wg));
  PetscCall(VecRestoreArrayRead(u, &ug));
  if (musl) PetscCall(VecRestoreArray(sum, &mom));
  // What the class took from the nodes, summed over the ending classes into taken (zero before
  // the levels of the first: endClasses); with MUSL its correction forms it in its own pass.
  if (musl) {
    PetscCall(correction(c, k, e, flip));
    w = w0.meanW;
  } else {
    PetscCall(takenBy(k, flip, c.dt, w0.taken, e > 0, true));
  }
  // (a report follows the coarse step: the class's strain energy before its update, the last
  // one of the coarse step counting; WorkLedger::strainBefore)
  double *sb = s.work.strainBefore.empty() ? nullptr : &s.work.strainBefore[k];
  typename Step<D>::CheckTally mine;
  PetscCall(step_.stress(r.st[k], q, w, every * c.dt, sb, tally ? &mine : nullptr));
  if (tally) { // (the classes end in swarm order: the first bad one is the swarm's first)
    if (tally->bad < 0 && mine.bad >= 0) tally->bad = r.begin[k] + mine.bad;
    tally->leaving += mine.leaving;
  }
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode MultiRate<D>::correction(const StepClock &c, int k, size_t e, double flip) {
  // The stress from the mean grid velocity over the class's step (what moved it); with MUSL
  // plus the class's own re-projection correction (its new momenta minus what it took, over the
  // nodal mass): with one class MUSL's velocity, with several each class's share of it. What it
  // took (Taken) is formed here, in the same pass, and added to taken.
  RunState<D> &s = s_;
  RateScratch &w0 = scratch_;
  Nodal &n = s.nodal;
  const double every = static_cast<double>(r_.every[k]);
  const int from = r_.from[k];
  PetscCall(s.grid.endSum(n.sumW, w0.corr, from)); // (the class's new momenta: endClass)
  Vec vsv = r_.every[k] > 1 ? sums_.vsum[k] : n.vel;
  Taken took = taken(k, flip, c.dt);
  const PetscScalar *im = nullptr, *vs = nullptr;
  PetscScalar *cr = nullptr, *cs = nullptr, *sf = nullptr, *tk = nullptr;
  PetscCall(took.get(true)); // (the class's sums are read here last: zeroed after)
  PetscCall(VecGetArray(w0.taken, &tk));
  PetscCall(VecGetArrayRead(n.invMass, &im));
  PetscCall(VecGetArrayRead(vsv, &vs));
  PetscCall(VecGetArray(w0.corr, &cr));
  PetscCall(VecGetArray(w0.corrSum, &cs));
  // The stress velocity on the window: formed on nodal.f (free after the grid update) and moved
  // there, or formed there where the window is the global array and no crack contact follows.
  const bool direct = s.grid.windowIsLocal() && s.sc.cracks.empty();
  Vec sv = direct ? w0.meanW : n.f;
  PetscCall(VecGetArray(sv, &sf));
  // (corrSum, taken: zero outside the first's values)
  // (endClasses: with velInCorrection the correction goes to the velocity, with
  // momentumInCorrection what the class took comes off P; each value's reads come first, so
  // vs and took read the velocity before it)
  PetscScalar *vel = nullptr, *P = nullptr;
  if (w0.velInCorrection) PetscCall(VecGetArray(n.vel, &vel));
  if (w0.momentumInCorrection) PetscCall(VecGetArray(n.P, &P));
  const DivideBy by(every);
  const auto pass = [&](auto flipOn, auto firstOn, auto power2On, auto velOn, auto momentumOn) {
    constexpr bool first = decltype(firstOn)::value; // (the branches as constants: one loop)
    constexpr bool power2 = decltype(power2On)::value;
    for (const auto &st : r_.values[k])
      for (PetscInt node = st[0]; node < st[1]; node += D) { // (a node's first value)
        for (int q = 0; q < D; ++q) {
          const PetscInt i = node + q;
          const double t = took.template at<decltype(flipOn)::value>(node, q);
          const double ci = (cr[i] - t) * im[i];
          const double stressVelocity = (power2 ? vs[i] * by.inverse : vs[i] / every) + ci;
          if constexpr (decltype(momentumOn)::value)
            P[i] = P[i] - t;
          else
            tk[i] = first ? t : tk[i] + t;
          if constexpr (decltype(velOn)::value)
            vel[i] = vel[i] + ci;
          else
            cs[i] = first ? ci : cs[i] + ci;
          sf[i] = stressVelocity;
          cr[i] = 0.0; // (read no more: zero for the next class's sum)
        }
        took.zero(node);
      }
  };
  const std::true_type on;
  const std::false_type off;
  const auto passBy = [&](auto flipOn, auto firstOn) {
    const auto fused = [&](auto power2On) {
      if (w0.velInCorrection)
        w0.momentumInCorrection ? pass(flipOn, firstOn, power2On, on, on)
                                : pass(flipOn, firstOn, power2On, on, off);
      else
        w0.momentumInCorrection ? pass(flipOn, firstOn, power2On, off, on)
                                : pass(flipOn, firstOn, power2On, off, off);
    };
    by.power2 ? fused(on) : fused(off);
  };
  if (took.flip > 0)
    e == 0 ? passBy(on, on) : passBy(on, off);
  else
    e == 0 ? passBy(off, on) : passBy(off, off);
  if (P) PetscCall(VecRestoreArray(n.P, &P));
  if (vel) PetscCall(VecRestoreArray(n.vel, &vel));
  PetscCall(VecRestoreArray(sv, &sf));
  PetscCall(VecRestoreArray(w0.corrSum, &cs));
  PetscCall(VecRestoreArray(w0.corr, &cr));
  PetscCall(VecRestoreArrayRead(vsv, &vs));
  PetscCall(VecRestoreArrayRead(n.invMass, &im));
  PetscCall(VecRestoreArray(w0.taken, &tk));
  PetscCall(took.restore());
  sums_.clean[k] = 1;
  if (!direct) PetscCall(s.grid.toWindow(n.f, w0.meanW, from));
  // The re-projected fields of a cracked node may approach each other again: the same contact
  // as the single-rate step's (Step::reproject), or the strain would see the faces
  // interpenetrate.
  if (!s.sc.cracks.empty()) PetscCall(step_.crackContact(c, w0.meanW, n.f, nullptr, nullptr));
  return PETSC_SUCCESS;
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template PetscErrorCode MultiRate<D>::classForces(const ParticleView<D> &, const StepClock &,    \
                                                    PetscInt, StartPower &);                       \
  template PetscErrorCode MultiRate<D>::accumulate(const StepClock &, PetscInt);                   \
  template PetscErrorCode MultiRate<D>::endClasses(ParticleView<D> &, const StepClock &, PetscInt, \
                                                   const StartPower &,                             \
                                                   typename Step<D>::CheckTally *);
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
