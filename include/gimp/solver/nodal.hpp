// The nodal vectors of the composite grid (dof D). Global Vecs (DMComposite of the level DMDAs)
// live on the owning ranks; window Vecs hold this rank's window of every level, where the
// particle kernels add and read (Grid::toWindow / addFromWindow move between them).
#pragma once

#include "gimp/grid/grid.hpp"

namespace gimp {

/// The global vectors.
struct NodalGlobal {
  Vec P = nullptr;       // momentum: the TS solution
  Vec mass = nullptr;    // nodal mass, in component 0 (dof layout of the momentum)
  Vec vel = nullptr;     // nodal velocity
  Vec acc = nullptr;     // nodal acceleration; the re-projected velocity after G2P
  Vec f = nullptr;       // internal + external force of this step (before damping and masks)
  Vec rhs = nullptr;     // the last RHS: total nodal force incl. damping, masked
  Vec fext = nullptr;    // external force (tractions, body force, penalty), if the scene has any
  Vec bcMask = nullptr;  // 1 free, 0 constrained, per dof
  Vec mask = nullptr;    // bcMask times (node has mass)
  Vec invMass = nullptr; // mask / mass
  Vec face = nullptr;    // with cracks: where each field's material ends toward the other
  Vec vstar = nullptr, term = nullptr; // XPIC: the filtered velocity and its series' term
};

/// The window vectors.
struct NodalWindow {
  Vec sumW = nullptr, massW = nullptr, velW = nullptr, accW = nullptr, extW = nullptr;
  Vec faceW = nullptr, maskW = nullptr; // with cracks: faces; mask on the window
  Vec vstarW = nullptr;                 // XPIC: the filtered velocity on the window
};

struct Nodal : NodalGlobal, NodalWindow {
  Nodal() = default;
  Nodal(const Nodal &) = delete;
  Nodal &operator=(const Nodal &) = delete;
  ~Nodal();
  /// Every Vec destroyed (create() may make them again on a new grid).
  void destroy();
  template <int D>
  PetscErrorCode create(const Grid<D> &grid, bool external, bool cracks, bool xpic);
};

} // namespace gimp
