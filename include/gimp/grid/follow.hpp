// Level boxes that follow a point (-gimp_levelK_follow; docs/method.md, *Levels that follow a
// point*): where a box goes when the point comes near its faces. Pure lattice geometry: boxes in
// finest-lattice units (Lattice<D>::Level::lo, hi), no PETSc.
#pragma once

#include <array>
#include <cstdint>

namespace gimp {

/// A level box in finest-lattice units: low corner, high corner.
template <int D> struct LatticeBox {
  std::array<std::int64_t, D> lo{}, hi{};
  bool operator==(const LatticeBox &o) const { return lo == o.lo && hi == o.hi; }
  bool operator!=(const LatticeBox &o) const { return !(*this == o); }
};

/// The box `box` (its corners on the parent's grid lines, every `cell` units) after following the
/// point x (in lattice units): along each axis where x lies within `margin` units of a face, or
/// beyond it, the box moves by the whole number of parent cells that puts x nearest its centre;
/// then, along every axis, it moves back inside `parent` (which must be at least as large) by
/// whole cells where it stands out. Its size never changes.
template <int D>
LatticeBox<D> followBox(const LatticeBox<D> &box, const LatticeBox<D> &parent, std::int64_t cell,
                        const double *x, double margin);

} // namespace gimp
