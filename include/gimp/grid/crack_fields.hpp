// Which of a cracked node's two velocity fields each particle joins (explicit cracks, 2D): the
// grid's second slots (Grid::crackSlot, src/grid/crack_fields.cpp) and the crack polylines
// decide it, per particle-node entry of the stencils.
#pragma once

#include "gimp/geometry/crack.hpp"
#include "gimp/grid/grid.hpp"

#include <vector>

namespace gimp::cracks {

/// A particle joins field 1 of a node (the node's own slot) when the segment from the particle
/// (its weight centre x) to the node crosses no crack, and field 2 (the node's crack slot) when
/// it crosses one: entries of cracked nodes are moved to the second slot accordingly.
void assignFields(const Grid<2> &g, const std::vector<Crack> &cracks, PetscInt n, const double *x,
                  Stencils<2> &st);

} // namespace gimp::cracks
