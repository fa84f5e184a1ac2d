#include "gimp/diagnostics/gather.hpp"

namespace gimp {

PetscErrorCode gatherToRoot(MPI_Comm comm, const std::vector<double> &loc,
                            std::vector<double> &all) {
  PetscMPIInt rank = 0, size = 1;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  const int mine = static_cast<int>(loc.size());
  std::vector<int> counts(size), displs(size, 0);
  PetscCallMPI(MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm));
  all.clear();
  if (rank == 0) {
    for (int r = 1; r < size; ++r)
      displs[r] = displs[r - 1] + counts[r - 1];
    all.resize(static_cast<size_t>(displs.back() + counts.back()));
  }
  PetscCallMPI(MPI_Gatherv(loc.data(), mine, MPI_DOUBLE, all.data(), counts.data(), displs.data(),
                           MPI_DOUBLE, 0, comm));
  return PETSC_SUCCESS;
}

} // namespace gimp
