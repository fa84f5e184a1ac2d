// The multi-rate step (solver/multirate.hpp): the classes, the coarse step and the classes'
// starts. Their forces and ends: solver/multirate_ends.cpp.
#include "gimp/solver/multirate.hpp"

#include "gimp/core/pair.hpp"
#include "gimp/grid/rounding.hpp"
#include "gimp/physics/constraints.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>

namespace gimp {

ClassSums::~ClassSums() {
  for (std::vector<Vec> *vs : {&mass, &mom, &inc, &vsum, &force, &base, &fext, &baseExt, &faces})
    for (Vec &v : *vs)
      (void)VecDestroy(&v);
  (void)VecDestroy(&nodeRate);
}

RateScratch::~RateScratch() {
  for (Vec *v : {&taken, &field, &corr, &corrSum, &fieldW, &meanW, &forceW})
    (void)VecDestroy(v);
}

Stretches unite(const Stretches &a, const Stretches &b) {
  // (both in order and disjoint: one merge of the two)
  Stretches u;
  u.reserve(a.size() + b.size());
  const auto add = [&u](const std::array<PetscInt, 2> &t) {
    if (t[0] >= t[1]) return;
    if (!u.empty() && t[0] <= u.back()[1])
      u.back()[1] = std::max(u.back()[1], t[1]);
    else
      u.push_back(t);
  };
  size_t i = 0, j = 0;
  while (i < a.size() || j < b.size())
    add(j == b.size() || (i < a.size() && a[i] < b[j]) ? a[i++] : b[j++]);
  return u;
}

Stretches minus(const Stretches &a, const Stretches &b) {
  // (both in order and disjoint: one walk along each)
  Stretches d;
  size_t e = 0;
  for (const auto &t : a) {
    while (e < b.size() && b[e][1] <= t[0])
      ++e;
    PetscInt at = t[0];
    for (size_t c = e; c < b.size() && b[c][0] < t[1]; ++c) {
      if (b[c][0] > at) d.push_back({at, b[c][0]});
      at = std::max(at, b[c][1]);
    }
    if (at < t[1]) d.push_back({at, t[1]});
  }
  return d;
}

PetscErrorCode zeroStretches(Vec v, const Stretches &at) {
  if (at.empty()) return PETSC_SUCCESS;
  PetscScalar *a = nullptr;
  PetscCall(VecGetArray(v, &a));
  for (const auto &t : at)
    std::fill(a + t[0], a + t[1], 0.0);
  PetscCall(VecRestoreArray(v, &a));
  return PETSC_SUCCESS;
}

PetscErrorCode dotsOn(Vec a, Vec b, Vec y, const Stretches &at, PetscScalar *z) {
  const PetscScalar *pa = nullptr, *pb = nullptr, *py = nullptr;
  PetscCall(VecGetArrayRead(a, &pa));
  PetscCall(VecGetArrayRead(b, &pb));
  PetscCall(VecGetArrayRead(y, &py));
  PetscScalar sum[2] = {0, 0};
  for (const auto &t : at)
    for (PetscInt i = t[0]; i < t[1]; ++i) {
      sum[0] = sum[0] + pa[i] * py[i];
      sum[1] = sum[1] + pb[i] * py[i];
    }
  PetscCall(VecRestoreArrayRead(y, &py));
  PetscCall(VecRestoreArrayRead(b, &pb));
  PetscCall(VecRestoreArrayRead(a, &pa));
  MPI_Comm comm = MPI_COMM_NULL;
  PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(y), &comm));
  PetscCallMPI(MPI_Allreduce(sum, z, 2, MPIU_SCALAR, MPIU_SUM, comm));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode MultiRate<D>::create(Vec like) {
  const Grid<D> &grid = s_.grid;
  RateClasses<D> &r = r_;
  const int n = static_cast<int>(grid.levels.size());
  r.n = n;
  r.every.resize(n);
  for (int c = 0; c < n; ++c)
    r.every[c] = static_cast<PetscInt>(grid.levels[c].step);
  r.begin.assign(n + 1, 0);
  r.size.assign(n, 0);
  r.switched.assign(n, 0);
  r.st.resize(n);
  r.start.assign(n, 0);
  r.live.assign(n, 0);
  r.from.assign(n, 0);
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(like, &nloc));
  r.values.assign(n, Stretches{{0, nloc}}); // (until their first start: anywhere)
  scratch_.dirty = {{0, nloc}};
  ClassSums &v = sums_;
  std::vector<std::vector<Vec> *> perClass = {&v.mass, &v.mom, &v.inc, &v.vsum};
  if (s_.sc.multirateNodeRule) { // the node rule's forces, bases and rates (the impulse rule
                                 // sums on the window)
    perClass.insert(perClass.end(), {&v.force, &v.base});
    if (s_.boundary.active()) perClass.push_back(&v.baseExt);
    PetscCall(VecDuplicate(like, &v.nodeRate));
  }
  if (s_.boundary.active()) perClass.push_back(&v.fext); // (for the work at the class's end)
  v.clean.assign(n, 0);
  r.extStart.assign(n, 0.0);
  r.extScale.assign(n, 0.0);
  r.loaded.assign(n, 1); // (until the first coarse start)
  r.fextZero.assign(n, 0);
  for (std::vector<Vec> *vs : perClass) {
    vs->assign(n, nullptr);
    for (Vec &x : *vs)
      PetscCall(VecDuplicate(like, &x));
  }
  RateScratch &w = scratch_;
  for (Vec *x : {&w.taken, &w.field, &w.corr, &w.corrSum})
    PetscCall(VecDuplicate(like, x));
  for (Vec *x : {&w.fieldW, &w.meanW, &w.forceW})
    PetscCall(grid.createWindowVec(x));
  return PETSC_SUCCESS;
}

namespace {

/// How far outside each side of level c's box (lows, then highs) its nodes reach: the zone of
/// its boundary nodes, the cell of the first coarser level whose box side does not coincide with
/// that side (a box sharing a side with its parent borders the grandparent's cells there).
template <int D> std::array<double, 2 * D> outwardZones(const Grid<D> &g, int c) {
  std::array<double, 2 * D> z{};
  for (int side = 0; side < 2 * D; ++side) {
    int q = c - 1;
    while (q > 0 && g.levels[q].box[side] == g.levels[c].box[side])
      --q;
    z[side] = g.levels[q].h;
  }
  return z;
}

/// Classes of whole cells (2D): the lane kernels take a cell's four particles as one block
/// (transfer/lane_runs.hpp, byBlock), which a class slice that starts inside a cell breaks for
/// every lane group after it. The 3D kernels take one particle at a time: there a whole cell only
/// adds particles to the faster classes (on options/block3d_multirate.opts the finest class grew
/// by half and the per-level step took 20 % more instructions).
template <int D> constexpr bool kWholeCells = D == 2;

/// Each particle's class (cls, n particles at x with half-sizes l): the finest level c whose box,
/// widened by the reach of its boundary nodes (zones), the particle's half-size and one finest
/// cell of motion within the coarse step, the particle's leaf cell (kWholeCells) or its own
/// domain overlaps (0 if none). Its leaf cell: the cell that holds its centre on the finest level
/// whose box holds it. The particle lies in that cell, so its class is never coarser than its own
/// domain needs, and the particles of one cell (of one half-size) share a class: a class holds
/// whole cells. One pass over the particles, each tried from the finest level down.
template <int D>
void classesOf(const Grid<D> &g, const std::vector<std::array<double, 2 * D>> &zones, PetscInt n,
               const double *x, const double *l, int *cls) {
  const int K = static_cast<int>(g.levels.size());
  const double m = g.hMin(), h0 = g.levels[0].h;
  // Per level c: its box widened by its zones, the finest cell and two level-0 cells (the
  // pretest: the leaf cell lies within a level-0 cell of the centre, so a box that the particle's
  // domain widened so does not meet, its leaf cell does not either, whatever the rounding; nor its
  // domain).
  // Their hull first: a particle whose domain misses it is near no box, class 0 (the same
  // comparisons: it misses each box's).
  std::vector<std::array<double, 2 * D>> near(K);
  std::array<double, 2 * D> hull;
  for (int a = 0; a < D; ++a)
    hull[a] = std::numeric_limits<double>::infinity(), hull[D + a] = -hull[a];
  for (int c = 1; c < K; ++c)
    for (int a = 0; a < D; ++a) {
      near[c][a] = g.levels[c].box[a] - zones[c][a] - m - 2 * h0;
      near[c][D + a] = g.levels[c].box[D + a] + zones[c][D + a] + m + 2 * h0;
      hull[a] = std::min(hull[a], near[c][a]);
      hull[D + a] = std::max(hull[D + a], near[c][D + a]);
    }
  const auto inside = [&](const double *xk, int q) {
    const BoxOf<D> &b = g.levels[q].box;
    bool in = true;
    for (int a = 0; a < D; ++a)
      in = in && xk[a] >= b[a] && xk[a] < b[D + a];
    return in;
  };
  for (PetscInt k = 0; k < n; ++k) {
    const double *xk = x + D * k, *lk = l + D * k;
    // Tried from the finest level down: a centre inside level c's box (and no finer one) has its
    // leaf cell there, which meets the box. Otherwise the leaf cell (or the particle's domain)
    // widened by the half-size, [lo, hi], is found when the box is near enough to need it.
    bool inHull = true;
    for (int a = 0; a < D; ++a)
      inHull = inHull && xk[a] + lk[a] > hull[a] && xk[a] - lk[a] < hull[D + a];
    if (!inHull) {
      cls[k] = 0;
      continue;
    }
    double lo[D] = {}, hi[D] = {};
    bool found = false;
    int c = K - 1;
    for (; c > 0; --c) {
      // (every comparison made, and'ed without branches: the outcome changes from particle to
      // particle along a row, where a branch per comparison is mispredicted)
      bool close = true;
      for (int a = 0; a < D; ++a)
        close = close & (xk[a] + lk[a] > near[c][a]) & (xk[a] - lk[a] < near[c][D + a]);
      if (!close) continue;
      if (inside(xk, c)) break;
      if (!found) {
        if constexpr (kWholeCells<D>) {
          // (the leaf level: the finest coarser than c whose box holds the centre)
          int q = c - 1;
          while (q > 0 && !inside(xk, q))
            --q;
          const Level<D> &L = g.levels[q];
          for (int a = 0; a < D; ++a) {
            lo[a] = L.box[a] + static_cast<double>(ifloor((xk[a] - L.box[a]) * L.ih)) * L.h;
            hi[a] = lo[a] + L.h + lk[a];
            lo[a] -= lk[a];
          }
        } else {
          for (int a = 0; a < D; ++a)
            lo[a] = xk[a] - lk[a], hi[a] = xk[a] + lk[a];
        }
        found = true;
      }
      const BoxOf<D> &b = g.levels[c].box; // (the box widened by its zones and the finest cell)
      const std::array<double, 2 *D> &z = zones[c];
      bool meets = true;
      for (int a = 0; a < D; ++a)
        meets = meets && hi[a] + z[a] + m > b[a] && lo[a] - z[D + a] - m < b[D + a];
      if (meets) break;
    }
    cls[k] = c;
  }
}

/// f called with n as a constant (std::integral_constant<int, n>) for n up to 3, else with -1
/// (any count): loops over a few classes unrolled.
template <class F> void countAsConstant(size_t n, F &&f) {
  switch (n) {
  case 0:
    return f(std::integral_constant<int, 0>{});
  case 1:
    return f(std::integral_constant<int, 1>{});
  case 2:
    return f(std::integral_constant<int, 2>{});
  case 3:
    return f(std::integral_constant<int, 3>{});
  default:
    return f(std::integral_constant<int, -1>{});
  }
}

/// The largest window node particle k's stencil reaches (levels are concatenated in the window,
/// coarse to fine, so this tells the finest level it reaches); a crack's second-field slot counts
/// as its node.
template <int D> PetscInt maxSlot(const Grid<D> &g, const Stencils<D> &st, PetscInt k) {
  if (st.isBlock(k)) {
    const Block<D> &b = st.block(k);
    PetscInt s = b.base + 2;
    for (int d = 0; d < D - 1; ++d)
      s += 2 * b.stride[d];
    return s;
  }
  if constexpr (D == 2)
    if (st.isBlock4(k)) {
      const Block<2, 4> &b = st.block4(k);
      return b.base + 3 * b.stride[0] + 3;
    }
  PetscInt s = -1;
  if (st.isLevels(k)) { // (window nodes: a level block holds no cracked node's second slot)
    // Per block the node of its highest entry bit that forEach visits (rows j < n[1], planes q
    // < n[2]: bit i + 4 j + 16 q; the slot grows with i, j and q).
    for (const LevelBlock<D> *b = st.levelBlocks.data() + st.levelOf[k];; ++b) {
      const int nq = D == 3 ? b->n[D - 1] : 1;
      const std::uint64_t row = (std::uint64_t{1} << (4 * b->n[1])) - 1;
      std::uint64_t visited = 0;
      for (int q = 0; q < nq; ++q)
        visited |= row << (16 * q);
      if (const std::uint64_t m = b->mask & visited) {
        const int top = 63 - __builtin_clzll(m), q = top / 16, j = top % 16 / 4;
        PetscInt slot = b->base + j * b->stride[0] + top % 4;
        if constexpr (D == 3) slot += q * b->stride[1];
        s = std::max(s, slot);
      }
      if (b->last) return s;
    }
  }
  for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e)
    s = std::max(s, g.slotNode[st.node[e]]);
  return s;
}

} // namespace

template <int D> PetscErrorCode MultiRate<D>::run(StepClock &done) {
  RunState<D> &s = s_;
  StepClock c0;
  PetscCall(readStepClock(s.ts, s.sc.halfStepStart, c0));
  PetscCall(PetscLogStagePush(s.stages.p2g));
  PetscCall(step_.migrate());
  PetscCall(classify(c0.step));
  PetscCall(PetscLogStagePop());
  ParticleView<D> p;
  PetscCall(p.get(s.sw));
  PetscCall(VecZeroEntries(s.nodal.P));                         // every class starts at sub-step 0
  scratch_.accAt = {{0, std::numeric_limits<PetscInt>::max()}}; // (gridUpdate: unknown here)
  PetscCall(decideSparseUpdate());
  s.work.strainBefore.assign(s.work.measureStrain ? r_.n : 0, 0.0);
  const bool cracked = !s.sc.cracks.empty();
  typename Step<D>::CheckTally tally; // (taken by the classes' stress updates at the last sub-step)
  for (PetscInt j = 0; j < s.stride(); ++j) {
    StepClock c;
    PetscCall(readStepClock(s.ts, s.sc.halfStepStart, c));
    PetscCall(startClasses(p, j));
    if (cracked) { // the classes' crack faces, contact on the momentum
      std::vector<Vec> faces;
      for (int k = 0; k < r_.n; ++k)
        if (r_.size[k] > 0) faces.push_back(sums_.faces[k]);
      PetscCall(step_.crackFaces(p, &faces));
      PetscCall(step_.contactOnMomentum(c));
    }
    StartPower power;
    PetscCall(classForces(p, c, j, power));
    PetscCall(gridUpdate(c, cracked, power));
    if (cracked) PetscCall(contactAfterUpdate(c));
    PetscCall(accumulate(c, j));
    PetscCall(endClasses(p, c, j, power, j + 1 == s.stride() ? &tally : nullptr));
  }
  PetscCall(readStepClock(s.ts, s.sc.halfStepStart, done));
  PetscCall(step_.checks(p, done.step, done.t, &tally));
  PetscCall(p.restore(s.sw));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode MultiRate<D>::decideSparseUpdate() {
  // Elsewhere a node's force is zero (classForces) and its momentum, mass and velocity are as
  // the last update left them (startNodes sets them where classes start): the euler update
  // would leave them, but for the damping, which moves every node whose momentum is not zero:
  // those lie on the classes' values (startNodes masks P to zero where no class has mass). Not
  // with the node rule (forces at other sub-steps), cracks (contact on every node) or several
  // ranks (the values are a tail); and TS must step over the final time, as it does by default
  // (a matched final step is TS's to choose).
  const RunState<D> &s = s_;
  TSExactFinalTimeOption exact = TS_EXACTFINALTIME_STEPOVER;
  PetscCall(TSGetExactFinalTime(s.ts, &exact));
  sparse_ = s.grid.windowIsLocal() && !s.sc.multirateNodeRule && s.sc.cracks.empty() &&
            exact == TS_EXACTFINALTIME_STEPOVER;
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode MultiRate<D>::gridUpdate(const StepClock &c, bool cracked, StartPower &power) {
  RunState<D> &s = s_;
  if (!sparse_) {
    scratch_.accAt = {{0, std::numeric_limits<PetscInt>::max()}};
    return step_.gridUpdate(cracked);
  }
  // Step::rhs and TS euler's update, value by value on the forced values (the same operations:
  // F = kick mask f, with damping kick mask (f - d P), P + dt F, v = P / m, a = F / m), with
  // damping also on the other values where P may be nonzero (f is zero there: F = kick mask (0 -
  // d P)), the velocity moved to the window where it changed (here or in startNodes), the
  // acceleration zeroed where it was left from before; with damping F kept in nodal.rhs for the
  // damping's work.
  Nodal &n = s.nodal;
  RateScratch &w0 = scratch_;
  PetscCall(PetscLogStagePush(s.stages.grid));
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(n.P, &nloc));
  const bool acc = s.sc.transfer != Transfer::Apic;
  const bool damped = s.sc.damping > 0;
  const PetscScalar *f = nullptr, *mk = nullptr, *im = nullptr;
  PetscScalar *P = nullptr, *v = nullptr, *a = nullptr, *vw = nullptr;
  PetscCall(VecGetArrayRead(n.f, &f));
  PetscCall(VecGetArrayRead(n.mask, &mk));
  PetscCall(VecGetArrayRead(n.invMass, &im));
  PetscCall(VecGetArray(n.P, &P));
  PetscCall(VecGetArray(n.vel, &v));
  if (acc) PetscCall(VecGetArray(n.acc, &a));
  const double dt = c.dt, kick = c.kick, nd = -s.sc.damping;
  const auto update = [&](PetscInt i, double F) { // (F with the kick: the RHS)
    if (kick != 1.0) F *= kick;
    P[i] = P[i] + dt * F;
    v[i] = P[i] * im[i];
    if (acc) a[i] = F * im[i];
    return F;
  };
  if (!damped) {
    for (const auto &t : w0.forced)
      for (PetscInt i = t[0]; i < t[1]; ++i)
        update(i, f[i] * mk[i]);
  } else {
    // In the values' order, with VecDot's sums of P v before (the damping's power at the
    // start) and after, and of F v after (Step::work); the forced values lie among them, and
    // f is zero on the rest (VecAXPY's 0 + (-d) P there).
    w0.massive.clear(); // (P is zero off the classes' values: decideSparseUpdate)
    for (int k = 0; k < r_.n; ++k)
      if (r_.size[k] > 0) w0.massive = unite(w0.massive, r_.values[k]);
    PetscScalar *rhs = nullptr;
    PetscCall(VecGetArray(n.rhs, &rhs));
    std::array<PetscScalar, 3> sums{}; // (P v before, P v after, F v after)
    // By blocks: the products and the update value by value (in pairs of lanes: F = (f - d P)
    // mask kick, P + dt F, v = P / m, a = F / m, the same operations; a kick of 1 leaves F as it
    // is), then the three sums over the block in the values' order.
    constexpr PetscInt kBlock = 256;
    std::array<PetscScalar, kBlock> before, after, rate; // (P v, P v, F v)
    const Stretches &fd = w0.forced;
    size_t e = 0;
    for (const auto &t : w0.massive)
      for (PetscInt i0 = t[0]; i0 < t[1];) {
        while (e < fd.size() && fd[e][1] <= i0)
          ++e;
        const bool forced = e < fd.size() && fd[e][0] <= i0;
        const PetscInt i1 = std::min(
            {t[1], e < fd.size() ? fd[e][forced ? 1 : 0] : t[1], i0 + kBlock}); // (one block)
        const PetscInt nb = i1 - i0;
        double *Pb = P + i0, *vb = v + i0, *rb = rhs + i0;
        const double *fb = f + i0, *mb = mk + i0, *ib = im + i0;
        for (PetscInt q = 0; q < nb; ++q)
          before[q] = Pb[q] * vb[q];
        if (forced)
          for (PetscInt q = 0; q < nb; ++q)
            rb[q] = (fb[q] + nd * Pb[q]) * mb[q] * kick;
        else
          for (PetscInt q = 0; q < nb; ++q)
            rb[q] = (0.0 + nd * Pb[q]) * mb[q] * kick;
        for (PetscInt q = 0; q < nb; ++q) {
          Pb[q] = Pb[q] + dt * rb[q];
          vb[q] = Pb[q] * ib[q];
          after[q] = Pb[q] * vb[q];
          rate[q] = rb[q] * vb[q];
        }
        if (acc)
          for (PetscInt q = 0; q < nb; ++q)
            a[i0 + q] = rb[q] * ib[q];
        for (PetscInt q = 0; q < nb; ++q) {
          sums[0] = sums[0] + before[q];
          sums[1] = sums[1] + after[q];
          sums[2] = sums[2] + rate[q];
        }
        i0 = i1;
      }
    PetscCall(VecRestoreArray(n.rhs, &rhs));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums.data(), 3, MPIU_SCALAR, MPIU_SUM, s.comm));
    power.damping = s.sc.damping * sums[0];
    w0.dampingDots = {sums[1], sums[2]};
  }
  const Stretches &moved = damped ? w0.massive : w0.forced; // (forced lies in massive)
  if (acc) {
    Stretches stale = minus(w0.accAt, moved);
    for (auto &t : stale) {
      t[1] = std::min(t[1], nloc);
      if (t[0] < t[1]) std::fill(a + t[0], a + t[1], 0.0);
    }
    w0.accAt = moved;
    PetscCall(VecRestoreArray(n.acc, &a));
  }
  PetscCall(VecGetArray(n.velW, &vw));
  for (const auto &t : unite(moved, w0.swept))
    std::copy(v + t[0], v + t[1], vw + t[0]);
  PetscCall(VecRestoreArray(n.velW, &vw));
  PetscCall(VecRestoreArray(n.vel, &v));
  PetscCall(VecRestoreArray(n.P, &P));
  PetscCall(VecRestoreArrayRead(n.invMass, &im));
  PetscCall(VecRestoreArrayRead(n.mask, &mk));
  PetscCall(VecRestoreArrayRead(n.f, &f));
  // TS's clock, as its euler step moves it
  PetscReal t = 0, h = 0;
  PetscInt step = 0;
  PetscCall(TSGetTime(s.ts, &t));
  PetscCall(TSGetTimeStep(s.ts, &h));
  PetscCall(TSGetStepNumber(s.ts, &step));
  PetscCall(TSSetTime(s.ts, t + h));
  PetscCall(TSSetStepNumber(s.ts, step + 1));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode MultiRate<D>::contactAfterUpdate(const StepClock &c) {
  // Contact on the new velocities; the momentum follows them.
  Nodal &n = s_.nodal;
  PetscCall(VecCopy(n.vel, scratch_.field));
  PetscCall(step_.crackContact(c, n.velW, n.vel, n.accW, n.acc));
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(n.P, &nloc));
  const PetscScalar *m = nullptr, *v = nullptr, *was = nullptr;
  PetscScalar *P = nullptr;
  PetscCall(VecGetArrayRead(n.mass, &m));
  PetscCall(VecGetArrayRead(n.vel, &v));
  PetscCall(VecGetArrayRead(scratch_.field, &was));
  PetscCall(VecGetArray(n.P, &P));
  for (PetscInt i = 0; i < nloc; i += D)
    for (int d = 0; d < D; ++d)
      P[i + d] += m[i] * (v[i + d] - was[i + d]);
  PetscCall(VecRestoreArray(n.P, &P));
  PetscCall(VecRestoreArrayRead(scratch_.field, &was));
  PetscCall(VecRestoreArrayRead(n.vel, &v));
  PetscCall(VecRestoreArrayRead(n.mass, &m));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode MultiRate<D>::classify(PetscInt step) {
  RunState<D> &s = s_;
  RateClasses<D> &r = r_;
  ParticleView<D> p;
  PetscCall(p.get(s.sw));
  std::vector<int> &cls = cls_; // (every entry written below: the room of the last call)
  cls.resize(static_cast<size_t>(p.n));
  std::vector<std::array<double, 2 * D>> zones(s.grid.levels.size());
  for (size_t c = 1; c < zones.size(); ++c)
    zones[c] = outwardZones(s.grid, static_cast<int>(c));
  classesOf<D>(s.grid, zones, p.n, p.x, p.l, cls.data());
  // A particle with a penalty face is in the finest class: the penalty's stability bound is the
  // finest step's.
  if (p.dbc)
    for (PetscInt k = 0; k < p.n; ++k)
      for (int a = 0; a < D; ++a)
        if (p.dbc[D * k + a] >= 0) cls[k] = r.n - 1;
  PetscCall(p.restore(s.sw));
  // Classes contiguous every coarse step; ordered by cell within a class when a sort is due.
  PetscCall(step_.sortParticles(&cls, dueIn(step, step + s.stride(), s.sc.sortInterval)));
  PetscCall(p.get(s.sw));
  std::vector<PetscInt64> count(r.n, 0);
  for (int c = 0; c < r.n; ++c) { // (the classes are contiguous and in order now)
    r.begin[c + 1] =
        static_cast<PetscInt>(std::upper_bound(cls.begin(), cls.end(), c) - cls.begin());
    count[c] = r.begin[c + 1] - r.begin[c];
  }
  PetscCallMPI(MPI_Allreduce(count.data(), r.size.data(), r.n, MPI_INT64_T, MPI_SUM, s.comm));
  std::string sizes;
  for (int c = 0; c < r.n; ++c)
    sizes += " " + std::to_string(r.size[c]) + " (every " + std::to_string(r.every[c]) + ")";
  PetscCall(PetscInfo(nullptr, "step %" PetscInt_FMT ": particles per rate class:%s\n", step,
                      sizes.c_str()));
  // A particle that changes class gets the mean of its old and new steps as its first kick (the
  // variable-step leapfrog): its velocity stands half its old step before and half its new step
  // after the sync point.
  // (kickScale is read only for a class with switched particles: filled when one switched)
  r.kickScale.clear();
  r.switched.assign(r.n, 0);
  // (most particles keep their class: a block of them is passed over after one vector pass)
  constexpr PetscInt kBlock = 64;
  for (PetscInt k0 = 0; k0 < p.n; k0 += kBlock) {
    const PetscInt k1 = std::min(p.n, k0 + kBlock);
    unsigned changed = 0;
    for (PetscInt k = k0; k < k1; ++k)
      changed |= static_cast<unsigned>(p.rate[k] ^ cls[k]);
    if (!changed) continue;
    for (PetscInt k = k0; k < k1; ++k) {
      const PetscInt was = p.rate[k], now = cls[k];
      if (was == now) continue;
      if (was >= 0) {
        if (r.kickScale.empty()) r.kickScale.assign(static_cast<size_t>(p.n), 1.0);
        r.kickScale[k] = 0.5 * static_cast<double>(r.every[was] + r.every[now]) /
                         static_cast<double>(r.every[now]);
        ++r.switched[now];
      }
      p.rate[k] = now;
    }
  }
  PetscCall(p.restore(s.sw));
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode MultiRate<D>::startClass(ParticleView<D> &p, int k, PetscInt j, Stretches &changed) {
  RunState<D> &s = s_;
  RateClasses<D> &r = r_;
  Nodal &n = s.nodal;
  const ParticleView<D> q = p.slice(r.begin[k], r.begin[k + 1]);
  r.st[k].swarmOrigin = r.begin[k];
  // The bounding box of the class's particles' domains (classReach) and, below the finest
  // class, whether its margin kept it off the finer levels' nodes (only where they might reach:
  // no node of level k + 1 or finer reaches farther out of level k + 1's box than a level-0
  // cell, the widest zone): the build notes both as it reads the particles (Grid::BuildSeen).
  const bool finer = k + 1 < r.n;
  typename Grid<D>::BuildSeen &seen = seen_;
  seen.watch = finer;
  seen.near = s.grid.levels[finer ? k + 1 : k].box;
  seen.reach = s.grid.levels[0].h;
  const bool built = s.grid.buildStencils(q.n, q.x, q.l, r.st[k], true, s.lanes, true, &seen);
  if (!built) {
    // (a particle that went bad inside the coarse step: the check at its end reports it; the
    // class reaches no node until then)
    s.status.localFailure = "a particle is larger than a level-0 cell (its half-size exceeds "
                            "-gimp_h)";
    r.st[k].compact = false;
    r.st[k].start.assign(static_cast<size_t>(q.n) + 1, 0);
  }
  cracks::assignFields<D>(s.grid, s.sc.cracks, q.n, q.x, r.st[k]);
  double lo[D], hi[D];
  bool reached = false;
  if (built) {
    for (int a = 0; a < D; ++a)
      lo[a] = seen.lo[a], hi[a] = seen.hi[a];
    const PetscInt finerStart = finer ? s.grid.levels[k + 1].offset : 0;
    for (PetscInt i : seen.nearParticles)
      if (maxSlot(s.grid, r.st[k], i) >= finerStart) {
        reached = true;
        break;
      }
  } else { // (no particle has entries; the class's values: every level's, until the step fails)
    for (int a = 0; a < D; ++a)
      lo[a] = -std::numeric_limits<double>::infinity(), hi[a] = -lo[a];
  }
  if (reached)
    s.status.localFailure = "a particle of level " + std::to_string(k) +
                            "'s rate class reached level " + std::to_string(k + 1) +
                            "'s nodes within a coarse step (it moved more than one finest "
                            "cell; reduce -ts_dt)";
  // Its P2G onto the values it reaches (its sums zero where its last start's or this one's
  // values lie, zero elsewhere already): the nodal sums and moves from its level on.
  const Stretches was = r.values[k];
  PetscCall(classReach(lo, hi, q.n > 0, k));
  const int from = r.from[k];
  changed = unite(was, r.values[k]); // (its momenta join P in startNodes)
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(n.P, &nloc));
  if (!sums_.clean[k]) { // (else zero everywhere: its last end zeroed them)
    PetscCall(zeroStretches(sums_.mom[k], changed));
    PetscCall(zeroStretches(sums_.mass[k], changed));
  }
  sums_.clean[k] = 0;
  PetscScalar *mom = nullptr, *mass = nullptr;
  Vec momSum = nullptr, massSum = nullptr;
  PetscCall(s.grid.startSum(n.sumW, sums_.mom[k], &momSum, from, nloc));
  PetscCall(s.grid.startSum(n.massW, sums_.mass[k], &massSum, from, nloc));
  PetscCall(VecGetArray(momSum, &mom));
  PetscCall(VecGetArray(massSum, &mass));
  step_.projectMomentum(r.st[k], q, q.x, mom, mass);
  PetscCall(VecRestoreArray(massSum, &mass));
  PetscCall(VecRestoreArray(momSum, &mom));
  PetscCall(s.grid.endSum(n.sumW, sums_.mom[k], from));
  PetscCall(s.grid.endSum(n.massW, sums_.mass[k], from));
  if constexpr (D == 2)
    if (!s.sc.cracks.empty()) { // the class's crack faces, until its end
      if (sums_.faces.empty()) sums_.faces.assign(r.n, nullptr);
      if (!sums_.faces[k]) PetscCall(s.grid.createWindowVec(&sums_.faces[k]));
      PetscScalar *f = nullptr;
      PetscCall(VecGetArray(sums_.faces[k], &f));
      step_.contact().faces(s.grid, r.st[k], q.n, q.x, q.X0, q.m, f);
      PetscCall(VecRestoreArray(sums_.faces[k], &f));
    }
  r.start[k] = j;
  r.live[k] = 0;
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode MultiRate<D>::startClasses(ParticleView<D> &p, PetscInt j) {
  RunState<D> &s = s_;
  RateClasses<D> &r = r_;
  Nodal &n = s.nodal;
  PetscCall(PetscLogStagePush(s.stages.p2g));
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(n.P, &nloc));
  Stretches sweep;
  for (int k = 0; k < r.n; ++k) {
    if (r.size[k] == 0 || j % r.every[k] != 0) continue;
    Stretches changed;
    PetscCall(startClass(p, k, j, changed));
    sweep = unite(sweep, changed);
  }
  // The mass of every class (each from its last start), the masks and the velocity, where the
  // starting classes changed them. Elsewhere the nodes kept them: the classes that start are
  // those that ended at the sub-step before, and the grid update left v = P / m. At a coarse
  // step's start everywhere (a class may have emptied).
  if (j == 0) sweep = {{0, nloc}};
  if (!sweep.empty()) PetscCall(startNodes(sweep, j));
  scratch_.swept = sweep;
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode MultiRate<D>::startNodes(const Stretches &sweep, PetscInt j) {
  // One pass over the nodes of `sweep`. The starting classes' momenta join P (in class
  // order). The nodal mass is the sum of every class's (each from its last start, in class
  // order). With the node rule also each node's rate: the step of the slowest class whose mass is
  // on it now (its anchor; 1 on an empty node); the anchor stays on the node through its own
  // step, so the changes of the faster classes' forces (MultiRate::classForces) always find mass
  // there. Then the masks, P masked and v = P / m (physics::maskMomentumNode).
  RunState<D> &s = s_;
  RateClasses<D> &r = r_;
  Nodal &n = s.nodal;
  struct Part { // a class's nodal sums, zero outside its values
    Vec v;
    const PetscScalar *a;
    const Stretches *at;
    double every;
    size_t next; // (has: the first of its stretches that may hold a later piece)
    bool has(PetscInt i) {
      while (next < at->size() && (*at)[next][1] <= i)
        ++next;
      return next < at->size() && (*at)[next][0] <= i;
    }
  };
  std::vector<Part> masses, moms;
  for (int k = 0; k < r.n; ++k) {
    if (r.size[k] == 0) continue;
    masses.push_back({sums_.mass[k], nullptr, &r.values[k], static_cast<double>(r.every[k]), 0});
    if (j % r.every[k] == 0) moms.push_back({sums_.mom[k], nullptr, &r.values[k], 0.0, 0});
  }
  for (std::vector<Part> *parts : {&masses, &moms})
    for (Part &c : *parts)
      PetscCall(VecGetArrayRead(c.v, &c.a));
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(n.mass, &nloc));
  const double cut = s.sc.massCutoff * s.meanParticleMass;
  PetscScalar *m = nullptr, *rate = nullptr, *P = nullptr, *v = nullptr, *mk = nullptr,
              *im = nullptr;
  const PetscScalar *bc = nullptr;
  PetscCall(VecGetArray(n.mass, &m));
  if (s.sc.multirateNodeRule) PetscCall(VecGetArray(sums_.nodeRate, &rate));
  PetscCall(VecGetArray(n.P, &P));
  PetscCall(VecGetArray(n.vel, &v));
  PetscCall(VecGetArray(n.mask, &mk));
  PetscCall(VecGetArray(n.invMass, &im));
  PetscCall(VecGetArrayRead(n.bcMask, &bc));
  // By pieces of the sweep in which the same classes have values (each class's sums are zero
  // outside its values): cut where a class's values start or end.
  std::vector<PetscInt> cuts; // (each set's ends in order: merged as they come)
  const auto addCuts = [&cuts](const Stretches &at) {
    const auto mid = static_cast<std::ptrdiff_t>(cuts.size());
    for (const auto &t : at)
      cuts.insert(cuts.end(), {t[0], t[1]});
    std::inplace_merge(cuts.begin(), cuts.begin() + mid, cuts.end());
  };
  addCuts(sweep);
  for (const std::vector<Part> *parts : {&masses, &moms})
    for (const Part &c : *parts)
      addCuts(*c.at);
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  std::vector<const PetscScalar *> ms, ps; // the sums of the classes with values in the piece
  std::vector<double> everyOf;             // (the node rule: ms's steps)
  Part swept{nullptr, nullptr, &sweep, 0.0, 0};
  for (size_t t = 0; t + 1 < cuts.size(); ++t) { // (the pieces in order: has walks on)
    const PetscInt i0 = cuts[t], i1 = cuts[t + 1];
    if (!swept.has(i0)) continue;
    ms.clear();
    ps.clear();
    everyOf.clear();
    for (Part &c : masses)
      if (c.has(i0)) ms.push_back(c.a), everyOf.push_back(c.every);
    for (Part &c : moms)
      if (c.has(i0)) ps.push_back(c.a);
    // Node by node in one pass: its momenta and mass summed in class order (from P and from
    // 0.0), the rest of the mass values 0, its rate, then its masks. (The class counts as
    // constants up to 3 classes of each: the sums unrolled.)
    const auto piece = [&](auto npOf, auto nmOf) {
      constexpr int kP = decltype(npOf)::value, kM = decltype(nmOf)::value; // (-1: any)
      const size_t np = kP >= 0 ? static_cast<size_t>(kP) : ps.size();
      const size_t nm = kM >= 0 ? static_cast<size_t>(kM) : ms.size();
      for (PetscInt i = i0; i < i1; i += D) {
        for (int d = 0; d < D; ++d) {
          double sum = P[i + d];
          for (size_t c = 0; c < np; ++c)
            sum += ps[c][i + d];
          P[i + d] = sum;
        }
        double mass = 0.0; // (the mass in component 0, the rest 0)
        for (size_t c = 0; c < nm; ++c)
          mass += ms[c][i];
        m[i] = mass;
        for (int d = 1; d < D; ++d)
          m[i + d] = 0.0;
        if (rate)
          for (int d = 0; d < D; ++d) {
            rate[i + d] = 1.0;
            for (size_t c = 0; c < nm; ++c)
              if (ms[c][i] > 0) rate[i + d] = std::max(rate[i + d], everyOf[c]);
          }
        physics::maskMomentumNode(mass, bc + i, cut, D, mk + i, im + i, P + i, v + i);
      }
    };
    countAsConstant(ps.size(), [&](auto npOf) {
      countAsConstant(ms.size(), [&](auto nmOf) { piece(npOf, nmOf); });
    });
  }
  PetscCall(VecRestoreArrayRead(n.bcMask, &bc));
  PetscCall(VecRestoreArray(n.invMass, &im));
  PetscCall(VecRestoreArray(n.mask, &mk));
  PetscCall(VecRestoreArray(n.vel, &v));
  PetscCall(VecRestoreArray(n.P, &P));
  if (rate) PetscCall(VecRestoreArray(sums_.nodeRate, &rate));
  PetscCall(VecRestoreArray(n.mass, &m));
  for (std::vector<Part> *parts : {&masses, &moms})
    for (Part &c : *parts)
      PetscCall(VecRestoreArrayRead(c.v, &c.a));
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode MultiRate<D>::addOnAndZero(Vec y, double a, Vec x, const Stretches &at,
                                          bool onZero) {
  if (at.empty()) return PETSC_SUCCESS;
  PetscScalar *py = nullptr, *px = nullptr;
  PetscCall(VecGetArray(y, &py));
  PetscCall(VecGetArray(x, &px));
  for (const auto &t : at)
    for (PetscInt i = t[0]; i < t[1]; ++i) {
      py[i] = (onZero ? 0.0 : py[i]) + a * px[i];
      px[i] = 0.0;
    }
  PetscCall(VecRestoreArray(x, &px));
  PetscCall(VecRestoreArray(y, &py));
  return PETSC_SUCCESS;
}

template <int D> Stretches MultiRate<D>::windowValues(int k, PetscInt nw) const {
  return s_.grid.windowIsLocal() ? r_.values[k]
                                 : Stretches{{s_.grid.windowLevelStart(r_.from[k]), nw}};
}

template <int D>
PetscErrorCode MultiRate<D>::classReach(const double *a, const double *b, bool any, int k) {
  // No particle reaches a level coarser than the one whose box holds it (Grid::coarsestReaching),
  // so none of the class reaches a level coarser than the finest box that holds all their
  // domains (their bounding box [a, b]). With cracks every level: the crack contact works on
  // every cracked node's fields.
  const Grid<D> &g = s_.grid;
  int lo = static_cast<int>(g.levels.size()) - 1;
  if (!s_.sc.cracks.empty()) lo = 0;
  if (lo > 0 && any) {
    // (the boxes are nested: the finest box that holds every domain, as coarsestReaching tests
    // one domain, on the same x - l and x + l)
    while (lo > 0) {
      const BoxOf<D> &f = g.levels[lo].box;
      bool inside = true;
      for (int d = 0; d < D; ++d)
        inside = inside && a[d] >= f[d] && b[d] <= f[D + d];
      if (inside) break;
      --lo;
    }
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_INT, MPI_MIN, s_.comm));
  r_.from[k] = lo;
  // Where its values lie. On one rank (the window is the global array) the nodes of level lo
  // that may reach the class's domains (a node's zones are at most a level-0 cell, so its support
  // overlaps the domains only within a level-0 cell of [a, b] along every axis; one node more
  // each way, against rounding): its rows along x within that box, then the finer levels.
  // Elsewhere (and where a domain is not finite) every value from the level's start on. Without
  // cracks neither goes past level k: its particles reach no node of level k + 1 or finer until
  // its next start (its class says so, and startClass stops the run where one did). Outside them
  // the class's sums stay zero and its nodal passes skip them. With cracks every value from
  // level lo = 0 on: the contact reads every cracked node.
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(s_.nodal.P, &nloc));
  const PetscInt l0 = g.localLevelStart(lo);
  Stretches &v = r_.values[k];
  const bool cracked = !s_.sc.cracks.empty();
  const PetscInt end = cracked ? nloc : g.localLevelStart(std::max(lo, k) + 1);
  v = {{l0, end}};
  bool finite = any;
  for (int d = 0; d < D; ++d)
    finite = finite && std::isfinite(a[d]) && std::isfinite(b[d]);
  if (g.windowIsLocal() && !cracked && finite) {
    const Level<D> &L = g.levels[lo];
    const double h0 = g.levels[0].h;
    PetscInt i0[D], i1[D]; // (the nodes [i0, i1) of the level's window along each axis)
    for (int d = 0; d < D; ++d) {
      const auto node = [&](double y) { // (clamped before the cast: a far particle is finite)
        const double q = std::floor((y - L.box[d]) * L.ih) - static_cast<double>(L.w0[d]);
        return static_cast<PetscInt>(std::clamp(q, 0.0, static_cast<double>(L.wn(d))));
      };
      i0[d] = std::max<PetscInt>(node(a[d] - h0) - 1, 0);
      i1[d] = std::min<PetscInt>(node(b[d] + h0) + 2, L.wn(d));
    }
    // The rows along x (y, then z, in the window's order), a row's values next to the last's
    // joined to them.
    Stretches rows;
    const PetscInt nz = D == 3 ? i1[D - 1] : 1, z0 = D == 3 ? i0[D - 1] : 0;
    for (PetscInt q = z0; q < nz; ++q)
      for (PetscInt j = i0[1]; j < i1[1]; ++j) {
        const PetscInt row = l0 + D * L.wn(0) * (j + (D == 3 ? L.wn(1) * q : 0));
        const std::array<PetscInt, 2> t = {row + D * i0[0], row + D * i1[0]};
        if (t[0] >= t[1]) continue;
        if (!rows.empty() && rows.back()[1] == t[0])
          rows.back()[1] = t[1];
        else
          rows.push_back(t);
      }
    v = unite(rows, {{g.localLevelStart(lo + 1), end}});
  }
  return PETSC_SUCCESS;
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template PetscErrorCode MultiRate<D>::create(Vec);                                               \
  template Stretches MultiRate<D>::windowValues(int, PetscInt) const;                              \
  template PetscErrorCode MultiRate<D>::addOnAndZero(Vec, double, Vec, const Stretches &, bool);   \
  template PetscErrorCode MultiRate<D>::run(StepClock &);
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
