// gimp: explicit GIMP solid dynamics on a structured grid. See README.md and docs/.
#include "gimp/solver/solver.hpp"

#include <petscsys.h>

#include <cstdio>
#include <cstring>

static const char help[] =
    "gimp: explicit Generalized Interpolation Material Point solver.\n"
    "Usage: gimp -options_file options/plate.opts [-ts_max_steps N] [-log_view]\n"
    "Options are listed below and in docs/options.md (SI units).\n";

namespace {

/// PETSc reports a missing -options_file with a long trace; say it in one line instead.
bool optionsFilesExist(int argc, char **argv) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "-options_file") != 0) continue;
    std::FILE *f = std::fopen(argv[i + 1], "r");
    if (!f) {
      std::fprintf(stderr, "gimp: error: option -options_file %s: cannot open the file\n",
                   argv[i + 1]);
      return false;
    }
    std::fclose(f);
  }
  return true;
}

} // namespace

int main(int argc, char **argv) {
  if (!optionsFilesExist(argc, argv)) return 2;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, help));
  int code = 0;
  try {
    PetscErrorCode ierr;
    {
      gimp::Solver sim(PETSC_COMM_WORLD);
      ierr = sim.setup();
      if (!ierr) ierr = sim.run();
      // An unstable run stopped early with its outputs written: exit non-zero.
      if (!ierr && sim.failed()) code = 3;
    }
    if (ierr) code = 1;
  } catch (const gimp::InputError &e) {
    PetscMPIInt rank = 0;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    if (rank == 0) std::fprintf(stderr, "gimp: error: %s\n", e.what());
    code = 2;
  }
  // An input error is detected on every rank alike; finalize cleanly.
  (void)PetscFinalize();
  return code;
}
