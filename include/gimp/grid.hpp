// The background grid: a structured level of nodes held in PETSc DMDAs, with each node's
// influence zone [Lx-, Lx+, Ly-, Ly+] (paper section 3). A single uniform level is the
// case where every interior zone equals the cell size and the domain-edge sides are zero.
#pragma once

#include "gimp/scene.hpp"

#include <petscdmda.h>

#include <vector>

namespace gimp {

class Grid {
public:
  Grid() = default;
  Grid(const Grid &) = delete;
  Grid &operator=(const Grid &) = delete;
  ~Grid();

  /// Create the DMDAs for the scene's domain and cell size (collective).
  PetscErrorCode create(MPI_Comm comm, const Scene &sc);

  DM da = nullptr;  // dof 2: momentum, force, velocity
  DM da1 = nullptr; // dof 1: mass
  double x0 = 0, y0 = 0, h = 0;
  PetscInt M = 0, N = 0;                       // nodes in x and y
  PetscInt xs = 0, ys = 0, xm = 0, ym = 0;     // owned nodes
  PetscInt gxs = 0, gys = 0, gxm = 0, gym = 0; // ghosted local nodes
  std::vector<PetscInt> ownX, ownY; // first owned node index of each rank column/row (+end)

  // Influence zones by global node index. On one uniform level they depend on i (x zones)
  // and j (y zones) alone.
  std::vector<double> Lxm, Lxp, Lym, Lyp;

  /// Rank that owns the cell containing (x, y).
  PetscMPIInt ownerOf(double x, double y) const;

  /// Active nodes as CSV level,x,y,Lxm,Lxp,Lym,Lyp (rank 0 writes).
  PetscErrorCode dump(MPI_Comm comm, const std::string &file) const;

  /// Global index of the grid line nearest to coordinate c on axis (0: x, 1: y), or -1 if c is
  /// not on a grid line (relative tolerance 1e-9 of h).
  PetscInt lineIndex(int axis, double c) const;
};

} // namespace gimp
