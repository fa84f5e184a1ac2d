#include "gimp/core/errors.hpp"

#include <sstream>
#include <vector>

namespace gimp {

std::string formatNumber(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

PetscErrorCode agree(MPI_Comm comm, const std::string &localError) {
  PetscMPIInt rank = 0, size = 1;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscMPIInt mine = localError.empty() ? size : rank, first = size;
  PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm));
  if (first == size) return PETSC_SUCCESS;
  int len = static_cast<int>(localError.size());
  PetscCallMPI(MPI_Bcast(&len, 1, MPI_INT, first, comm));
  std::vector<char> text(localError.begin(), localError.end());
  text.resize(static_cast<size_t>(len));
  PetscCallMPI(MPI_Bcast(text.data(), len, MPI_CHAR, first, comm));
  throw InputError(std::string(text.begin(), text.end()));
}

} // namespace gimp
