// Every rank's rows concatenated on rank 0, for dumps and measures that need all particles.
#pragma once

#include "gimp/core/petsc_compat.hpp"

#include <vector>

namespace gimp {

/// Collective: rank 0 receives every rank's `loc` in rank order; `all` is empty elsewhere.
PetscErrorCode gatherToRoot(MPI_Comm comm, const std::vector<double> &loc,
                            std::vector<double> &all);

} // namespace gimp
