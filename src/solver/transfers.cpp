// The transfer phases of the step: P2G, G2P and the re-projection after it, for the three
// particle velocity transfers of -gimp_transfer (docs/method.md, "Velocity transfers"):
//   flip  FLIP/PIC blend: v_p <- flip (v_p + dt S a) + (1 - flip) S v
//   apic  affine PIC: P2G of m_p (v_p + C_p (x_i - x_p)), G2P v_p = S v, B_p = S v (x_i - x_p)^T
//   xpic  XPIC(m): v_p <- S (v* + dt a), v* the start velocity filtered by m - 1 projections
// Particles always move by dt S v with v the updated grid velocity.
#include "gimp/physics/constraints.hpp"
#include "gimp/solver/solver.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/lanes2.hpp"
#include "gimp/transfer/transfer.hpp"

#include <algorithm>

namespace gimp {

const double *Solver::stencilCentres(const ParticleView<2> &p) {
  // With APIC the re-projection's affine moments are taken about the stencils' centres: where
  // those are the positions, each particle is re-projected before it moves (gridToParticles,
  // in one pass), so no copy is needed.
  return tracking::domainCentres(p, centres_, sc_.tracking);
}

const double *Solver::affineCentres(const ParticleView<2> &p, const double *centres) {
  // cpdi2's weights integrate the quadrilateral of the corners, whose centroid drifts from the
  // material point that G2P moves; moments about the material point would read the particle's
  // velocity times that offset as a velocity gradient (and divide it by D_p, ratio^2 smaller on
  // a finer level). Corners and GIMP domains are centred where their weights are.
  if (sc_.transfer != Transfer::Apic || sc_.tracking != Tracking::Cpdi2) return centres;
  centres_.resize(kDim * static_cast<size_t>(p.n));
  transfer::weightCentroids<kDim>(st_, p.n, slotCoordinates(), centres_.data());
  return centres_.data();
}

const double *Solver::slotCoordinates() {
  if (slotX_.size() != kDim * static_cast<size_t>(grid_.nSlots)) {
    slotX_.resize(kDim * static_cast<size_t>(grid_.nSlots));
    for (PetscInt s = 0; s < grid_.nSlots; ++s) { // a crack's second slot: its node's place
      const PetscInt nd = grid_.slotNode[s];
      slotX_[kDim * s] = grid_.X[nd];
      slotX_[kDim * s + 1] = grid_.Y[nd];
    }
  }
  return slotX_.data();
}

void Solver::projectMomentum(const Stencils<kDim> &st, const ParticleView<2> &p,
                             const double *centres, double *mom, double *mass) {
  if (sc_.transfer != Transfer::Apic) {
    transfer::particlesToGrid<kDim>(st, p.n, p.m, p.v, mom, mass);
    return;
  }
  // C_p = B_p D_p^-1 per particle from its stencil, at the step's P2G and at the re-projection.
  if (lanes_)
    transfer::lanes2::particlesToGridAffineB(st, p.n, p.m, p.v, p.B, centres, slotCoordinates(),
                                             mom, mass);
  else
    transfer::particlesToGridAffineB<kDim>(st, p.n, p.m, p.v, p.B, centres, slotCoordinates(), mom,
                                           mass);
}

PetscErrorCode Solver::particlesToGrid(const ParticleView<2> &p, const double *centres) {
  // Mass and momentum to the nodes, masked (constraints, empty nodes); the nodal velocity.
  PetscScalar *mom = nullptr, *mass = nullptr;
  PetscCall(VecZeroEntries(nodal_.sumW));
  PetscCall(VecZeroEntries(nodal_.massW));
  PetscCall(VecGetArray(nodal_.sumW, &mom));
  PetscCall(VecGetArray(nodal_.massW, &mass));
  projectMomentum(st_, p, centres, mom, mass);
  PetscCall(VecRestoreArray(nodal_.massW, &mass));
  PetscCall(VecRestoreArray(nodal_.sumW, &mom));
  PetscCall(VecZeroEntries(nodal_.P));
  PetscCall(grid_.addFromWindow(nodal_.sumW, nodal_.P));
  PetscCall(VecZeroEntries(nodal_.mass));
  PetscCall(grid_.addFromWindow(nodal_.massW, nodal_.mass));
  PetscCall(physics::massMask(nodal_.mass, nodal_.bcMask, sc_.massCutoff * meanParticleMass_,
                              nodal_.mask, nodal_.invMass));
  PetscCall(VecPointwiseMult(nodal_.P, nodal_.P, nodal_.mask));
  PetscCall(VecPointwiseMult(nodal_.vel, nodal_.P, nodal_.invMass));
  if (scheme_.stressBeforeGridUpdate) PetscCall(grid_.toWindow(nodal_.vel, nodal_.velW));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::xpicFilter(const ParticleView<2> &p, const StepClock &c) {
  // v^n = v^{n+1} - dt a (what TS started from, masked); v* = sum_{k=0}^{m-1} (I - Q)^k v^n with
  // Q = M^-1 S^T M_p S the lumped projection through the particles (the step's stencils): the
  // truncated series of the consistent-mass projection Q^-1 v^n.
  PetscCall(VecWAXPY(nodal_.term, -c.dt, nodal_.acc, nodal_.vel));
  PetscCall(VecCopy(nodal_.term, nodal_.vstar));
  xpicVp_.resize(kDim * static_cast<size_t>(p.n));
  for (int k = 1; k < sc_.xpicOrder; ++k) {
    PetscCall(grid_.toWindow(nodal_.term, nodal_.vstarW));
    const PetscScalar *t = nullptr;
    PetscScalar *mom = nullptr;
    PetscCall(VecGetArrayRead(nodal_.vstarW, &t));
    transfer::interpolate<kDim>(st_, p.n, t, xpicVp_.data());
    PetscCall(VecRestoreArrayRead(nodal_.vstarW, &t));
    PetscCall(VecZeroEntries(nodal_.sumW));
    PetscCall(VecGetArray(nodal_.sumW, &mom));
    transfer::particlesToGrid<kDim>(st_, p.n, p.m, xpicVp_.data(), mom, nullptr);
    PetscCall(VecRestoreArray(nodal_.sumW, &mom));
    PetscCall(VecZeroEntries(nodal_.f)); // free after the grid update: Q t
    PetscCall(grid_.addFromWindow(nodal_.sumW, nodal_.f));
    PetscCall(VecPointwiseMult(nodal_.f, nodal_.f, nodal_.invMass));
    PetscCall(VecAXPY(nodal_.term, -1.0, nodal_.f)); // (I - Q) t
    PetscCall(VecAXPY(nodal_.vstar, 1.0, nodal_.term));
  }
  PetscCall(grid_.toWindow(nodal_.vstar, nodal_.vstarW));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::gridToParticles(ParticleView<2> &p, const StepClock &c,
                                       const double *centres) {
  PetscCall(PetscLogStagePush(stages_.g2p));
  if (sc_.transfer == Transfer::Xpic) PetscCall(xpicFilter(p, c));
  const PetscScalar *vg = nullptr, *ag = nullptr;
  PetscCall(VecGetArrayRead(nodal_.velW, &vg));
  PetscCall(VecGetArrayRead(nodal_.accW, &ag));
  const bool reprojects = scheme_.stressFromReprojection || tracksCorners(sc_.tracking);
  // With a re-projection (FLIP/PIC and APIC) each particle's new momentum goes back to the grid
  // with the same stencil right after its G2P, in one pass over the particles.
  const bool fused = reprojects && sc_.transfer != Transfer::Xpic;
  PetscScalar *mom = nullptr;
  if (fused) {
    PetscCall(VecZeroEntries(nodal_.sumW));
    PetscCall(VecGetArray(nodal_.sumW, &mom));
  }
  if (sc_.transfer == Transfer::Apic && fused && lanes_) {
    transfer::lanes2::gridToParticlesAffineProjected(st_, p.n, vg, centres, slotCoordinates(), c.dt,
                                                     p.m, p.v, p.B, p.x, mom);
  } else if (sc_.transfer == Transfer::Apic && fused) {
    transfer::gridToParticlesAffineProjected<kDim>(st_, p.n, vg, centres, slotCoordinates(), c.dt,
                                                   p.m, p.v, p.B, p.x, mom);
  } else if (sc_.transfer == Transfer::Apic && lanes_) {
    transfer::lanes2::gridToParticlesAffine(st_, p.n, vg, centres, slotCoordinates(), c.dt, p.v,
                                            p.B, p.x);
  } else if (sc_.transfer == Transfer::Apic) {
    transfer::gridToParticlesAffine<kDim>(st_, p.n, vg, centres, slotCoordinates(), c.dt, p.v, p.B,
                                          p.x);
  } else if (sc_.transfer == Transfer::Xpic) {
    const PetscScalar *vs = nullptr;
    PetscCall(VecGetArrayRead(nodal_.vstarW, &vs));
    transfer::gridToParticlesFiltered<kDim>(st_, p.n, vg, ag, vs, c.dt, p.v, p.x);
    PetscCall(VecRestoreArrayRead(nodal_.vstarW, &vs));
  } else if (fused) {
    transfer::gridToParticlesProjected<kDim>(st_, p.n, vg, ag, c.dt, sc_.flip, p.m, p.v, p.x, mom);
  } else {
    transfer::gridToParticles<kDim>(st_, p.n, vg, ag, c.dt, sc_.flip, p.v, p.x);
  }
  if (fused) PetscCall(VecRestoreArray(nodal_.sumW, &mom));
  PetscCall(VecRestoreArrayRead(nodal_.accW, &ag));
  PetscCall(VecRestoreArrayRead(nodal_.velW, &vg));
  if (reprojects) PetscCall(reproject(p, c, centres, fused));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

PetscErrorCode Solver::reproject(ParticleView<2> &p, const StepClock &c, const double *centres,
                                 bool projected) {
  // Re-project the updated particle momentum (acc is free now) with the step's own P2G (APIC:
  // the affine fields of the new B_p): the velocity field of MUSL's stress update, and the one
  // the corners follow. Unlike p^n+1 / m it is a weighted mean of particle velocities, so a
  // node that a particle barely touches (tiny mass, huge F / m) cannot throw a corner away.
  if (!projected) { // (else G2P put the momenta on the window already)
    PetscScalar *mom = nullptr;
    PetscCall(VecZeroEntries(nodal_.sumW));
    PetscCall(VecGetArray(nodal_.sumW, &mom));
    projectMomentum(st_, p, centres, mom, nullptr);
    PetscCall(VecRestoreArray(nodal_.sumW, &mom));
  }
  PetscCall(VecZeroEntries(nodal_.acc));
  PetscCall(grid_.addFromWindow(nodal_.sumW, nodal_.acc));
  PetscCall(VecPointwiseMult(nodal_.acc, nodal_.acc, nodal_.invMass));
  PetscCall(grid_.toWindow(nodal_.acc, nodal_.accW));
  // The re-projected fields of a cracked node may approach each other again: the same contact
  // (faces of this step), or MUSL's strain would see the faces interpenetrate.
  if (!sc_.cracks.empty()) PetscCall(crackContact(c, nodal_.accW, nodal_.acc, nullptr, nullptr));
  if (scheme_.stressFromReprojection) {
    PetscCall(VecCopy(nodal_.acc, nodal_.vel));
    PetscCall(VecCopy(nodal_.accW, nodal_.velW));
  }
  if (tracksCorners(sc_.tracking)) {
    PetscCall(grid_.toWindow(nodal_.mass, nodal_.massW)); // the summed mass on the window
    const PetscScalar *va = nullptr, *mw = nullptr;
    PetscCall(VecGetArrayRead(nodal_.accW, &va));
    PetscCall(VecGetArrayRead(nodal_.massW, &mw));
    // cpdi2 moves its corners with the grid's point shape functions (Sadeghirad et al. 2013).
    const double size = sc_.tracking == Tracking::Cpdi2 ? 0.0 : sc_.cornerSize;
    const bool ok =
        corners_.move(grid_, sc_.cracks, size, sc_.massCutoff * meanParticleMass_, c.dt, va, mw, p);
    PetscCall(VecRestoreArrayRead(nodal_.massW, &mw));
    PetscCall(VecRestoreArrayRead(nodal_.accW, &va));
    if (!ok)
      localFailure_ = "a tracked corner's particle is larger than a level-0 cell, or a corner "
                      "left the grid";
  }
  return PETSC_SUCCESS;
}

} // namespace gimp
