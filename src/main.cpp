// gimp: explicit GIMP solid dynamics on a structured grid. See README.md and docs/.
#include "gimp/simulation.hpp"

#include <petscsys.h>

#include <cstdio>

static const char help[] =
    "gimp: explicit Generalized Interpolation Material Point solver.\n"
    "Usage: gimp -options_file runs/plate.opts [-ts_max_steps N] [-log_view]\n"
    "Options are listed below and in docs/options.md (SI units).\n";

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, help));
  int code = 0;
  try {
    PetscErrorCode ierr;
    {
      gimp::Simulation sim(PETSC_COMM_WORLD);
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
