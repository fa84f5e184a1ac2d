// Helpers shared by the readers of the scene's options (src/input only).
#pragma once

#include "gimp/input/scene.hpp"

#include <string>

namespace gimp::input {

/// "v0,v1,..." as written in error messages.
std::string fmtList(const double *v, PetscInt n);

/// Throw the one-line error for option -opt with the given value and what would be valid.
[[noreturn]] void bad(const std::string &opt, const std::string &value, const std::string &valid);

bool isPerfectSquare(int n);

/// The run's intervals in steps (-gimp_output_interval >= 0, -gimp_history_interval >= 1,
/// -gimp_monitor_interval >= 0, -gimp_sort_interval >= 0), 2D and 3D alike.
void checkRunIntervals(int output, int history, int monitor, int sort);

/// PETSc's EList stops with a trace on an unknown value; check it first and say it in one line.
PetscErrorCode checkChoice(const std::string &opt, const char *const *list, int n);

// The parts of the scene, each from its options (collective; sc.help lists them only).
PetscErrorCode readMaterial(MPI_Comm comm, Scene<2> &sc);
/// mu, lambda and the 2D model's lambda from E and nu.
void deriveMaterial(Material &m);
PetscErrorCode readBodies(MPI_Comm comm, Scene<2> &sc);
PetscErrorCode readLoads(MPI_Comm comm, Scene<2> &sc);
PetscErrorCode readLevels(MPI_Comm comm, Scene<2> &sc);
/// After the levels and bodies (scene_cracks.cpp): -gimp_cracks and each -gimp_crackK_points,
/// checked; each end classified as a tip (strictly inside a body) or a mouth.
PetscErrorCode readCracks(MPI_Comm comm, Scene<2> &sc);

} // namespace gimp::input
