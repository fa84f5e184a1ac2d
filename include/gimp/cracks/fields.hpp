// The two velocity fields of explicit cracks on the grid: which field of a cracked node a
// particle joins, and frictionless contact between the fields after the grid update.
#pragma once

#include "gimp/cracks/geometry.hpp"
#include "gimp/grid/grid.hpp"

#include <vector>

namespace gimp::cracks {

/// A particle joins field 1 of a node (the node's own slot) when the segment from the particle
/// (its weight centre x) to the node crosses no crack, and field 2 (the node's crack slot) when
/// it crosses one: entries of cracked nodes are moved to the second slot accordingly.
void assignFields(const Grid &g, const std::vector<Crack> &cracks, PetscInt n, const double *x,
                  Stencils<kDim> &st);

/// Contact between the two fields of every cracked node of a window.
class Contact {
public:
  /// The direction d of each cracked window node, from field 1's material toward field 2's:
  /// field 1 is on the node's side of the nearest crack, field 2 across it.
  void setup(const Grid &g, const std::vector<Crack> &cracks);

  /// Where each field's material ends toward the other, into the window array `face` (component
  /// 0 of each slot; initialised here): field 1 slots get the largest x_p.d + extent of their
  /// particles, field 2 slots minus the smallest x_p.d - extent (so that both combine across
  /// ranks by MAX). Other slots get -inf.
  void faces(const Grid &g, const Stencils<kDim> &st, PetscInt n, const double *x, const double *l,
             double *face) const;

  /// Frictionless contact where both fields carry mass (> cut) and their faces touch (a gap
  /// below 1e-3 of the cell): when the fields approach each other along d, both take the normal
  /// velocity of their common centre of mass (momentum is kept); fields that separate stay
  /// free. Window arrays, mass in component 0; the accelerations get the same change / dt so a
  /// FLIP update sees it (acc may be null: a velocity field alone, as MUSL's re-projection).
  /// Returns the number of nodes in contact.
  PetscInt apply(const Grid &g, double cut, double dt, const double *mass, const double *face,
                 double *vel, double *acc) const;

private:
  std::vector<double> dir_; // 2 per crack slot (slot - nWindow)
};

} // namespace gimp::cracks
