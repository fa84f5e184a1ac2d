// Which of a cracked node's two velocity fields each particle joins (explicit cracks): the
// grid's second slots (Grid::crackSlot, src/grid/crack_fields.cpp) and the cracks (polylines,
// polygons in 3D) decide it, per particle-node entry of the stencils.
#pragma once

#include "gimp/geometry/crack.hpp"
#include "gimp/geometry/crack_surface.hpp"
#include "gimp/grid/grid.hpp"

#include <vector>

namespace gimp::cracks {

/// A particle joins field 1 of a node (the node's own slot) when the segment from the particle
/// (its weight centre x) to the node crosses no crack, and field 2 (the node's crack slot) when
/// it crosses one: entries of cracked nodes are moved to the second slot accordingly.
template <int D>
void assignFields(const Grid<D> &g, const std::vector<CrackOf<D>> &cracks, PetscInt n,
                  const double *x, Stencils<D> &st);

} // namespace gimp::cracks
