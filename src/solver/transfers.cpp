// The transfer phases of the step: P2G, G2P and the re-projection after it, for the three
// particle velocity transfers of -gimp_transfer (docs/method.md, "Velocity transfers"):
//   flip  FLIP/PIC blend: v_p <- flip (v_p + dt S a) + (1 - flip) S v
//   apic  affine PIC: P2G of m_p (v_p + C_p (x_i - x_p)), G2P v_p = S v, B_p = S v (x_i - x_p)^T
//   xpic  XPIC(m): v_p <- S (v* + dt a), v* the start velocity filtered by m - 1 projections
// Particles always move by dt S v with v the updated grid velocity.
#include "gimp/physics/constraints.hpp"
#include "gimp/solver/step.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/lane_loops.hpp"
#include "gimp/transfer/lane_loops3.hpp"
#include "gimp/transfer/transfer.hpp"

#include <algorithm>

namespace gimp {

template <int D> const double *Step<D>::stencilCentres(const ParticleView<D> &p) {
  // With APIC the re-projection's affine moments are taken about the stencils' centres: where
  // those are the positions, each particle is re-projected before it moves (gridToParticles,
  // in one pass), so no copy is needed.
  return tracking::domainCentres<D>(p, centres_, s_.sc.tracking);
}

template <int D>
const double *Step<D>::affineCentres(const ParticleView<D> &p, const double *centres) {
  // cpdi2's weights integrate the quadrilateral of the corners, whose centroid drifts from the
  // material point that G2P moves; moments about the material point would read the particle's
  // velocity times that offset as a velocity gradient (and divide it by D_p, ratio^2 smaller on
  // a finer level). Corners and GIMP domains are centred where their weights are.
  if (s_.sc.transfer != Transfer::Apic || s_.sc.tracking != Tracking::Cpdi2) return centres;
  centres_.resize(D * static_cast<size_t>(p.n));
  transfer::weightCentroids<D>(s_.st, p.n, slotCoordinates(), centres_.data());
  return centres_.data();
}

template <int D> const double *Step<D>::slotCoordinates() {
  const Grid<D> &g = s_.grid;
  if (slotX_.size() != D * static_cast<size_t>(g.nSlots)) {
    slotX_.resize(D * static_cast<size_t>(g.nSlots));
    for (PetscInt s = 0; s < g.nSlots; ++s) // a crack's second slot: its node's place
      for (int a = 0; a < D; ++a)
        slotX_[D * s + a] = g.coordinates(a)[g.slotNode[s]];
  }
  return slotX_.data();
}

template <int D>
void Step<D>::projectMomentum(const Stencils<D> &st, const ParticleView<D> &p,
                              const double *centres, double *mom, double *mass) {
  namespace lanes = transfer::laneLoops; // (2D: four particles at a time; 3D: x, y, z)
  if (s_.sc.transfer != Transfer::Apic) {
    if (s_.lanes) return lanes::particlesToGrid(st, p.n, p.m, p.v, mom, mass);
    return transfer::particlesToGrid<D>(st, p.n, p.m, p.v, mom, mass);
  }
  // C_p = B_p D_p^-1 per particle from its stencil, at the step's P2G and at the re-projection.
  if (s_.lanes)
    return lanes::particlesToGridAffineB(st, p.n, p.m, p.v, p.B, centres, slotCoordinates(), mom,
                                         mass);
  transfer::particlesToGridAffineB<D>(st, p.n, p.m, p.v, p.B, centres, slotCoordinates(), mom,
                                      mass);
}

template <int D>
PetscErrorCode Step<D>::particlesToGrid(const ParticleView<D> &p, const double *centres) {
  // Mass and momentum to the nodes, masked (constraints, empty nodes); the nodal velocity.
  RunState<D> &s = s_;
  Nodal &n = s.nodal;
  PetscScalar *mom = nullptr, *mass = nullptr;
  Vec momSum = nullptr, massSum = nullptr;
  PetscCall(s.grid.startSum(n.sumW, n.P, &momSum));
  PetscCall(s.grid.startSum(n.massW, n.mass, &massSum));
  PetscCall(VecGetArray(momSum, &mom));
  PetscCall(VecGetArray(massSum, &mass));
  projectMomentum(s.st, p, centres, mom, mass);
  PetscCall(VecRestoreArray(massSum, &mass));
  PetscCall(VecRestoreArray(momSum, &mom));
  PetscCall(s.grid.endSum(n.sumW, n.P));
  PetscCall(s.grid.endSum(n.massW, n.mass));
  PetscCall(physics::massMaskMomentum(n.mass, n.bcMask, s.sc.massCutoff * s.meanParticleMass,
                                      n.mask, n.invMass, n.P, n.vel, D));
  if (s.scheme.stressBeforeGridUpdate) PetscCall(s.grid.toWindow(n.vel, n.velW));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Step<D>::xpicFilter(const ParticleView<D> &p, const StepClock &c) {
  // v^n = v^{n+1} - dt a (what TS started from, masked); v* = sum_{k=0}^{m-1} (I - Q)^k v^n with
  // Q = M^-1 S^T M_p S the lumped projection through the particles (the step's stencils): the
  // truncated series of the consistent-mass projection Q^-1 v^n.
  RunState<D> &s = s_;
  Nodal &n = s.nodal;
  PetscCall(VecWAXPY(n.term, -c.dt, n.acc, n.vel));
  PetscCall(VecCopy(n.term, n.vstar));
  xpicVp_.resize(D * static_cast<size_t>(p.n));
  for (int k = 1; k < s.sc.xpicOrder; ++k) {
    PetscCall(s.grid.toWindow(n.term, n.vstarW));
    const PetscScalar *t = nullptr;
    PetscScalar *mom = nullptr;
    PetscCall(VecGetArrayRead(n.vstarW, &t));
    transfer::interpolate<D>(s.st, p.n, t, xpicVp_.data());
    PetscCall(VecRestoreArrayRead(n.vstarW, &t));
    Vec sum = nullptr; // (n.f is free after the grid update: Q t)
    PetscCall(s.grid.startSum(n.sumW, n.f, &sum));
    PetscCall(VecGetArray(sum, &mom));
    transfer::particlesToGrid<D>(s.st, p.n, p.m, xpicVp_.data(), mom, nullptr);
    PetscCall(VecRestoreArray(sum, &mom));
    PetscCall(s.grid.endSum(n.sumW, n.f));
    PetscCall(VecPointwiseMult(n.f, n.f, n.invMass));
    PetscCall(VecAXPY(n.term, -1.0, n.f)); // (I - Q) t
    PetscCall(VecAXPY(n.vstar, 1.0, n.term));
  }
  PetscCall(s.grid.toWindow(n.vstar, n.vstarW));
  return PETSC_SUCCESS;
}

template <int D>
void Step<D>::gridToParticlesKernel(ParticleView<D> &p, const StepClock &c, const double *centres,
                                    const double *vg, const double *ag, bool fused, double *mom) {
  namespace lanes = transfer::laneLoops;
  const Scene<D> &sc = s_.sc;
  const Stencils<D> &st = s_.st;
  const double *xs = slotCoordinates();
  if (sc.transfer == Transfer::Apic) {
    if (fused)
      return s_.lanes ? lanes::gridToParticlesAffineProjected(st, p.n, vg, centres, xs, c.dt, p.m,
                                                              p.v, p.B, p.x, mom)
                      : transfer::gridToParticlesAffineProjected<D>(st, p.n, vg, centres, xs, c.dt,
                                                                    p.m, p.v, p.B, p.x, mom);
    return s_.lanes
               ? lanes::gridToParticlesAffine(st, p.n, vg, centres, xs, c.dt, p.v, p.B, p.x)
               : transfer::gridToParticlesAffine<D>(st, p.n, vg, centres, xs, c.dt, p.v, p.B, p.x);
  }
  if (s_.lanes)
    return fused
               ? lanes::gridToParticlesProjected(st, p.n, vg, ag, c.dt, sc.flip, p.m, p.v, p.x, mom)
               : lanes::gridToParticles(st, p.n, vg, ag, c.dt, sc.flip, p.v, p.x);
  if (fused)
    return transfer::gridToParticlesProjected<D>(st, p.n, vg, ag, c.dt, sc.flip, p.m, p.v, p.x,
                                                 mom);
  transfer::gridToParticles<D>(st, p.n, vg, ag, c.dt, sc.flip, p.v, p.x);
}

template <int D>
void Step<D>::gridToParticlesRated(const Stencils<D> &st, ParticleView<D> &q, const double *ug,
                                   const double *wg, double dt, double flip, double *mom) {
  namespace lanes = transfer::laneLoops;
  if (s_.sc.transfer == Transfer::Apic)
    return s_.lanes ? lanes::gridToParticlesAffineRated(st, q.n, ug, wg, slotCoordinates(), dt, q.m,
                                                        q.v, q.B, q.x, mom)
                    : transfer::gridToParticlesAffineRated<D>(st, q.n, ug, wg, slotCoordinates(),
                                                              dt, q.m, q.v, q.B, q.x, mom);
  if (s_.lanes) return lanes::gridToParticlesRated(st, q.n, ug, wg, dt, flip, q.m, q.v, q.x, mom);
  transfer::gridToParticlesRated<D>(st, q.n, ug, wg, dt, flip, q.m, q.v, q.x, mom);
}

template <int D>
PetscErrorCode Step<D>::gridToParticles(ParticleView<D> &p, const StepClock &c,
                                        const double *centres) {
  RunState<D> &s = s_;
  Nodal &n = s.nodal;
  PetscCall(PetscLogStagePush(s.stages.g2p));
  const bool xpic = s.sc.transfer == Transfer::Xpic;
  if (xpic) PetscCall(xpicFilter(p, c));
  const PetscScalar *vg = nullptr, *ag = nullptr;
  PetscCall(VecGetArrayRead(n.velW, &vg));
  PetscCall(VecGetArrayRead(n.accW, &ag));
  const bool reprojects = s.scheme.stressFromReprojection || tracksCorners(s.sc.tracking);
  // With a re-projection (FLIP/PIC and APIC) each particle's new momentum goes back to the grid
  // with the same stencil right after its G2P, in one pass over the particles.
  const bool fused = reprojects && !xpic;
  PetscScalar *mom = nullptr;
  Vec sum = nullptr; // (the re-projection's sum ends in n.acc: free once accW holds it)
  if (fused) {
    PetscCall(s.grid.startSum(n.sumW, n.acc, &sum));
    PetscCall(VecGetArray(sum, &mom));
  }
  if (xpic) {
    const PetscScalar *vs = nullptr;
    PetscCall(VecGetArrayRead(n.vstarW, &vs));
    transfer::gridToParticlesFiltered<D>(s.st, p.n, vg, ag, vs, c.dt, p.v, p.x);
    PetscCall(VecRestoreArrayRead(n.vstarW, &vs));
  } else {
    gridToParticlesKernel(p, c, centres, vg, ag, fused, mom);
  }
  if (fused) PetscCall(VecRestoreArray(sum, &mom));
  PetscCall(VecRestoreArrayRead(n.accW, &ag));
  PetscCall(VecRestoreArrayRead(n.velW, &vg));
  if (reprojects) PetscCall(reproject(p, c, centres, fused));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Step<D>::reproject(ParticleView<D> &p, const StepClock &c, const double *centres,
                                  bool projected) {
  // Re-project the updated particle momentum (acc is free now) with the step's own P2G (APIC:
  // the affine fields of the new B_p): the velocity field of MUSL's stress update, and the one
  // the corners follow. Unlike p^n+1 / m it is a weighted mean of particle velocities, so a
  // node that a particle barely touches (tiny mass, huge F / m) cannot throw a corner away.
  RunState<D> &s = s_;
  Nodal &n = s.nodal;
  if (!projected) { // (else G2P made the sums already: Step::gridToParticles)
    PetscScalar *mom = nullptr;
    Vec sum = nullptr;
    PetscCall(s.grid.startSum(n.sumW, n.acc, &sum));
    PetscCall(VecGetArray(sum, &mom));
    projectMomentum(s.st, p, centres, mom, nullptr);
    PetscCall(VecRestoreArray(sum, &mom));
  }
  PetscCall(s.grid.endSum(n.sumW, n.acc));
  PetscCall(VecPointwiseMult(n.acc, n.acc, n.invMass));
  PetscCall(s.grid.toWindow(n.acc, n.accW));
  // The re-projected fields of a cracked node may approach each other again: the same contact
  // (faces of this step), or MUSL's strain would see the faces interpenetrate.
  if (!s.sc.cracks.empty()) PetscCall(crackContact(c, n.accW, n.acc, nullptr, nullptr));
  if (s.scheme.stressFromReprojection) {
    PetscCall(VecCopy(n.acc, n.vel));
    PetscCall(VecCopy(n.accW, n.velW));
  }
  if (tracksCorners(s.sc.tracking)) {
    PetscCall(s.grid.toWindow(n.mass, n.massW)); // the summed mass on the window
    const PetscScalar *va = nullptr, *mw = nullptr;
    PetscCall(VecGetArrayRead(n.accW, &va));
    PetscCall(VecGetArrayRead(n.massW, &mw));
    // cpdi2 moves its corners with the grid's point shape functions (Sadeghirad et al. 2013).
    const double size = s.sc.tracking == Tracking::Cpdi2 ? 0.0 : s.sc.cornerSize;
    const bool ok = corners_.move(s.grid, s.sc.cracks, size, s.sc.massCutoff * s.meanParticleMass,
                                  c.dt, va, mw, s.st, p);
    PetscCall(VecRestoreArrayRead(n.massW, &mw));
    PetscCall(VecRestoreArrayRead(n.accW, &va));
    if (!ok)
      s.status.localFailure = "a tracked corner's particle is larger than a level-0 cell, or a "
                              "corner left the grid";
  }
  return PETSC_SUCCESS;
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template const double *Step<D>::stencilCentres(const ParticleView<D> &);                         \
  template const double *Step<D>::affineCentres(const ParticleView<D> &, const double *);          \
  template const double *Step<D>::slotCoordinates();                                               \
  template void Step<D>::projectMomentum(const Stencils<D> &, const ParticleView<D> &,             \
                                         const double *, double *, double *);                      \
  template PetscErrorCode Step<D>::particlesToGrid(const ParticleView<D> &, const double *);       \
  template void Step<D>::gridToParticlesRated(const Stencils<D> &, ParticleView<D> &,              \
                                              const double *, const double *, double, double,      \
                                              double *);                                           \
  template PetscErrorCode Step<D>::gridToParticles(ParticleView<D> &, const StepClock &,           \
                                                   const double *);
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
