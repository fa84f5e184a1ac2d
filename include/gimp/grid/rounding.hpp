// Node and cell indices from coordinates without a libm call, for hot loops (grid/stencils.cpp,
// grid/cpdi_stencils.cpp, the rate classes' leaf cells): floor, ceil, and the candidate nodes of a
// level along an axis.
#pragma once

#include <petscsys.h>

namespace gimp {

inline PetscInt ifloor(double v) {
  const PetscInt i = static_cast<PetscInt>(v);
  return i - (v < static_cast<double>(i));
}
inline PetscInt iceil(double v) {
  const PetscInt i = static_cast<PetscInt>(v);
  return i + (v > static_cast<double>(i));
}

/// The indices along axis a of level L's nodes strictly inside (lo, hi): the candidates whose
/// tents can reach a particle that spans [lo, hi] with their reach added (Grid::levelReach),
/// before the rank window clips them; last < first when there are none.
template <class Level>
inline void candidates(const Level &L, int a, double lo, double hi, PetscInt &first,
                       PetscInt &last) {
  first = ifloor((lo - L.box[a]) * L.ih) + 1;
  last = iceil((hi - L.box[a]) * L.ih) - 1;
}

} // namespace gimp
