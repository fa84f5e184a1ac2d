// Pieces every checked writer shares: closing a FILE with its write errors, the name of a field
// frame's group, and quiet error reporting around HDF5 writes (so a failed write is one agreed
// line, not HDF5's and PETSc's stacks).
#pragma once

#include <petscsys.h>

#include <hdf5.h>

#include <cstdio>
#include <string>

namespace gimp {

/// Flushes and closes f; the error of the first write that failed, or "".
std::string closeChecked(FILE *f);

/// fields.h5's group of the frame of `step` (under /particles and /grid): step_00000012.
std::string frameGroup(PetscInt step);

/// While alive, HDF5 prints no error stack and, with `petscErrors`, PETSc returns its error codes
/// without printing them; both are restored when it goes out of scope, by an exception too.
class QuietErrors {
public:
  explicit QuietErrors(bool petscErrors);
  ~QuietErrors();
  QuietErrors(const QuietErrors &) = delete;
  QuietErrors &operator=(const QuietErrors &) = delete;

private:
  H5E_auto2_t print_ = nullptr;
  void *data_ = nullptr;
  bool pushed_ = false;
};

} // namespace gimp
