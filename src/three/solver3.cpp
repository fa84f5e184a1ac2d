// The 3D solver: setup and the step's phases (docs/architecture.md, "The 3D solver").
#include "gimp/three/solver3.hpp"

#include "../input/scene_options.hpp"
#include "gimp/core/errors.hpp"
#include "gimp/core/interrupt.hpp"
#include "gimp/input/validate.hpp"
#include "gimp/particles/seed.hpp"
#include "gimp/physics/constraints.hpp"
#include "gimp/physics/internal_force.hpp"
#include "gimp/physics/material.hpp"
#include "gimp/physics/mms.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/transfer.hpp"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <limits>
#include <memory>

namespace gimp::three {

Solver3::~Solver3() {
  for (Vec *v : {&P_, &mass_, &vel_, &acc_, &f_, &fext_, &rhs_, &bcMask_, &mask_, &invMass_, &sumW_,
                 &massW_, &velW_, &accW_, &extW_})
    (void)VecDestroy(v);
  (void)TSDestroy(&ts_);
  (void)DMDestroy(&sw_);
  if (history_) std::fclose(history_);
}

PetscErrorCode Solver3::setup() {
  PetscCallMPI(MPI_Comm_rank(comm_, &rank_));
  PetscCallMPI(MPI_Comm_size(comm_, &size_));
  PetscCall(readOptionsOneLine([&] { return readScene<3>(comm_, sc_); }));
  if (sc_.help) return PETSC_SUCCESS;
  PetscCall(PetscTime(&wall0_));
  PetscCall(stages_.registerAll());
  std::vector<LevelBox<3>> boxes = sc_.levels;
  std::copy(sc_.domain.begin(), sc_.domain.end(), boxes[0].box.begin());
  PetscCall(grid_.create(comm_, sc_.h, boxes));
  PetscCall(createNodal());
  PetscCall(nodeConstraints());
  // The particles, and the checks that every body and every face condition got some.
  sc_.idSlots = bodyIdSlots<3>(grid_);
  PetscCall(createSwarm<3>(comm_, optionalFieldsOf(sc_), &sw_));
  LoadConflict conflict;
  PetscCall(seedParticles<3>(sc_, grid_, sw_, conflict));
  PetscCall(conflict.agree(comm_, sc_));
  {
    ParticleView<3> p;
    PetscCall(p.get(sw_));
    const size_t nb = sc_.bodies.size(), nt = sc_.tractions.size(), nd = sc_.dbcs.size();
    std::vector<PetscInt64> count(nb + nt + nd + 1, 0);
    double mass = 0;
    for (PetscInt k = 0; k < p.n; ++k) {
      ++count[static_cast<size_t>(p.id[k] / sc_.idSlots)];
      mass += p.m[k];
      for (int a = 0; a < 3 && p.trac; ++a) {
        if (p.trac[3 * k + a] >= 0) ++count[nb + static_cast<size_t>(p.trac[3 * k + a])];
        if (p.dbc[3 * k + a] >= 0) ++count[nb + nt + static_cast<size_t>(p.dbc[3 * k + a])];
      }
    }
    count[nb + nt + nd] = p.n;
    PetscCall(p.restore(sw_));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, count.data(), static_cast<int>(count.size()),
                               MPI_INT64_T, MPI_SUM, comm_));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &mass, 1, MPI_DOUBLE, MPI_SUM, comm_));
    for (size_t b = 0; b < nb; ++b)
      if (count[b] == 0)
        throw InputError("option -gimp_body" + std::to_string(b) + "_" + sc_.bodies[b].shapeOption +
                         ": the body holds no particle centre (check its shape and holes)");
    for (size_t q = 0; q < nt + nd; ++q)
      if (count[nb + q] == 0) {
        const bool tr = q < nt;
        static const char *const sides[] = {"left", "right", "bottom", "top", "back", "front"};
        const Face<3> &f = tr ? static_cast<const Face<3> &>(sc_.tractions[q]) : sc_.dbcs[q - nt];
        throw InputError(std::string("option -gimp_") + (tr ? "traction" : "dbc") +
                         std::to_string(tr ? q : q - nt) + "_side " + sides[f.side] +
                         ": no particle has a face on this face of body " + std::to_string(f.body) +
                         "'s box (within its range or disk, if given)");
      }
    nParticles_ = count[nb + nt + nd];
    meanParticleMass_ = mass / static_cast<double>(nParticles_);
  }
  if (sc_.mms == Mms::AxialWave) { // start displaced and pre-stressed, at rest (as in 2D)
    const mms::Skb1d ex(sc_.mmsAmplitude, sc_.material);
    ParticleView<3> p;
    PetscCall(p.get(sw_));
    for (PetscInt k = 0; k < p.n; ++k) {
      const double X = p.X0[3 * k], F = ex.F(X, 0.0);
      p.x[3 * k] = X + ex.u(X, 0.0);
      for (int a = 0; a < 3; ++a)
        p.v[3 * k + a] = 0.0;
      p.F[9 * k] = F;
      p.V[k] = F * p.V0[k];
      if (sc_.tracking == Tracking::Stretch) p.l[3 * k] = F * p.l0[3 * k];
      material::neoHookeanStress(sc_.material, Tensor<3>(tensorAt<3>(p.F, k)), tensorAt<3>(p.s, k));
    }
    PetscCall(p.restore(sw_));
  }
  external_ = !sc_.tractions.empty() || !sc_.dbcs.empty() || sc_.gravity != Coords<3>{} ||
              sc_.mms != Mms::None;
  // The window coordinates of every slot (APIC's moments, the face forces).
  slotX_.resize(3 * static_cast<size_t>(grid_.nSlots));
  for (PetscInt s = 0; s < grid_.nSlots; ++s)
    for (int a = 0; a < 3; ++a)
      slotX_[3 * s + a] = grid_.coordinates(a)[grid_.slotNode[s]];
  // TS: explicit Euler on the momentum, dt from -ts_dt or the CFL number.
  PetscCall(TSCreate(comm_, &ts_));
  PetscCall(TSSetType(ts_, TSEULER));
  PetscCall(TSSetDM(ts_, grid_.dm));
  PetscCall(TSSetRHSFunction(ts_, nullptr, &Solver3::rhs, this));
  const double cp = sc_.maxWaveSpeed(), dtStable = grid_.hMin() / cp;
  PetscCall(TSSetTimeStep(ts_, sc_.cfl * dtStable));
  PetscCall(TSSetMaxSteps(ts_, 1000));
  PetscCall(TSSetMaxTime(ts_, 1e300));
  PetscCall(TSSetExactFinalTime(ts_, TS_EXACTFINALTIME_STEPOVER));
  PetscCall(timeStepFromOptions(ts_, cp, grid_.hMin(), false, sc_.damping));
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(ts_, &dt));
  PetscCall(TSSetSolution(ts_, P_));
  PetscCall(TSSetUp(ts_));
  // The penalty of Eq. 9, as in 2D (docs/method.md, "Penalty"): alpha h^2 on a node of mass
  // about rho h^3 / 2 is stable below 2 rho h / dt^2.
  if (!sc_.dbcs.empty()) {
    double M = 0, rho = 1e300, worst = 0, weakest = 1e300;
    for (const Body<3> &b : sc_.bodies) {
      const Material &m = sc_.oneMaterial ? sc_.material : b.material;
      M = std::max(M, m.lambda + 2.0 * m.mu);
      rho = std::min(rho, m.rho);
    }
    for (const DisplacementBC<3> &d : sc_.dbcs) {
      worst = std::max(worst, d.penaltyScale);
      weakest = std::min(weakest, d.penaltyScale);
    }
    const double h = grid_.hMin(), limit = 1.6 * rho * h / (dt * dt);
    alpha_ = sc_.penalty > 0 ? sc_.penalty : std::min(100.0 * M / h, 0.5 * rho * h / (dt * dt));
    if (sc_.penalty > 0 && alpha_ * worst > limit)
      throw InputError("option -gimp_penalty " + formatNumber(sc_.penalty) +
                       ": with the largest face scale " + formatNumber(worst) +
                       " it exceeds the stable limit 1.6 rho h_min / dt^2 = " +
                       formatNumber(limit) + " Pa/m for -ts_dt " + formatNumber(dt));
    if (sc_.penaltyTraction && alpha_ * weakest < 4.0 * M / h)
      throw InputError("option -gimp_penalty " + formatNumber(alpha_) +
                       ": with the smallest face scale " + formatNumber(weakest) +
                       " it is below 4 M / h_min = " + formatNumber(4.0 * M / h) +
                       " Pa/m, where the traction term of Eq. 9 goes unstable; raise it, or use "
                       "-gimp_penalty_traction false");
    PetscCall(PetscPrintf(comm_, "gimp: penalty alpha = %.6g Pa/m (%.3g M / h_min)\n", alpha_,
                          alpha_ * h / M));
  }
  // Probes: the particle nearest each point (the smallest id among equals), fixed for the run.
  if (!sc_.probes.empty()) {
    ParticleView<3> p;
    PetscCall(p.get(sw_));
    for (const Probe<3> &q : sc_.probes) {
      struct {
        double d;
        PetscInt64 id;
      } best{1e300, -1};
      for (PetscInt k = 0; k < p.n; ++k) {
        double d2 = 0;
        for (int a = 0; a < 3; ++a)
          d2 += (p.X0[3 * k + a] - q.x[a]) * (p.X0[3 * k + a] - q.x[a]);
        if (d2 < best.d || (d2 == best.d && p.id[k] < best.id)) best = {d2, p.id[k]};
      }
      double all = best.d;
      PetscCallMPI(MPI_Allreduce(&best.d, &all, 1, MPI_DOUBLE, MPI_MIN, comm_));
      PetscInt64 id = best.d == all ? best.id : std::numeric_limits<PetscInt64>::max(), minId = id;
      PetscCallMPI(MPI_Allreduce(&id, &minId, 1, MPI_INT64_T, MPI_MIN, comm_));
      probeIds_.push_back(minId);
    }
    PetscCall(p.restore(sw_));
  }
  PetscCall(rejectUnusedOptions(3));
  PetscCall(openOutput());
  PetscCall(PetscPrintf(comm_,
                        "gimp: 3D scene %s: %" PetscInt64_FMT " particles, %zu levels, h_min = "
                        "%.6g m, dt = %.6g s\n",
                        sc_.name.c_str(), nParticles_, grid_.levels.size(), grid_.hMin(), dt));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::createNodal() {
  PetscCall(DMCreateGlobalVector(grid_.dm, &P_));
  for (Vec *v : {&mass_, &vel_, &acc_, &f_, &fext_, &rhs_, &bcMask_, &mask_, &invMass_})
    PetscCall(VecDuplicate(P_, v));
  for (Vec *v : {&sumW_, &massW_, &velW_, &accW_, &extW_})
    PetscCall(grid_.createWindowVec(v));
  for (Vec v : {P_, vel_, acc_, f_, fext_, rhs_})
    PetscCall(VecZeroEntries(v));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::nodeConstraints() {
  // Each constraint's plane must be a level-0 grid plane; every active node on it (within the
  // range) has its fixed components masked, on every level.
  PetscCall(VecSet(bcMask_, 1.0));
  if (sc_.bcs.empty()) return PETSC_SUCCESS;
  static const char *const axes[] = {"x", "y", "z"};
  std::vector<std::int64_t> lines;
  for (size_t b = 0; b < sc_.bcs.size(); ++b) {
    const NodeBC<3> &bc = sc_.bcs[b];
    const PetscInt line = grid_.lineIndex(bc.axis, bc.coord);
    if (line < 0)
      throw InputError("option -gimp_bc" + std::to_string(b) + "_" + axes[bc.axis] + " " +
                       formatNumber(bc.coord) +
                       ": not on a level-0 grid plane inside the domain "
                       "(planes at " +
                       formatNumber(grid_.origin[bc.axis]) + " + i * " + formatNumber(grid_.h0()) +
                       ")");
    lines.push_back(grid_.levels[0].lo[bc.axis] + line * grid_.levels[0].step);
  }
  const int K = static_cast<int>(grid_.levels.size());
  std::vector<Vec> sub(K);
  std::vector<PetscInt64> hits(sc_.bcs.size(), 0); // the nodes each constraint fixes
  PetscCall(DMCompositeGetAccessArray(grid_.dm, bcMask_, K, nullptr, sub.data()));
  for (int k = 0; k < K; ++k) {
    const Level<3> &L = grid_.levels[k];
    PetscInt s[3], m[3];
    PetscScalar ****mk;
    PetscCall(DMDAGetCorners(grid_.da[k], &s[0], &s[1], &s[2], &m[0], &m[1], &m[2]));
    PetscCall(DMDAVecGetArrayDOF(grid_.da[k], sub[k], &mk));
    const double tol = 1e-9 * L.h;
    for (PetscInt q = s[2]; q < s[2] + m[2]; ++q)
      for (PetscInt j = s[1]; j < s[1] + m[1]; ++j)
        for (PetscInt i = s[0]; i < s[0] + m[0]; ++i) {
          const LatticeIndex<3> idx = {i, j, q};
          if (!grid_.nodeActive(k, idx)) continue;
          for (size_t b = 0; b < sc_.bcs.size(); ++b) {
            const NodeBC<3> &bc = sc_.bcs[b];
            if (L.at(bc.axis, idx[bc.axis]) != lines[b]) continue;
            bool in = true;
            int r = 0;
            for (int a = 0; a < 3 && bc.hasRange; ++a) {
              if (a == bc.axis) continue;
              const double c = grid_.nodeCoordinate(k, a, idx[a]);
              in = in && c >= bc.range[2 * r] - tol && c <= bc.range[2 * r + 1] + tol;
              ++r;
            }
            if (!in) continue;
            ++hits[b];
            for (int c = 0; c < 3; ++c)
              if (bc.fix[c]) mk[q][j][i][c] = 0.0;
          }
        }
    PetscCall(DMDAVecRestoreArrayDOF(grid_.da[k], sub[k], &mk));
  }
  PetscCall(DMCompositeRestoreAccessArray(grid_.dm, bcMask_, K, nullptr, sub.data()));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, hits.data(), static_cast<int>(hits.size()), MPI_INT64_T,
                             MPI_SUM, comm_));
  for (size_t b = 0; b < hits.size(); ++b)
    if (hits[b] == 0)
      throw InputError("option -gimp_bc" + std::to_string(b) + "_range " +
                       input::fmtList(sc_.bcs[b].range.data(), 4) +
                       ": no active grid node of the plane lies in the range");
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::rhs(TS ts, PetscReal, Vec X, Vec F, void *ctx) {
  // F = kick * mask * (f - d p), as in 2D (Solver::rhs).
  const Solver3 *s = static_cast<const Solver3 *>(ctx);
  StepClock c;
  PetscCall(readStepClock(ts, s->sc_.halfStepStart, c));
  PetscCall(VecCopy(s->f_, F));
  if (s->sc_.damping > 0) PetscCall(VecAXPY(F, -s->sc_.damping, X));
  PetscCall(VecPointwiseMult(F, F, s->mask_));
  if (c.kick != 1.0) PetscCall(VecScale(F, c.kick));
  PetscCall(VecCopy(F, s->rhs_));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::step() {
  StepClock c;
  PetscCall(readStepClock(ts_, sc_.halfStepStart, c));
  ParticleView<3> p;
  PetscCall(PetscLogStagePush(stages_.p2g));
  PetscCall(migrate());
  if (sc_.sortInterval > 0 && c.step % sc_.sortInterval == 0) PetscCall(sortParticles());
  PetscCall(p.get(sw_));
  // The checks after every step keep each particle within the grid and its rank's window; a
  // failure here joins those checks (kernels then see no particle on this rank).
  if (!grid_.buildStencils(p.n, p.x, p.l, st_, true)) {
    localFailure_ = "a particle is larger than a level-0 cell or left the grid";
    p.n = 0;
  }
  PetscCall(particlesToGrid(p));
  PetscCall(PetscLogStagePop());
  PetscCall(forces(p, c));
  PetscCall(gridUpdate());
  PetscCall(gridToParticles(p, c));
  // The work of the external and damping forces over the step (as Solver::work in 2D).
  if (external_) {
    PetscScalar fv = 0;
    PetscCall(VecDot(fext_, vel_, &fv));
    workExt_ += 0.5 * c.kick * c.dt * (powerExt0_ + fv);
  }
  if (sc_.damping > 0) {
    PetscScalar pv = 0, fv = 0;
    PetscCall(VecDot(P_, vel_, &pv));
    PetscCall(VecDot(rhs_, vel_, &fv));
    workDamp_ += 0.5 * c.kick * c.dt * (powerDamp0_ + sc_.damping * (pv - c.dt * fv));
  }
  PetscCall(stress(p, c.dt));
  PetscCall(checks(p, c.step + 1, c.t + c.dt));
  PetscCall(p.restore(sw_));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::migrate() {
  // Particles go to the rank owning their level-0 cell (the checks keep them within one cell of
  // it, inside its window).
  if (size_ == 1 || leaving_ == 0) return PETSC_SUCCESS;
  ParticleView<3> p;
  PetscCall(p.get(sw_));
  double box[6];
  grid_.ownedBox(rank_, box);
  PetscInt64 moved = 0;
  for (PetscInt k = 0; k < p.n; ++k) {
    const double *x = p.x + 3 * k;
    bool stays = true;
    for (int a = 0; a < 3; ++a)
      stays = stays && x[a] >= box[a] && x[a] < box[3 + a];
    if (stays) continue;
    p.rank[k] = grid_.ownerOf(x);
    if (p.rank[k] != rank_) ++moved;
  }
  PetscCall(p.restore(sw_));
  // The last check counted the particles leaving their ranks (leaving_); unknown (-1) at the
  // start, and this counts them itself.
  PetscInt64 any = leaving_;
  if (leaving_ < 0) PetscCallMPI(MPI_Allreduce(&moved, &any, 1, MPI_INT64_T, MPI_SUM, comm_));
  if (any) PetscCall(DMSwarmMigrate(sw_, PETSC_TRUE));
  migrated_ += any;
  leaving_ = -1;
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::sortParticles() {
  // P2G and G2P then walk the nodal arrays in order, whatever the seeding and the migrations;
  // nothing is allocated when the particles are in order already.
  ParticleView<3> p;
  PetscCall(p.get(sw_));
  const Level<3> &L = grid_.levels[0];
  using Key = std::pair<PetscInt64, PetscInt64>;
  auto keyOf = [&](PetscInt k) {
    PetscInt64 cell = 0;
    for (int a = 2; a >= 0; --a)
      cell = cell * static_cast<PetscInt64>(L.n[a]) +
             static_cast<PetscInt64>(std::floor((p.x[3 * k + a] - L.box[a]) * L.ih));
    return Key{cell, p.id[k]};
  };
  bool sorted = true;
  for (PetscInt k = 1; k < p.n && sorted; ++k)
    sorted = keyOf(k - 1) < keyOf(k);
  if (sorted) return p.restore(sw_);
  st_.release(); // the last step's stencils: room for the keys and the permutation buffer
  std::vector<std::pair<Key, PetscInt>> key(static_cast<size_t>(p.n));
  for (PetscInt k = 0; k < p.n; ++k)
    key[k] = {keyOf(k), k};
  PetscCall(p.restore(sw_));
  std::sort(key.begin(), key.end());
  std::vector<PetscInt> order(static_cast<size_t>(p.n));
  for (PetscInt k = 0; k < p.n; ++k)
    order[k] = key[k].second;
  return permuteSwarm<3>(sw_, order);
}

PetscErrorCode Solver3::particlesToGrid(const ParticleView<3> &p) {
  PetscScalar *mom = nullptr, *mass = nullptr;
  PetscCall(VecZeroEntries(sumW_));
  PetscCall(VecZeroEntries(massW_));
  PetscCall(VecGetArray(sumW_, &mom));
  PetscCall(VecGetArray(massW_, &mass));
  if (sc_.transfer == Transfer::Apic)
    transfer::particlesToGridAffineB<3>(st_, p.n, p.m, p.v, p.B, p.x, slotX_.data(), mom, mass);
  else
    transfer::particlesToGrid<3>(st_, p.n, p.m, p.v, mom, mass);
  PetscCall(VecRestoreArray(massW_, &mass));
  PetscCall(VecRestoreArray(sumW_, &mom));
  PetscCall(VecZeroEntries(P_));
  PetscCall(grid_.addFromWindow(sumW_, P_));
  PetscCall(VecZeroEntries(mass_));
  PetscCall(grid_.addFromWindow(massW_, mass_));
  // The mask: constrained components and nodes lighter than the cut-off take no force.
  PetscCall(
      physics::massMask(mass_, bcMask_, sc_.massCutoff * meanParticleMass_, mask_, invMass_, 3));
  PetscCall(VecPointwiseMult(P_, P_, mask_));
  PetscCall(VecPointwiseMult(vel_, P_, invMass_));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::forces(const ParticleView<3> &p, const StepClock &c) {
  PetscCall(PetscLogStagePush(stages_.forces));
  // f = f_int + f_ext; the external part alone (fext_) for the step's work.
  PetscScalar *f = nullptr;
  PetscCall(VecZeroEntries(sumW_));
  PetscCall(VecGetArray(sumW_, &f));
  physics::internalForce<3>(st_, p.n, p.V, p.s, f);
  if (external_) {
    PetscScalar *fe = nullptr;
    PetscCall(VecZeroEntries(extW_));
    PetscCall(VecGetArray(extW_, &fe));
    externalForces(p, c.t, fe);
    for (PetscInt i = 0; i < 3 * grid_.nSlots; ++i)
      f[i] += fe[i];
    PetscCall(VecRestoreArray(extW_, &fe));
    PetscCall(VecZeroEntries(fext_));
    PetscCall(grid_.addFromWindow(extW_, fext_));
    PetscCall(VecDot(fext_, vel_, &powerExt0_));
  }
  PetscCall(VecRestoreArray(sumW_, &f));
  PetscCall(VecZeroEntries(f_));
  PetscCall(grid_.addFromWindow(sumW_, f_));
  if (sc_.damping > 0) {
    PetscScalar pv = 0;
    PetscCall(VecDot(P_, vel_, &pv));
    powerDamp0_ = sc_.damping * pv;
  }
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

namespace {

/// f(slot, S) for every node of particle k's stencil, S the node's shape function integrated
/// over the particle's face normal to axis a at coordinate `at`, per unit face area: the tent
/// across the face taken at the face (Eq. 14) times the 1D weights along the face.
template <class Fn>
void forEachFaceWeight(const Grid<3> &g, const Stencils<3> &st, PetscInt k, int a, double at,
                       Fn &&f) {
  auto tentAt = [&](PetscInt slot) {
    const PetscInt nd = g.slotNode[slot];
    return shape::tent(at - g.coordinates(a)[nd], g.zone[6 * nd + 2 * a],
                       g.zone[6 * nd + 2 * a + 1]);
  };
  if (!st.isBlock(k)) {
    for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
      double w = tentAt(st.node[e]);
      for (int b = 0; b < 3; ++b)
        if (b != a) w *= st.w[b][e];
      f(st.node[e], w);
    }
    return;
  }
  const Block<3> &b = st.block(k);
  int nn[3];
  for (int d = 0; d < 3; ++d)
    nn[d] = b.g[d][2] > 0.0 ? 3 : 2;
  for (int q = 0; q < nn[2]; ++q)
    for (int j = 0; j < nn[1]; ++j)
      for (int i = 0; i < nn[0]; ++i) {
        const PetscInt slot = b.base + i + j * b.stride[0] + q * b.stride[1];
        const int idx[3] = {i, j, q};
        double w = tentAt(slot);
        for (int d = 0; d < 3; ++d)
          if (d != a) w *= b.w[d][idx[d]];
        f(slot, w);
      }
}

} // namespace

void Solver3::externalForces(const ParticleView<3> &p, double t, double *fe) {
  const bool gravity = sc_.gravity != Coords<3>{} || sc_.mms != Mms::None;
  std::unique_ptr<mms::Skb1d> ex;
  if (sc_.mms == Mms::AxialWave) ex = std::make_unique<mms::Skb1d>(sc_.mmsAmplitude, sc_.material);
  std::vector<double> factor(sc_.tractions.size()), ubar(3 * sc_.dbcs.size());
  for (size_t q = 0; q < factor.size(); ++q)
    factor[q] = sc_.tractions[q].ramp.at(t);
  for (size_t q = 0; q < sc_.dbcs.size(); ++q)
    for (int c = 0; c < 3; ++c)
      ubar[3 * q + c] = sc_.dbcs[q].u[c].valueOr0(t);
  reactionsLocal_.assign(3 * sc_.dbcs.size(), 0.0);
  if (!gravity && !p.trac) return;
  for (PetscInt k = 0; k < p.n; ++k) {
    if (gravity) { // Eq. 8: f_i = sum_p m_p b S_ip (b with the manufactured solution's force)
      double fb[3];
      for (int c = 0; c < 3; ++c)
        fb[c] = p.m[k] * sc_.gravity[c];
      if (ex) fb[0] += p.m[k] * ex->bodyForce(p.X0[3 * k], t);
      st_.forEach(k, [&](PetscInt nd, double w, const Vector<3> &) {
        for (int c = 0; c < 3; ++c)
          fe[3 * nd + c] += w * fb[c];
      });
    }
    if (!p.trac) continue;
    for (int a = 0; a < 3; ++a) {
      const int b1 = (a + 1) % 3, b2 = (a + 2) % 3;
      // Tractions (Eq. 8): a dead load on the particle's initial face area (with a disk, the
      // part of it inside the circle).
      if (const PetscInt q = p.trac[3 * k + a]; q >= 0) {
        const Traction<3> &tr = sc_.tractions[q];
        const int c1 = std::min(b1, b2), c2 = std::max(b1, b2);
        const double *X = p.X0 + 3 * k, *l0 = p.l0 + 3 * k;
        const double area =
            tr.loadedArea(X[c1] - l0[c1], X[c1] + l0[c1], X[c2] - l0[c2], X[c2] + l0[c2]);
        const double at = p.x[3 * k + a] + tr.normal() * p.l[3 * k + a];
        double force[3];
        for (int c = 0; c < 3; ++c)
          force[c] = tr.value[c] * factor[q] * area;
        forEachFaceWeight(grid_, st_, k, a, at, [&](PetscInt nd, double w) {
          for (int c = 0; c < 3; ++c)
            fe[3 * nd + c] += w * force[c];
        });
      }
      // Penalty (Eq. 9) per constrained component: sigma_ca n - alpha (u_c - u_bar_c) on the
      // face's current area, u the face's displacement u_p + (F - I) n l0 (exact for a uniformly
      // strained particle).
      if (const PetscInt q = p.dbc[3 * k + a]; q >= 0) {
        const DisplacementBC<3> &d = sc_.dbcs[q];
        const double n = d.normal(), area = 4.0 * p.l[3 * k + b1] * p.l[3 * k + b2];
        const double at = p.x[3 * k + a] + n * p.l[3 * k + a];
        const auto F = tensorAt<3>(p.F, k), sg = tensorAt<3>(p.s, k);
        const double alpha = alpha_ * d.penaltyScale;
        double force[3] = {0, 0, 0};
        for (int c = 0; c < 3; ++c) {
          if (!d.fix[c]) continue;
          const double u = p.x[3 * k + c] - p.X0[3 * k + c] +
                           (F(c, a) - (c == a ? 1.0 : 0.0)) * n * p.l0[3 * k + a];
          const double sca = sc_.penaltyTraction ? sg(c, a) : 0.0;
          force[c] = (sca * n - alpha * (u - ubar[3 * q + c])) * area;
          reactionsLocal_[3 * q + c] += force[c];
        }
        forEachFaceWeight(grid_, st_, k, a, at, [&](PetscInt nd, double w) {
          for (int c = 0; c < 3; ++c)
            fe[3 * nd + c] += w * force[c];
        });
      }
    }
  }
}

PetscErrorCode Solver3::gridUpdate() {
  PetscCall(PetscLogStagePush(stages_.grid));
  PetscCall(TSStep(ts_));
  PetscCall(VecPointwiseMult(vel_, P_, invMass_));
  PetscCall(grid_.toWindow(vel_, velW_));
  if (sc_.transfer == Transfer::Flip) { // APIC's G2P reads the velocity only
    PetscCall(VecPointwiseMult(acc_, rhs_, invMass_));
    PetscCall(grid_.toWindow(acc_, accW_));
  }
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::gridToParticles(ParticleView<3> &p, const StepClock &c) {
  // G2P; with MUSL each particle's new momentum goes back to the grid with the same stencil in
  // the same pass, and that re-projected velocity drives the stress update.
  PetscCall(PetscLogStagePush(stages_.g2p));
  const bool musl = sc_.update == Update::MUSL;
  const PetscScalar *vg = nullptr, *ag = nullptr;
  PetscScalar *mom = nullptr;
  PetscCall(VecGetArrayRead(velW_, &vg));
  PetscCall(VecGetArrayRead(accW_, &ag));
  if (musl) {
    PetscCall(VecZeroEntries(sumW_));
    PetscCall(VecGetArray(sumW_, &mom));
  }
  const double *xs = slotX_.data();
  if (sc_.transfer == Transfer::Apic && musl)
    transfer::gridToParticlesAffineProjected<3>(st_, p.n, vg, p.x, xs, c.dt, p.m, p.v, p.B, p.x,
                                                mom);
  else if (sc_.transfer == Transfer::Apic)
    transfer::gridToParticlesAffine<3>(st_, p.n, vg, p.x, xs, c.dt, p.v, p.B, p.x);
  else if (musl)
    transfer::gridToParticlesProjected<3>(st_, p.n, vg, ag, c.dt, sc_.flip, p.m, p.v, p.x, mom);
  else
    transfer::gridToParticles<3>(st_, p.n, vg, ag, c.dt, sc_.flip, p.v, p.x);
  if (musl) PetscCall(VecRestoreArray(sumW_, &mom));
  PetscCall(VecRestoreArrayRead(accW_, &ag));
  PetscCall(VecRestoreArrayRead(velW_, &vg));
  if (musl) {
    PetscCall(VecZeroEntries(vel_));
    PetscCall(grid_.addFromWindow(sumW_, vel_));
    PetscCall(VecPointwiseMult(vel_, vel_, invMass_));
    PetscCall(grid_.toWindow(vel_, velW_));
  }
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::stress(ParticleView<3> &p, double dt) {
  // L from the scheme's grid velocity, then F <- (I + dt L) F, V = det(F) V0, the stress by the
  // material model and the half-sizes by the tracking mode.
  PetscCall(PetscLogStagePush(stages_.stress));
  const PetscScalar *vg = nullptr;
  PetscCall(VecGetArrayRead(velW_, &vg));
  for (PetscInt k = 0; k < p.n; ++k) {
    const Material &mat = sc_.materialOf(p.id[k]);
    const Tensor<3> L = transfer::velocityGradientAt<3>(st_, k, vg);
    auto F = tensorAt<3>(p.F, k);
    F += dt * product<3>(L, F);
    p.V[k] = determinant3(F) * p.V0[k];
    if (mat.model == MaterialModel::Linear)
      material::jaumannUpdate(mat, L, dt, tensorAt<3>(p.s, k));
    else
      material::neoHookeanStress(mat, Tensor<3>(F), tensorAt<3>(p.s, k));
    if (sc_.tracking == Tracking::Stretch)
      for (int a = 0; a < 3; ++a)
        p.l[3 * k + a] = F.col(a).norm() * p.l0[3 * k + a];
  }
  PetscCall(VecRestoreArrayRead(velW_, &vg));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::checks(const ParticleView<3> &p, PetscInt step, double t) {
  // As Solver::checks in 2D: a particle that is not finite, left the grid, or is inverted or
  // larger than a level-0 cell stops the run on every rank (the first such particle of each rank
  // is named); one reduction also counts the particles leaving their rank's cells (the next
  // step's migration) and agrees on SIGINT / SIGTERM.
  const double *d = sc_.domain.data(), h0 = grid_.h0();
  double box[6] = {-INFINITY, -INFINITY, -INFINITY, INFINITY, INFINITY, INFINITY};
  if (size_ > 1) grid_.ownedBox(rank_, box);
  PetscInt bad = -1;
  PetscInt64 leaving = 0;
  for (PetscInt k = 0; k < p.n; ++k) {
    const double *x = p.x + 3 * k, *l = p.l + 3 * k;
    bool mine = true, ok = p.V[k] > 0 && std::isfinite(p.V[k]) && tensorAt<3>(p.s, k).allFinite();
    for (int a = 0; a < 3; ++a) {
      mine = mine && x[a] >= box[a] && x[a] < box[3 + a];
      // NaN fails every comparison: written so that it lands in the bad branch.
      ok = ok && std::isfinite(x[a] + p.v[3 * k + a]) && x[a] - l[a] >= d[a] &&
           x[a] + l[a] <= d[3 + a] && l[a] > 0 && l[a] <= h0;
    }
    leaving += !mine;
    if (!ok && bad < 0) bad = k;
  }
  if (bad >= 0) {
    const PetscInt k = bad;
    const double *x = p.x + 3 * k, *l = p.l + 3 * k;
    bool finite = tensorAt<3>(p.s, k).allFinite(), inside = true, in = true;
    for (int a = 0; a < 3; ++a) {
      finite = finite && std::isfinite(x[a]);
      inside = inside && x[a] - l[a] >= d[a] && x[a] + l[a] <= d[3 + a];
      in = in && x[a] >= d[a] && x[a] <= d[3 + a];
    }
    const std::string why =
        !finite ? "its position or stress is not finite: the run went unstable (reduce -ts_dt)"
        : !(p.V[k] > 0)
            ? "its volume " + formatNumber(p.V[k]) +
                  " m^3 is not positive: the particle is inverted (det F <= 0): the run went "
                  "unstable (reduce -ts_dt)"
        : !inside
            ? "it left the grid domain (enlarge -gimp_domain or -gimp_pad)"
            : "its half-size (" + formatNumber(l[0]) + ", " + formatNumber(l[1]) + ", " +
                  formatNumber(l[2]) +
                  ") is not in (0, h0]: the particle is inverted or stretched beyond one level-0 "
                  "cell";
    const std::string level = in && finite ? std::to_string(grid_.leafLevelAt(x)) : "none";
    char head[256];
    std::snprintf(head, sizeof(head),
                  "step %lld t %.9g s: particle %lld at (%.9g, %.9g, %.9g) on level %s: ",
                  static_cast<long long>(step), t, static_cast<long long>(p.id[k]), x[0], x[1],
                  x[2], level.c_str());
    localFailure_ = head + why;
  } else if (!localFailure_.empty()) {
    localFailure_ = "step " + std::to_string(step) + ": " + localFailure_;
  }
  if (!localFailure_.empty())
    PetscCall(
        PetscSynchronizedFPrintf(comm_, PETSC_STDERR, "gimp: error: %s\n", localFailure_.c_str()));
  const int sig = interruptSignal();
  const PetscInt64 mine[4] = {localFailure_.empty() ? 0 : 1, sig == SIGINT ? 1 : 0,
                              sig == SIGTERM ? 1 : 0, leaving};
  PetscInt64 any[4] = {0, 0, 0, 0};
  PetscCallMPI(MPI_Allreduce(mine, any, 4, MPI_INT64_T, MPI_SUM, comm_));
  interrupt_ = any[2] ? SIGTERM : any[1] ? SIGINT : 0;
  leaving_ = any[3];
  if (any[0] == 0) return PETSC_SUCCESS;
  failed_ = true;
  PetscCall(PetscSynchronizedFlush(comm_, PETSC_STDERR));
  // The lowest failing rank's line goes into summary.json.
  PetscMPIInt first = size_, me = localFailure_.empty() ? size_ : rank_;
  PetscCallMPI(MPI_Allreduce(&me, &first, 1, MPI_INT, MPI_MIN, comm_));
  int len = static_cast<int>(localFailure_.size());
  PetscCallMPI(MPI_Bcast(&len, 1, MPI_INT, first, comm_));
  failure_ = localFailure_;
  failure_.resize(static_cast<size_t>(len));
  PetscCallMPI(MPI_Bcast(failure_.data(), len, MPI_CHAR, first, comm_));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::energies(Energies3 &e) {
  ParticleView<3> p;
  PetscCall(p.get(sw_));
  double s[6] = {0, 0, 0, 0, 0, 0};
  for (PetscInt k = 0; k < p.n; ++k) {
    const Material &mat = sc_.materialOf(p.id[k]);
    s[5] += p.m[k];
    double v2 = 0;
    for (int a = 0; a < 3; ++a) {
      v2 += p.v[3 * k + a] * p.v[3 * k + a];
      s[2 + a] += p.m[k] * p.v[3 * k + a];
    }
    s[0] += 0.5 * p.m[k] * v2;
    s[1] += material::strainEnergy(mat, Tensor<3>(tensorAt<3>(p.s, k)),
                                   Tensor<3>(tensorAt<3>(p.F, k)), p.V0[k], p.V[k]);
  }
  PetscCall(p.restore(sw_));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, s, 6, MPI_DOUBLE, MPI_SUM, comm_));
  e.mass = s[5];
  e.kinetic = s[0];
  e.strain = s[1];
  for (int a = 0; a < 3; ++a)
    e.momentum[a] = s[2 + a];
  e.externalWork = workExt_;
  e.damping = workDamp_;
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::probes(std::vector<ProbeState3> &out) {
  out.assign(probeIds_.size(), ProbeState3{});
  if (probeIds_.empty()) return PETSC_SUCCESS;
  ParticleView<3> p;
  PetscCall(p.get(sw_));
  std::vector<double> buf(9 * probeIds_.size(), 0.0);
  static const int comp[6][2] = {{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};
  for (PetscInt k = 0; k < p.n; ++k)
    for (size_t q = 0; q < probeIds_.size(); ++q) {
      if (p.id[k] != probeIds_[q]) continue;
      for (int a = 0; a < 3; ++a)
        buf[9 * q + a] = p.x[3 * k + a] - p.X0[3 * k + a];
      for (int c = 0; c < 6; ++c)
        buf[9 * q + 3 + c] = p.s[9 * k + 3 * comp[c][0] + comp[c][1]];
    }
  PetscCall(p.restore(sw_));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, buf.data(), static_cast<int>(buf.size()), MPI_DOUBLE,
                             MPI_SUM, comm_));
  for (size_t q = 0; q < probeIds_.size(); ++q) {
    std::copy(&buf[9 * q], &buf[9 * q + 3], out[q].u);
    std::copy(&buf[9 * q + 3], &buf[9 * q + 9], out[q].s);
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::mmsErrors(double t, double &linf, double &rms) {
  // The displacement error against the manufactured solution: largest and volume-weighted RMS
  // over the particles (as mmsErrors in 2D, with the y and z displacements exactly 0).
  linf = rms = 0;
  if (sc_.mms == Mms::None) return PETSC_SUCCESS;
  const mms::Skb1d ex(sc_.mmsAmplitude, sc_.material);
  ParticleView<3> p;
  PetscCall(p.get(sw_));
  double loc[3] = {0, 0, 0}, glob[3];
  for (PetscInt k = 0; k < p.n; ++k) {
    const double X = p.X0[3 * k];
    double e2 = 0;
    for (int a = 0; a < 3; ++a) {
      const double e = p.x[3 * k + a] - p.X0[3 * k + a] - (a == 0 ? ex.u(X, t) : 0.0);
      e2 += e * e;
    }
    loc[0] = std::max(loc[0], std::sqrt(e2));
    loc[1] += e2 * p.V0[k];
    loc[2] += p.V0[k];
  }
  PetscCall(p.restore(sw_));
  PetscCallMPI(MPI_Allreduce(&loc[0], &glob[0], 1, MPI_DOUBLE, MPI_MAX, comm_));
  PetscCallMPI(MPI_Allreduce(&loc[1], &glob[1], 2, MPI_DOUBLE, MPI_SUM, comm_));
  linf = glob[0];
  rms = std::sqrt(glob[1] / glob[2]);
  mmsMax_[0] = std::max(mmsMax_[0], linf);
  mmsMax_[1] = std::max(mmsMax_[1], rms);
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::reportState(Energies3 &e, std::vector<ProbeState3> &pr,
                                    std::vector<double> &rf) {
  PetscCall(energies(e));
  PetscCall(probes(pr));
  return reactions(rf);
}

PetscErrorCode Solver3::reactions(std::vector<double> &force) {
  force.assign(3 * sc_.dbcs.size(), 0.0);
  if (force.empty()) return PETSC_SUCCESS;
  if (reactionsLocal_.size() == force.size()) force = reactionsLocal_;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, force.data(), static_cast<int>(force.size()), MPI_DOUBLE,
                             MPI_SUM, comm_));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::report(PetscInt step, double t, bool last) {
  PetscCall(PetscLogStagePush(stages_.output));
  if (step % sc_.historyInterval == 0 || last) PetscCall(writeHistory(step, t));
  if (failed_) { // the energy balance rose: the row shows it, the unstable state is not written
    PetscCall(PetscLogStagePop());
    return PETSC_SUCCESS;
  }
  if ((sc_.outputInterval > 0 && step % sc_.outputInterval == 0) || last)
    PetscCall(writeFields(step, t));
  PetscCall(TSMonitor(ts_, step, t, P_));
  if (sc_.monitorInterval > 0 && step % sc_.monitorInterval == 0) {
    Energies3 e;
    PetscCall(energies(e));
    PetscCall(PetscPrintf(comm_,
                          "gimp: step %" PetscInt_FMT " t %.6e kinetic %.6e strain %.6e "
                          "momentum %.3e %.3e %.3e\n",
                          step, t, e.kinetic, e.strain, e.momentum[0], e.momentum[1],
                          e.momentum[2]));
  }
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::run() {
  if (sc_.help) return PETSC_SUCCESS;
  PetscInt maxSteps = 0, steps = 0;
  PetscReal maxTime = 0, t = 0;
  PetscCall(TSGetMaxSteps(ts_, &maxSteps));
  PetscCall(TSGetMaxTime(ts_, &maxTime));
  PetscCall(writeHistory(0, 0.0));
  PetscCall(writeFields(0, 0.0));
  PetscCall(TSMonitor(ts_, 0, 0.0, P_));
  while (steps < maxSteps && t < maxTime && !failed_ && !interrupt_) {
    PetscCall(step());
    PetscCall(TSGetStepNumber(ts_, &steps));
    PetscCall(TSGetTime(ts_, &t));
    const bool last = steps >= maxSteps || t >= maxTime || interrupt_;
    // An unstable step's state is not written: the outputs keep what the run had written.
    if (!failed_) PetscCall(report(steps, t, last));
  }
  if (steps >= maxSteps || t >= maxTime) interrupt_ = 0; // the run was complete anyway
  PetscCall(TSViewFromOptions(ts_, nullptr, "-ts_view"));
  if (!sc_.particleDump.empty() && !failed_) PetscCall(writeParticleDump());
  PetscCall(writeSummary(failed_      ? "unstable"
                         : interrupt_ ? "interrupted"
                                      : "completed",
                         steps, t));
  return PETSC_SUCCESS;
}

} // namespace gimp::three
