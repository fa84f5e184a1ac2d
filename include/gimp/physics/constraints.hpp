// Grid-node constraints and the mask of nodes that take part in the grid update.
#pragma once

#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"

namespace gimp::physics {

/// bcMask (global, dof layout of the momentum): 1 for a free dof, 0 for a dof fixed by a
/// grid-node constraint (-gimp_bcK_*) on a level-0 grid line (2D) or plane (3D), applied to the
/// active nodes of every level within the constraint's range. A constraint off the level-0
/// lines, or whose range holds no active node, is an input error (on every rank alike).
template <int D>
PetscErrorCode nodeConstraints(const Scene<D> &sc, const Grid<D> &grid, Vec bcMask);

/// mask = bcMask where the node's mass exceeds `cut`, else 0; invMass = mask / m (the mass sits
/// in component 0 of each node's `dof` values, D); in the same pass the momentum masked,
/// P *= mask, and the velocity vel = P invMass.
PetscErrorCode massMaskMomentum(Vec mass, Vec bcMask, double cut, Vec mask, Vec invMass, Vec P,
                                Vec vel, int dof);

/// The mask at one node (massMaskMomentum, MultiRate::startNodes): its `dof` values of mask and
/// invMass from its mass m and bcMask bc.
inline void maskNode(double m, const double *bc, double cut, int dof, double *mask,
                     double *invMass) {
  const bool has = m > cut;
  const double inverse = has ? 1.0 / m : 0.0; // (one division per node, not per value)
  for (int c = 0; c < dof; ++c) {
    mask[c] = has ? bc[c] : 0.0;
    invMass[c] = bc[c] != 0.0 ? inverse : 0.0;
  }
}

/// maskNode, then the node's momentum masked, P *= mask, and its velocity vel = P invMass.
inline void maskMomentumNode(double m, const double *bc, double cut, int dof, double *mask,
                             double *invMass, double *P, double *vel) {
  maskNode(m, bc, cut, dof, mask, invMass);
  for (int c = 0; c < dof; ++c) {
    P[c] *= mask[c];
    vel[c] = P[c] * invMass[c];
  }
}

} // namespace gimp::physics
