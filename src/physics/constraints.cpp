#include "gimp/physics/constraints.hpp"

#include <vector>

namespace gimp::physics {

namespace {

/// Level-0 grid line of constraint b, as finest-lattice units; throws when it is off the lines.
std::int64_t constraintLine(const Scene<2> &sc, const Grid<2> &grid, size_t b) {
  const NodeBC<2> &bc = sc.bcs[b];
  const PetscInt line = grid.lineIndex(bc.axis, bc.coord);
  if (line < 0) {
    const double o = bc.axis == 0 ? grid.origin[0] : grid.origin[1];
    throw InputError("option -gimp_bc" + std::to_string(b) + (bc.axis == 0 ? "_x " : "_y ") +
                     formatNumber(bc.coord) +
                     ": not on a level-0 grid line inside the domain (lines at " + formatNumber(o) +
                     " + i * " + formatNumber(grid.h0()) + ")");
  }
  const Level<2> &L0 = grid.levels[0];
  return (bc.axis == 0 ? L0.lo[0] : L0.lo[1]) + line * L0.step;
}

} // namespace

namespace {

/// Whether constraint b fixes level k's node (i, j), on its line `line` [lattice units].
bool constrains(const Scene<2> &sc, const Grid<2> &grid, size_t b, std::int64_t line, int k,
                PetscInt i, PetscInt j) {
  const NodeBC<2> &bc = sc.bcs[b];
  const Level<2> &L = grid.levels[k];
  const std::int64_t u = bc.axis == 0 ? L.at(0, i) : L.at(1, j);
  if (u != line || !grid.nodeActive(k, {i, j})) return false;
  const double along = bc.axis == 0 ? grid.nodeCoordinate(k, 1, j) : grid.nodeCoordinate(k, 0, i);
  const double tol = 1e-9 * L.h;
  return !bc.hasRange || (along >= bc.range[0] - tol && along <= bc.range[1] + tol);
}

} // namespace

PetscErrorCode nodeConstraints(const Scene<2> &sc, const Grid<2> &grid, Vec bcMask) {
  std::vector<std::int64_t> lines;
  for (size_t b = 0; b < sc.bcs.size(); ++b)
    lines.push_back(constraintLine(sc, grid, b));
  const int K = static_cast<int>(grid.levels.size());
  const int parts = K + (grid.crackDm ? 1 : 0);
  std::vector<Vec> sub(parts);
  PetscCall(VecSet(bcMask, 1.0));
  PetscCall(DMCompositeGetAccessArray(grid.dm, bcMask, parts, nullptr, sub.data()));
  for (int k = 0; k < K; ++k) {
    PetscInt xs, ys, xm, ym;
    PetscScalar ***mk;
    PetscCall(DMDAGetCorners(grid.da[k], &xs, &ys, nullptr, &xm, &ym, nullptr));
    PetscCall(DMDAVecGetArrayDOF(grid.da[k], sub[k], &mk));
    for (size_t b = 0; b < sc.bcs.size(); ++b)
      for (PetscInt j = ys; j < ys + ym; ++j)
        for (PetscInt i = xs; i < xs + xm; ++i)
          if (constrains(sc, grid, b, lines[b], k, i, j))
            for (int c = 0; c < 2; ++c)
              if (sc.bcs[b].fix[c]) mk[j][i][c] = 0.0;
    PetscCall(DMDAVecRestoreArrayDOF(grid.da[k], sub[k], &mk));
  }
  if (grid.crackDm) { // a cracked node's second field is fixed like its first
    PetscMPIInt rank = 0;
    PetscCallMPI(MPI_Comm_rank(PetscObjectComm(reinterpret_cast<PetscObject>(bcMask)), &rank));
    PetscScalar *mk = nullptr;
    PetscCall(VecGetArray(sub[K], &mk));
    for (const Grid<2>::CrackedNode &cn : grid.crackedNodes()) {
      if (cn.owner != rank) continue;
      for (size_t b = 0; b < sc.bcs.size(); ++b)
        if (constrains(sc, grid, b, lines[b], cn.k, cn.i, cn.j))
          for (int c = 0; c < 2; ++c)
            if (sc.bcs[b].fix[c]) mk[2 * cn.ownerPos + c] = 0.0;
    }
    PetscCall(VecRestoreArray(sub[K], &mk));
  }
  PetscCall(DMCompositeRestoreAccessArray(grid.dm, bcMask, parts, nullptr, sub.data()));
  return PETSC_SUCCESS;
}

PetscErrorCode massMask(Vec mass, Vec bcMask, double cut, Vec mask, Vec invMass, int dof) {
  const PetscScalar *m = nullptr, *bc = nullptr;
  PetscScalar *mk = nullptr, *im = nullptr;
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(mass, &nloc));
  PetscCall(VecGetArrayRead(mass, &m));
  PetscCall(VecGetArrayRead(bcMask, &bc));
  PetscCall(VecGetArray(mask, &mk));
  PetscCall(VecGetArray(invMass, &im));
  for (PetscInt i = 0; i < nloc; i += dof) {
    const bool has = m[i] > cut;
    for (int c = 0; c < dof; ++c) {
      mk[i + c] = has ? bc[i + c] : 0.0;
      im[i + c] = has && bc[i + c] != 0.0 ? 1.0 / m[i] : 0.0;
    }
  }
  PetscCall(VecRestoreArray(invMass, &im));
  PetscCall(VecRestoreArray(mask, &mk));
  PetscCall(VecRestoreArrayRead(bcMask, &bc));
  PetscCall(VecRestoreArrayRead(mass, &m));
  return PETSC_SUCCESS;
}

} // namespace gimp::physics
