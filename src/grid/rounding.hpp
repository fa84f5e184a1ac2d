// floor and ceil to a node index without a libm call, for the grid's hot loops (stencils.cpp,
// cpdi_stencils.cpp).
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

} // namespace gimp
