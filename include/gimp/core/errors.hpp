// User errors and how every rank learns of them.
//
// An InputError is one line naming the option, the value and what would be valid; main()
// prints it once and exits 2. It may only be thrown where every rank throws it alike: code
// that runs on all ranks together (reading the scene, collective PETSc calls) either finds a
// problem on every rank, or the rank that found it reports it through agree(), which makes all
// ranks throw the same error at the same point. Nothing throws through PETSc's C callbacks.
#pragma once

#include "gimp/core/petsc_compat.hpp"

#include <stdexcept>
#include <string>

namespace gimp {

/// One-line user error (bad option value, inconsistent scene, unwritable output).
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A number as written in error messages (12 significant digits).
std::string formatNumber(double v);

/// Collective: every rank passes the error it found (empty for none). When any rank found one,
/// every rank throws InputError with the message of the lowest such rank.
PetscErrorCode agree(MPI_Comm comm, const std::string &localError);

} // namespace gimp
