// A body's particles from a CSV file made elsewhere (-gimp_bodyK_shape file), in 2D and 3D.
#pragma once

#include <petscsys.h>

#include <string>
#include <vector>

namespace gimp {

/// One particle of a particle file (D = 2 or 3).
template <int D> struct FileParticle {
  double x[D] = {}; // position [m]
  double l[D] = {}; // half-sizes of its domain [m]
  double size = 0;  // its area [m^2] (2D: the volume over the thickness) or volume [m^3] (3D)
  double v[D] = {}; // initial velocity [m/s], if the file gives it
};

template <int D> struct ParticleFile {
  std::vector<FileParticle<D>> particles;
  bool hasVelocity = false;
};

/// Reads the CSV file `path` (collective: rank 0 reads, every rank receives the particles or
/// the same error). The header names the columns: the coordinates x, y (and z in 3D, required),
/// the half-sizes lx, ly (lz) and V (volume, m^3), at least the half-sizes or V, and the
/// velocity vx, vy (vz), optional; a particle without half-sizes gets the square (cube) of its
/// size, one without V the size 2^D lx ly (lz). Columns id and the stresses (sxx, syy, sxy, szz;
/// in 3D also syz, sxz) of gimp's own particle dump are allowed and ignored (a file body starts
/// unstressed); any other column is an error. The file is text: a UTF-8 byte-order mark is
/// skipped, a NUL byte (binary, UTF-16) refused. Two particles of which one's centre lies in the
/// other's domain (the same particle twice) are refused with their lines and positions. `opt`
/// names the option in the error line; `thickness` divides V in 2D (1 in 3D).
template <int D>
PetscErrorCode readParticleFile(MPI_Comm comm, const std::string &opt, const std::string &path,
                                double thickness, ParticleFile<D> &out);

} // namespace gimp
