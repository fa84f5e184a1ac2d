#include "gimp/grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gimp {

Grid::~Grid() {
  if (da) (void)DMDestroy(&da);
  if (da1) (void)DMDestroy(&da1);
}

PetscErrorCode Grid::create(MPI_Comm comm, const Scene &sc) {
  h = sc.h;
  x0 = sc.domain[0];
  y0 = sc.domain[1];
  M = static_cast<PetscInt>(std::lround((sc.domain[2] - sc.domain[0]) / h)) + 1;
  N = static_cast<PetscInt>(std::lround((sc.domain[3] - sc.domain[1]) / h)) + 1;
  // Stencil width 2: a particle owned by a rank (its cell's lower-left node is owned) with
  // half-size up to one cell reaches nodes at most one cell left/below and two right/above.
  PetscCall(DMDACreate2d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX, M, N,
                         PETSC_DECIDE, PETSC_DECIDE, 2, 2, nullptr, nullptr, &da));
  PetscCall(DMSetFromOptions(da)); // -da_processors_x/y choose the rank layout
  PetscCall(DMSetUp(da));
  PetscCall(DMDASetFieldName(da, 0, "x"));
  PetscCall(DMDASetFieldName(da, 1, "y"));
  PetscCall(
      DMDASetUniformCoordinates(da, sc.domain[0], sc.domain[2], sc.domain[1], sc.domain[3], 0, 0));
  PetscCall(DMDACreateCompatibleDMDA(da, 1, &da1));
  PetscCall(DMDAGetCorners(da, &xs, &ys, nullptr, &xm, &ym, nullptr));
  PetscCall(DMDAGetGhostCorners(da, &gxs, &gys, nullptr, &gxm, &gym, nullptr));

  PetscInt px = 0, py = 0;
  const PetscInt *lx = nullptr, *ly = nullptr;
  PetscCall(DMDAGetInfo(da, nullptr, nullptr, nullptr, nullptr, &px, &py, nullptr, nullptr, nullptr,
                        nullptr, nullptr, nullptr, nullptr));
  PetscCall(DMDAGetOwnershipRanges(da, &lx, &ly, nullptr));
  ownX.assign(px + 1, 0);
  ownY.assign(py + 1, 0);
  for (PetscInt r = 0; r < px; ++r)
    ownX[r + 1] = ownX[r] + lx[r];
  for (PetscInt r = 0; r < py; ++r)
    ownY[r + 1] = ownY[r] + ly[r];

  Lxm.assign(M, h);
  Lxp.assign(M, h);
  Lym.assign(N, h);
  Lyp.assign(N, h);
  Lxm.front() = 0; // no grid line beyond the domain edge
  Lxp.back() = 0;
  Lym.front() = 0;
  Lyp.back() = 0;
  return PETSC_SUCCESS;
}

PetscMPIInt Grid::ownerOf(double x, double y) const {
  const PetscInt ic =
      std::clamp<PetscInt>(static_cast<PetscInt>(std::floor((x - x0) / h)), 0, M - 1);
  const PetscInt jc =
      std::clamp<PetscInt>(static_cast<PetscInt>(std::floor((y - y0) / h)), 0, N - 1);
  const auto rx = std::upper_bound(ownX.begin(), ownX.end(), ic) - ownX.begin() - 1;
  const auto ry = std::upper_bound(ownY.begin(), ownY.end(), jc) - ownY.begin() - 1;
  // DMDA ranks are numbered x fastest.
  return static_cast<PetscMPIInt>(ry * (static_cast<PetscInt>(ownX.size()) - 1) + rx);
}

PetscInt Grid::lineIndex(int axis, double c) const {
  const double o = axis == 0 ? x0 : y0;
  const PetscInt n = axis == 0 ? M : N;
  const double s = (c - o) / h;
  const PetscInt i = static_cast<PetscInt>(std::lround(s));
  if (i < 0 || i >= n || std::fabs(s - static_cast<double>(i)) > 1e-9) return -1;
  return i;
}

PetscErrorCode Grid::dump(MPI_Comm comm, const std::string &file) const {
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank != 0) return PETSC_SUCCESS;
  FILE *f = std::fopen(file.c_str(), "w");
  if (!f) throw InputError("option -gimp_grid_dump " + file + ": cannot open the file for writing");
  std::fprintf(f, "level,x,y,Lxm,Lxp,Lym,Lyp\n");
  for (PetscInt j = 0; j < N; ++j)
    for (PetscInt i = 0; i < M; ++i)
      std::fprintf(f, "0,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", x0 + i * h, y0 + j * h, Lxm[i],
                   Lxp[i], Lym[j], Lyp[j]);
  std::fclose(f);
  return PETSC_SUCCESS;
}

} // namespace gimp
