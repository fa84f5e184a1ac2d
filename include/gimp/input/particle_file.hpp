// A body's particles from a CSV file made elsewhere (-gimp_bodyK_shape file).
#pragma once

#include <petscsys.h>

#include <string>
#include <vector>

namespace gimp {

/// One particle of a particle file.
struct FileParticle {
  double x = 0, y = 0;   // position [m]
  double lx = 0, ly = 0; // half-sizes of its domain [m]
  double area = 0;       // its area [m^2] (the volume over the thickness)
  double vx = 0, vy = 0; // initial velocity [m/s], if the file gives it
};

struct ParticleFile {
  std::vector<FileParticle> particles;
  bool hasVelocity = false;
};

/// Reads the CSV file `path` (collective: rank 0 reads, every rank receives the particles or
/// the same error). The header names the columns: x, y (required), lx and ly (half-sizes) and
/// V (volume, m^3), at least the pair or V, and vx, vy (optional); a particle without lx, ly
/// gets the square of its area, one without V the area 4 lx ly. Columns id, sxx, syy, sxy,
/// szz of gimp's own particle dump are allowed and ignored (a file body starts unstressed);
/// any other column is an error. The file is text: a UTF-8 byte-order mark is skipped, a NUL
/// byte (binary, UTF-16) refused. Two particles of which one's centre lies in the other's
/// domain (the same particle twice) are refused with their lines and positions. `opt` names the
/// option in the error line.
PetscErrorCode readParticleFile(MPI_Comm comm, const std::string &opt, const std::string &path,
                                double thickness, ParticleFile &out);

} // namespace gimp
