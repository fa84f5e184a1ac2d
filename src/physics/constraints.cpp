#include "gimp/physics/constraints.hpp"

#include <vector>

namespace gimp::physics {

namespace {

const char *const kAxes[] = {"x", "y", "z"};

/// Level-0 grid line (2D) or plane (3D) of constraint b, as finest-lattice units; throws when it
/// is off the lines.
template <int D> std::int64_t constraintLine(const Scene<D> &sc, const Grid<D> &grid, size_t b) {
  const NodeBC<D> &bc = sc.bcs[b];
  const PetscInt line = grid.lineIndex(bc.axis, bc.coord);
  if (line < 0) {
    const char *what = D == 2 ? "line" : "plane";
    throw InputError("option -gimp_bc" + std::to_string(b) + "_" + kAxes[bc.axis] + " " +
                     formatNumber(bc.coord) + ": not on a level-0 grid " + what +
                     " inside the domain (" + what + "s at " + formatNumber(grid.origin[bc.axis]) +
                     " + i * " + formatNumber(grid.h0()) + ")");
  }
  const Level<D> &L0 = grid.levels[0];
  return L0.lo[bc.axis] + line * L0.step;
}

/// Whether constraint b fixes level k's active node i, on its line or plane `line` [lattice
/// units], within its range.
template <int D>
bool constrains(const Scene<D> &sc, const Grid<D> &grid, size_t b, std::int64_t line, int k,
                const LatticeIndex<D> &i) {
  const NodeBC<D> &bc = sc.bcs[b];
  const Level<D> &L = grid.levels[k];
  if (L.at(bc.axis, i[bc.axis]) != line || !grid.nodeActive(k, i)) return false;
  const double tol = 1e-9 * L.h;
  int r = 0;
  for (int a = 0; a < D && bc.hasRange; ++a) {
    if (a == bc.axis) continue;
    const double along = grid.nodeCoordinate(k, a, i[a]);
    if (!(along >= bc.range[2 * r] - tol && along <= bc.range[2 * r + 1] + tol)) return false;
    ++r;
  }
  return true;
}

/// The masks of level k's owned nodes (sub: its part of bcMask, x fastest, D dofs a node); counts
/// the nodes each constraint fixes into hits.
template <int D>
PetscErrorCode maskLevel(const Scene<D> &sc, const Grid<D> &grid, int k,
                         const std::vector<std::int64_t> &lines, Vec sub,
                         std::vector<PetscInt64> &hits) {
  PetscInt s[3] = {0, 0, 0}, m[3] = {1, 1, 1};
  PetscCall(DMDAGetCorners(grid.da[k], &s[0], &s[1], &s[2], &m[0], &m[1], &m[2]));
  PetscScalar *mk = nullptr;
  PetscCall(VecGetArray(sub, &mk));
  std::array<PetscInt, D> n;
  for (int a = 0; a < D; ++a)
    n[a] = m[a];
  forEachIndex<D>(n, [&](const LatticeIndex<D> &o) {
    LatticeIndex<D> i;
    PetscInt at = 0;
    for (int a = D - 1; a >= 0; --a) {
      i[a] = s[a] + o[a];
      at = at * m[a] + static_cast<PetscInt>(o[a]);
    }
    for (size_t b = 0; b < sc.bcs.size(); ++b) {
      if (!constrains<D>(sc, grid, b, lines[b], k, i)) continue;
      ++hits[b];
      for (int c = 0; c < D; ++c)
        if (sc.bcs[b].fix[c]) mk[D * at + c] = 0.0;
    }
  });
  PetscCall(VecRestoreArray(sub, &mk));
  return PETSC_SUCCESS;
}

/// A cracked node's second field is fixed like its first (the crack part of the composite).
template <int D>
PetscErrorCode maskCrackFields(const Scene<D> &sc, const Grid<D> &grid,
                               const std::vector<std::int64_t> &lines, Vec sub) {
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm(reinterpret_cast<PetscObject>(sub)), &rank));
  PetscScalar *mk = nullptr;
  PetscCall(VecGetArray(sub, &mk));
  for (const typename Grid<D>::CrackedNode &cn : grid.crackedNodes()) {
    if (cn.owner != rank) continue;
    for (size_t b = 0; b < sc.bcs.size(); ++b)
      if (constrains<D>(sc, grid, b, lines[b], cn.k, cn.i))
        for (int c = 0; c < D; ++c)
          if (sc.bcs[b].fix[c]) mk[D * cn.ownerPos + c] = 0.0;
  }
  PetscCall(VecRestoreArray(sub, &mk));
  return PETSC_SUCCESS;
}

} // namespace

template <int D>
PetscErrorCode nodeConstraints(const Scene<D> &sc, const Grid<D> &grid, Vec bcMask) {
  PetscCall(VecSet(bcMask, 1.0));
  if (sc.bcs.empty()) return PETSC_SUCCESS;
  std::vector<std::int64_t> lines;
  for (size_t b = 0; b < sc.bcs.size(); ++b)
    lines.push_back(constraintLine(sc, grid, b));
  const int K = static_cast<int>(grid.levels.size());
  const int parts = K + (grid.crackDm ? 1 : 0);
  std::vector<Vec> sub(parts);
  std::vector<PetscInt64> hits(sc.bcs.size(), 0); // the nodes each constraint fixes
  PetscCall(DMCompositeGetAccessArray(grid.dm, bcMask, parts, nullptr, sub.data()));
  for (int k = 0; k < K; ++k)
    PetscCall(maskLevel(sc, grid, k, lines, sub[k], hits));
  if (grid.crackDm) PetscCall(maskCrackFields(sc, grid, lines, sub[K]));
  PetscCall(DMCompositeRestoreAccessArray(grid.dm, bcMask, parts, nullptr, sub.data()));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, hits.data(), static_cast<int>(hits.size()), MPI_INT64_T,
                             MPI_SUM, PetscObjectComm(reinterpret_cast<PetscObject>(bcMask))));
  const std::string what = D == 2 ? "line" : "plane";
  for (size_t b = 0; b < hits.size(); ++b) {
    const NodeBC<D> &bc = sc.bcs[b];
    if (hits[b] > 0) continue;
    std::string range;
    for (size_t r = 0; r < bc.range.size(); ++r)
      range += (r ? "," : "") + formatNumber(bc.range[r]);
    const std::string opt = "option -gimp_bc" + std::to_string(b);
    if (bc.hasRange)
      throw InputError(opt + "_range " + range + ": no active grid node of the " + what +
                       " lies in the range");
    throw InputError(opt + "_" + kAxes[bc.axis] + " " + formatNumber(bc.coord) +
                     ": no active grid node lies on the " + what);
  }
  return PETSC_SUCCESS;
}

namespace {
template <int dof>
void maskMomentum(PetscInt nloc, const double *m, const double *bc, double cut, double *mk,
                  double *im, double *p, double *v) {
  for (PetscInt i = 0; i < nloc; i += dof)
    maskMomentumNode(m[i], bc + i, cut, dof, mk + i, im + i, p + i, v + i);
}
} // namespace

PetscErrorCode massMaskMomentum(Vec mass, Vec bcMask, double cut, Vec mask, Vec invMass, Vec P,
                                Vec vel, int dof) {
  PetscCheck(dof == 2 || dof == 3, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "massMaskMomentum: dof %d (2 or 3)", dof);
  const PetscScalar *m = nullptr, *bc = nullptr;
  PetscScalar *mk = nullptr, *im = nullptr, *p = nullptr, *v = nullptr;
  PetscInt nloc = 0;
  PetscCall(VecGetLocalSize(mass, &nloc));
  PetscCall(VecGetArrayRead(mass, &m));
  PetscCall(VecGetArrayRead(bcMask, &bc));
  PetscCall(VecGetArray(mask, &mk));
  PetscCall(VecGetArray(invMass, &im));
  PetscCall(VecGetArray(P, &p));
  PetscCall(VecGetArray(vel, &v));
  if (dof == 2)
    maskMomentum<2>(nloc, m, bc, cut, mk, im, p, v);
  else
    maskMomentum<3>(nloc, m, bc, cut, mk, im, p, v);
  PetscCall(VecRestoreArray(vel, &v));
  PetscCall(VecRestoreArray(P, &p));
  PetscCall(VecRestoreArray(invMass, &im));
  PetscCall(VecRestoreArray(mask, &mk));
  PetscCall(VecRestoreArrayRead(bcMask, &bc));
  PetscCall(VecRestoreArrayRead(mass, &m));
  return PETSC_SUCCESS;
}

template PetscErrorCode nodeConstraints<2>(const Scene<2> &, const Grid<2> &, Vec);
template PetscErrorCode nodeConstraints<3>(const Scene<3> &, const Grid<3> &, Vec);

} // namespace gimp::physics
