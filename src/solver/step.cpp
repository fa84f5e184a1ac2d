// One time step as named phases. Each phase is a call into the room of its concept: grid
// (stencils), transfer (P2G, G2P), physics (forces, deformation, tracking), TS (grid update),
// diagnostics and io (report). Values one phase hands to a later one are passed explicitly.
#include "gimp/cracks/fields.hpp"
#include "gimp/physics/deformation.hpp"
#include "gimp/physics/internal_force.hpp"
#include "gimp/solver/solver.hpp"
#include "gimp/transfer/lanes2.hpp"
#include "gimp/transfer/transfer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

namespace gimp {

PetscErrorCode Solver::clockOf(TS ts, const Scene<2> &sc, StepClock &c) {
  return readStepClock(ts, sc.halfStepStart, c);
}

PetscErrorCode Solver::step() {
  if (sc_.multirate) return coarseStep(); // R fine steps, a step per level (multirate.cpp)
  StepClock c;
  PetscCall(clockOf(ts_, sc_, c));
  ParticleView<2> p;
  PetscCall(PetscLogStagePush(stages_.p2g));
  PetscCall(migrate());
  if (sc_.sortInterval > 0 && c.step % sc_.sortInterval == 0) PetscCall(sortParticles());
  PetscCall(p.get(sw_));
  // Where each particle's weights are centred (the corner box with corner tracking), for the
  // stencils and the crack faces of this step.
  const double *centres = stencilCentres(p);
  PetscCall(buildStencils(p, centres));
  centres = affineCentres(p, centres);
  PetscCall(particlesToGrid(p, centres));
  PetscCall(PetscLogStagePop());
  if (!sc_.cracks.empty()) {
    PetscCall(crackFaces(p));
    PetscCall(contactOnMomentum(c));
  }
  if (scheme_.stressBeforeGridUpdate) PetscCall(stress(st_, p, nodal_.velW, c.dt));
  StartPower power;
  PetscCall(forces(p, c, power));
  PetscCall(gridUpdate());
  if (!sc_.cracks.empty())
    PetscCall(crackContact(c, nodal_.velW, nodal_.vel, nodal_.accW, nodal_.acc));
  PetscCall(gridToParticles(p, c, centres));
  PetscCall(work(c, power));
  if (!scheme_.stressBeforeGridUpdate) PetscCall(stress(st_, p, nodal_.velW, c.dt));
  PetscCall(checks(p, c.step + 1, c.t + c.dt));
  PetscCall(p.restore(sw_));
  PetscCall(report(c.step + 1, c.t + c.dt));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::migrate() {
  // Particles go to the rank owning their level-0 cell. The previous step's check counted the
  // particles outside their rank's cells over all ranks (leaving_): none, and nothing is done;
  // unknown (-1: the first step, after a restart), and this counts them itself.
  if (size_ == 1 || leaving_ == 0) return PETSC_SUCCESS;
  ParticleView<2> p;
  PetscCall(p.get(sw_));
  PetscInt64 moved = 0, any = leaving_;
  double box[2 * kDim];
  grid_.ownedBox(rank_, box);
  for (PetscInt k = 0; k < p.n; ++k) {
    const double *x = p.x + kDim * k;
    bool stays = true;
    for (int a = 0; a < kDim; ++a)
      stays = stays && x[a] >= box[a] && x[a] < box[kDim + a];
    if (stays) continue;
    const PetscMPIInt r = grid_.ownerOf(x);
    p.rank[k] = r;
    if (r != rank_) ++moved;
  }
  PetscCall(p.restore(sw_));
  if (leaving_ < 0) PetscCallMPI(MPI_Allreduce(&moved, &any, 1, MPI_INT64_T, MPI_SUM, comm_));
  if (any) PetscCall(DMSwarmMigrate(sw_, PETSC_TRUE));
  measures_.migrated += any;
  leaving_ = -1;
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::sortParticles(std::vector<int> *cls, bool byCell) {
  // Each rank's particles in the order of their level-0 cell (row by row), by id within a cell:
  // P2G and G2P then walk the nodal arrays in order, and the order depends on neither the
  // seeding nor the migrations. Every -gimp_sort_interval steps; nothing is allocated when the
  // particles are in order already. With rate classes (cls, permuted along) the class comes
  // first; without byCell only the classes are made contiguous (a stable partition).
  ParticleView<2> p;
  PetscCall(p.get(sw_));
  const Level<2> &L = grid_.levels[0];
  using Key = std::array<PetscInt64, 3>;
  auto keyOf = [&](PetscInt k) {
    const PetscInt64 c = cls ? (*cls)[k] : 0;
    if (!byCell) return Key{c, 0, k};
    PetscInt64 cell = 0; // the level-0 cell, numbered x fastest
    for (int a = kDim - 1; a >= 0; --a)
      cell = cell * static_cast<PetscInt64>(L.n[a]) +
             static_cast<PetscInt64>(std::floor((p.x[kDim * k + a] - L.box[a]) * L.ih));
    return Key{c, cell, p.id[k]};
  };
  bool sorted = true;
  for (PetscInt k = 1; k < p.n && sorted; ++k)
    sorted = keyOf(k - 1) < keyOf(k);
  if (sorted) {
    PetscCall(p.restore(sw_));
    return PETSC_SUCCESS;
  }
  st_.release(); // the last step's stencils: room for the keys and the permutation buffer
  std::vector<std::pair<Key, PetscInt>> key(p.n);
  for (PetscInt k = 0; k < p.n; ++k)
    key[k] = {keyOf(k), k};
  PetscCall(p.restore(sw_));
  std::sort(key.begin(), key.end());
  std::vector<PetscInt> order(p.n);
  for (PetscInt k = 0; k < p.n; ++k)
    order[k] = key[k].second;
  key = {};
  PetscCall(permuteSwarm<2>(sw_, order));
  if (cls) {
    std::vector<int> was = *cls;
    for (PetscInt k = 0; k < p.n; ++k)
      (*cls)[k] = was[order[k]];
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::buildStencils(const ParticleView<2> &p, const double *centres) {
  // The checks after every step keep each particle within one level-0 cell, so this cannot
  // fail; if it does, the failure joins those checks (no extra collective in the step).
  if (usesCpdi(sc_.tracking)) {
    const char *why =
        grid_.buildCpdiStencils(p.n, tracking::cpdiCorners(sc_, p, cpdiCorners_), st_);
    if (why) localFailure_ = why;
  } else {
    // Blocks for every particle that one level's regular nodes alone reach, unless cracks
    // re-address entries (assignFields).
    if (!grid_.buildStencils(p.n, centres, p.l, st_, sc_.cracks.empty(), lanes_))
      localFailure_ = "a particle is larger than a level-0 cell (its half-size exceeds -gimp_h)";
  }
  cracks::assignFields(grid_, sc_.cracks, p.n, centres, st_);
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::forces(const ParticleView<2> &p, const StepClock &c, StartPower &power) {
  // f = f_int + f_ext (Eq. 8, 9) into nodal_.f; the RHS adds damping and masks it.
  PetscCall(PetscLogStagePush(stages_.forces));
  PetscScalar *f = nullptr;
  PetscCall(VecZeroEntries(nodal_.sumW));
  PetscCall(VecGetArray(nodal_.sumW, &f));
  if (lanes_)
    transfer::lanes2::internalForce(st_, p.n, p.V, p.s, f);
  else
    physics::internalForce<kDim>(st_, p.n, p.V, p.s, f);
  if (boundary_.active()) {
    PetscScalar *fe = nullptr;
    PetscCall(VecZeroEntries(nodal_.extW));
    PetscCall(VecGetArray(nodal_.extW, &fe));
    boundary_.externalForces(sc_, grid_, st_, p, c.t, fe);
    for (PetscInt i = 0; i < 2 * grid_.nSlots; ++i)
      f[i] += fe[i];
    PetscCall(VecRestoreArray(nodal_.extW, &fe));
  }
  PetscCall(VecRestoreArray(nodal_.sumW, &f));
  PetscCall(globalForces(power));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::globalForces(StartPower &power, bool external) {
  // The window's forces (nodal_.sumW, the external part in nodal_.extW) summed over the ranks
  // into nodal_.f and nodal_.fext; the power of the damping and external forces at the start.
  // Without `external` (the multi-rate step keeps each class's own) no nodal_.fext.
  external = external && boundary_.active();
  if (external) {
    PetscCall(VecZeroEntries(nodal_.fext));
    PetscCall(grid_.addFromWindow(nodal_.extW, nodal_.fext));
  }
  PetscCall(VecZeroEntries(nodal_.f));
  PetscCall(grid_.addFromWindow(nodal_.sumW, nodal_.f));
  if (sc_.damping > 0) {
    PetscScalar pv = 0;
    PetscCall(VecDot(nodal_.P, nodal_.vel, &pv));
    power.damping = sc_.damping * pv;
  }
  if (external) PetscCall(VecDot(nodal_.fext, nodal_.vel, &power.external));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::gridUpdate(bool accOnWindow) {
  // TS euler: p <- p + dt * rhs (Solver::rhs); then the nodal velocity and acceleration.
  PetscCall(PetscLogStagePush(stages_.grid));
  PetscCall(TSStep(ts_));
  PetscCall(VecPointwiseMult(nodal_.vel, nodal_.P, nodal_.invMass));
  PetscCall(VecPointwiseMult(nodal_.acc, nodal_.rhs, nodal_.invMass));
  PetscCall(grid_.toWindow(nodal_.vel, nodal_.velW));
  if (accOnWindow) PetscCall(grid_.toWindow(nodal_.acc, nodal_.accW));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::crackFaces(const ParticleView<2> &p) {
  // Each field's mass-weighted displacement along its contact normal at every cracked node:
  // summed over the ranks that hold the node, back to every window. With them the summed mass
  // and the mask on the window, which the step's contact passes read. With -gimp_multirate the
  // sum runs over the rate classes, each with its stencils from its last start.
  PetscCall(grid_.toWindow(nodal_.mass, nodal_.massW));
  PetscCall(grid_.toWindow(nodal_.mask, nodal_.maskW));
  if (!sc_.multirate) {
    PetscScalar *f = nullptr;
    PetscCall(VecGetArray(nodal_.faceW, &f));
    contact_.faces(grid_, st_, p.n, p.x, p.X0, p.m, f);
    PetscCall(VecRestoreArray(nodal_.faceW, &f));
  } else { // the classes' faces from their starts (Solver::startClasses)
    contact_.newStep();
    PetscCall(VecZeroEntries(nodal_.faceW));
    for (int k = 0; k < rate_.n; ++k)
      if (rate_.size[k] > 0) PetscCall(VecAXPY(nodal_.faceW, 1.0, rate_.faces[k]));
  }
  PetscCall(VecSet(nodal_.face, 0.0));
  PetscCall(grid_.fromWindow(nodal_.faceW, nodal_.face, ADD_VALUES));
  PetscCall(grid_.toWindow(nodal_.face, nodal_.faceW));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::contactOnMomentum(const StepClock &c) {
  // Contact on the projected momentum (before the forces): the fields' velocities and P, so the
  // step starts from fields that do not approach each other.
  PetscCall(grid_.toWindow(nodal_.vel, nodal_.velW));
  PetscCall(VecCopy(nodal_.velW, nodal_.accW));
  PetscCall(crackContact(c, nodal_.velW, nodal_.vel, nullptr, nullptr));
  PetscCall(grid_.toWindow(nodal_.P, nodal_.sumW));
  const PetscScalar *v = nullptr, *m = nullptr;
  PetscScalar *old = nullptr, *P = nullptr;
  PetscCall(VecGetArrayRead(nodal_.velW, &v));
  PetscCall(VecGetArrayRead(nodal_.massW, &m));
  PetscCall(VecGetArray(nodal_.accW, &old));
  PetscCall(VecGetArray(nodal_.sumW, &P));
  for (PetscInt s = 0; s < grid_.nSlots; ++s)
    for (int d = 0; d < 2; ++d)
      P[2 * s + d] += m[2 * s] * (v[2 * s + d] - old[2 * s + d]);
  PetscCall(VecRestoreArray(nodal_.sumW, &P));
  PetscCall(VecRestoreArray(nodal_.accW, &old));
  PetscCall(VecRestoreArrayRead(nodal_.massW, &m));
  PetscCall(VecRestoreArrayRead(nodal_.velW, &v));
  PetscCall(grid_.fromWindow(nodal_.sumW, nodal_.P, INSERT_VALUES));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::crackContact(const StepClock &c, Vec velW, Vec vel, Vec accW, Vec acc) {
  // Frictionless contact of the two fields at cracked nodes, on the window (every rank that
  // holds a node computes the same result), then back to the global vectors.
  PetscCall(PetscLogStagePush(stages_.grid));
  const PetscScalar *m = nullptr, *mask = nullptr, *face = nullptr;
  PetscScalar *v = nullptr, *a = nullptr;
  PetscCall(VecGetArrayRead(nodal_.massW, &m));
  PetscCall(VecGetArrayRead(nodal_.maskW, &mask));
  PetscCall(VecGetArrayRead(nodal_.faceW, &face));
  PetscCall(VecGetArray(velW, &v));
  if (accW) PetscCall(VecGetArray(accW, &a));
  const PetscInt touching =
      contact_.apply(grid_, sc_.massCutoff * meanParticleMass_, c.dt, m, face, v, a);
  for (PetscInt i = 0; i < 2 * grid_.nSlots; ++i) { // constrained dofs stay fixed
    v[i] *= mask[i];
    if (a) a[i] *= mask[i];
  }
  if (accW) PetscCall(VecRestoreArray(accW, &a));
  PetscCall(VecRestoreArray(velW, &v));
  PetscCall(VecRestoreArrayRead(nodal_.faceW, &face));
  PetscCall(VecRestoreArrayRead(nodal_.maskW, &mask));
  PetscCall(VecRestoreArrayRead(nodal_.massW, &m));
  PetscCall(PetscInfo(nullptr,
                      "step %" PetscInt_FMT ": %" PetscInt_FMT " cracked nodes in contact\n",
                      c.step, touching));
  PetscCall(grid_.fromWindow(velW, vel, INSERT_VALUES));
  if (accW) PetscCall(grid_.fromWindow(accW, acc, INSERT_VALUES));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::work(const StepClock &c, const StartPower &power, bool external) {
  // Work of the external and damping forces over the step: force times the mean of the grid
  // velocities at its start and end. With MUSL the end velocity is the re-projection of the
  // particles' velocities, so nodal force residuals that move no particle do no work.
  if (boundary_.active() && external) {
    PetscScalar fv = 0;
    PetscCall(VecDot(nodal_.fext, nodal_.vel, &fv));
    work_.external += 0.5 * c.kick * c.dt * (power.external + fv);
  }
  if (sc_.damping > 0) {
    // The damping force is -d p^n, and p^n = p^n+1 - dt F.
    PetscScalar pv = 0, fv = 0;
    PetscCall(VecDot(nodal_.P, nodal_.vel, &pv));
    PetscCall(VecDot(nodal_.rhs, nodal_.vel, &fv));
    work_.damping += 0.5 * c.kick * c.dt * (power.damping + sc_.damping * (pv - c.dt * fv));
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::stress(const Stencils<kDim> &st, ParticleView<2> &p, Vec velocityWindow,
                              double dt) {
  // Velocity gradient from the scheme's velocity field, then F, volume, stress and domain.
  PetscCall(PetscLogStagePush(stages_.stress));
  // In chunks that stay in cache: the gradients of a chunk, then its particles' update.
  constexpr PetscInt kChunk = 256;
  L_.resize(kDim * kDim * static_cast<size_t>(kChunk));
  const PetscScalar *vg = nullptr;
  PetscCall(VecGetArrayRead(velocityWindow, &vg));
  for (PetscInt k0 = 0; k0 < p.n; k0 += kChunk) {
    const PetscInt k1 = std::min(p.n, k0 + kChunk);
    if (lanes_) {
      transfer::lanes2::velocityGradients(st, k0, k1, vg, L_.data());
      transfer::lanes2::updateDeformation(sc_, p, L_.data(), dt, k0, k1);
      continue;
    }
    for (PetscInt k = k0; k < k1; ++k)
      tensorAt<kDim>(L_.data(), k - k0) = transfer::velocityGradientAt<kDim>(st, k, vg);
    physics::updateDeformation(sc_, p, L_.data(), dt, k0, k1);
  }
  PetscCall(VecRestoreArrayRead(velocityWindow, &vg));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

} // namespace gimp
