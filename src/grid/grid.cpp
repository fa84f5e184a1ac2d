#include "gimp/grid/grid.hpp"

#include <petscao.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace gimp {

Grid::~Grid() {
  for (DM &d : da)
    if (d) (void)DMDestroy(&d);
  for (DM &d : da1)
    if (d) (void)DMDestroy(&d);
  if (crackDm) (void)DMDestroy(&crackDm);
  if (dm) (void)DMDestroy(&dm);
  if (scatter_) (void)VecScatterDestroy(&scatter_);
  if (windowTemplate_) (void)VecDestroy(&windowTemplate_);
}

PetscErrorCode Grid::create(MPI_Comm comm, const Scene &sc) {
  setGeometry(sc);

  const int K = static_cast<int>(levels.size());

  // Level 0 decides the rank layout (and owns the particles); finer levels are DMDAs of their
  // own, partitioned by PETSc: the window scatter reaches whatever nodes a rank needs.
  da.assign(K, nullptr);
  da1.assign(K, nullptr);
  PetscCall(DMCompositeCreate(comm, &dm));
  for (int k = 0; k < K; ++k) {
    Level &L = levels[k];
    PetscCall(DMDACreate2d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX, L.n[0],
                           L.n[1], PETSC_DECIDE, PETSC_DECIDE, 2, 0, nullptr, nullptr, &da[k]));
    if (k == 0) PetscCall(DMSetFromOptions(da[k])); // -da_processors_x/y choose the rank layout
    PetscCall(DMSetUp(da[k]));
    PetscCall(DMDASetFieldName(da[k], 0, "x"));
    PetscCall(DMDASetFieldName(da[k], 1, "y"));
    PetscCall(DMDASetUniformCoordinates(da[k], L.box[0], L.box[2], L.box[1], L.box[3], 0, 0));
    PetscCall(DMDACreateCompatibleDMDA(da[k], 1, &da1[k]));
    PetscCall(DMCompositeAddDM(dm, da[k]));
  }
  PetscCall(setWindow());
  fillWindowNodes();
  PetscCall(addCrackFields(comm, sc));
  PetscCall(DMSetUp(dm));
  PetscCall(createScatter(comm));
  return PETSC_SUCCESS;
}

PetscErrorCode Grid::setWindow() {
  // Level-0 ownership of nodes; a rank owns the cells whose lower-left node it owns.
  {
    PetscInt px = 0, py = 0;
    const PetscInt *lx = nullptr, *ly = nullptr;
    PetscCall(DMDAGetInfo(da[0], nullptr, nullptr, nullptr, nullptr, &px, &py, nullptr, nullptr,
                          nullptr, nullptr, nullptr, nullptr, nullptr));
    PetscCall(DMDAGetOwnershipRanges(da[0], &lx, &ly, nullptr));
    ownX_.assign(px + 1, 0);
    ownY_.assign(py + 1, 0);
    for (PetscInt r = 0; r < px; ++r)
      ownX_[r + 1] = ownX_[r] + lx[r];
    for (PetscInt r = 0; r < py; ++r)
      ownY_[r + 1] = ownY_[r] + ly[r];
  }
  PetscInt xs = 0, ys = 0, xm = 0, ym = 0;
  PetscCall(DMDAGetCorners(da[0], &xs, &ys, nullptr, &xm, &ym, nullptr));
  // Window: level-0 nodes [xs - 2, xs + xm + 2) in each direction, as lattice units.
  const Level &L0 = levels[0];
  const std::int64_t wu0 = L0.lo[0] + std::max<std::int64_t>(xs - 2, 0) * L0.step;
  const std::int64_t wu1 = L0.lo[0] + std::min<std::int64_t>(xs + xm + 1, L0.n[0] - 1) * L0.step;
  const std::int64_t wv0 = L0.lo[1] + std::max<std::int64_t>(ys - 2, 0) * L0.step;
  const std::int64_t wv1 = L0.lo[1] + std::min<std::int64_t>(ys + ym + 1, L0.n[1] - 1) * L0.step;
  nWindow = 0;
  for (Level &L : levels) {
    auto lo = [&](std::int64_t w, std::int64_t o) {
      return static_cast<PetscInt>(std::max<std::int64_t>(0, (w - o + L.step - 1) / L.step));
    };
    L.w0[0] = std::min(lo(wu0, L.lo[0]), L.n[0]);
    L.w0[1] = std::min(lo(wv0, L.lo[1]), L.n[1]);
    L.w1[0] =
        wu1 < L.lo[0]
            ? 0
            : static_cast<PetscInt>(std::min<std::int64_t>((wu1 - L.lo[0]) / L.step + 1, L.n[0]));
    L.w1[1] =
        wv1 < L.lo[1]
            ? 0
            : static_cast<PetscInt>(std::min<std::int64_t>((wv1 - L.lo[1]) / L.step + 1, L.n[1]));
    if (L.w1[0] < L.w0[0]) L.w1[0] = L.w0[0];
    if (L.w1[1] < L.w0[1]) L.w1[1] = L.w0[1];
    L.offset = nWindow;
    nWindow += (L.w1[0] - L.w0[0]) * (L.w1[1] - L.w0[1]);
  }

  return PETSC_SUCCESS;
}

void Grid::fillWindowNodes() {
  const int K = static_cast<int>(levels.size());
  // Node data of the window.
  active.assign(nWindow, 0);
  regular.assign(nWindow, 0);
  flags_.assign(nWindow, 0);
  X.assign(nWindow, 0);
  Y.assign(nWindow, 0);
  zone.assign(4 * static_cast<size_t>(nWindow), 0);
  for (int k = 0; k < K; ++k) {
    const Level &L = levels[k];
    for (PetscInt j = L.w0[1]; j < L.w1[1]; ++j)
      for (PetscInt i = L.w0[0]; i < L.w1[0]; ++i) {
        const PetscInt n = L.offset + (j - L.w0[1]) * L.wnx() + (i - L.w0[0]);
        X[n] = origin[0] + static_cast<double>(L.lo[0] + i * L.step) * unit;
        Y[n] = origin[1] + static_cast<double>(L.lo[1] + j * L.step) * unit;
        active[n] = nodeActive(k, {i, j});
        if (!active[n]) continue;
        zonesOf(k, {i, j}, &zone[4 * n]);
        regular[n] = zone[4 * n] == L.h && zone[4 * n + 1] == L.h && zone[4 * n + 2] == L.h &&
                     zone[4 * n + 3] == L.h;
        flags_[n] = static_cast<std::uint8_t>(kActive | (regular[n] ? kRegular : 0));
      }
  }

  // block3_[n]: the 3 x 3 block of n's level starting at n (n and the two nodes after it in x
  // and y) lies in the window and is regular: buildStencils takes its closed-form path there.
  block3_.assign(nWindow, 0);
  for (int k = 0; k < K; ++k) {
    const Level &L = levels[k];
    for (PetscInt j = L.w0[1]; j + 2 < L.w1[1]; ++j)
      for (PetscInt i = L.w0[0]; i + 2 < L.w1[0]; ++i) {
        bool ok = true;
        for (PetscInt b = 0; b < 3; ++b)
          for (PetscInt a = 0; a < 3; ++a)
            ok = ok && regular[L.offset + (j + b - L.w0[1]) * L.wnx() + (i + a - L.w0[0])];
        block3_[L.offset + (j - L.w0[1]) * L.wnx() + (i - L.w0[0])] = ok;
      }
  }
}

PetscErrorCode Grid::createScatter(MPI_Comm comm) {
  PetscMPIInt size = 1;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  const int K = static_cast<int>(levels.size());
  // Scatter between the composite global Vec and the window: composite index of each window
  // node. A composite's local part is rank r's owned part of level 0, then of level 1, ...
  std::vector<std::vector<PetscInt>> levelStart(K); // level node ownership starts per rank
  std::vector<PetscInt> compStart(size + 1, 0);
  for (int k = 0; k < K; ++k) {
    Vec g;
    const PetscInt *ranges = nullptr;
    PetscCall(DMGetGlobalVector(da[k], &g));
    PetscCall(VecGetOwnershipRanges(g, &ranges));
    levelStart[k].assign(ranges, ranges + size + 1);
    for (auto &v : levelStart[k])
      v /= 2;
    PetscCall(DMRestoreGlobalVector(da[k], &g));
  }
  std::vector<PetscInt> levelsOwned(size, 0);
  for (int r = 0; r < size; ++r) {
    for (int k = 0; k < K; ++k)
      levelsOwned[r] += levelStart[k][r + 1] - levelStart[k][r];
    compStart[r + 1] = compStart[r] + levelsOwned[r] + (crackDm ? crackCount_[r] : 0);
  }
  std::vector<PetscInt> blocks(nSlots);
  // A composite's rank-r part ends with its cracked nodes' second fields, in cracked_ order.
  for (PetscInt s = nWindow; s < nSlots; ++s) {
    const CrackedNode &c = cracked_[crackedOfSlot_[s - nWindow]];
    blocks[s] = compStart[c.owner] + levelsOwned[c.owner] + c.ownerPos;
  }
  for (int k = 0; k < K; ++k) {
    const Level &L = levels[k];
    const PetscInt n = (L.w1[0] - L.w0[0]) * (L.w1[1] - L.w0[1]);
    std::vector<PetscInt> idx(n);
    for (PetscInt j = L.w0[1]; j < L.w1[1]; ++j)
      for (PetscInt i = L.w0[0]; i < L.w1[0]; ++i)
        idx[(j - L.w0[1]) * L.wnx() + (i - L.w0[0])] = 2 * (j * L.n[0] + i); // the AO counts dofs
    AO ao;
    PetscCall(DMDAGetAO(da[k], &ao));
    PetscCall(AOApplicationToPetsc(ao, n, idx.data()));
    for (PetscInt q = 0; q < n; ++q) {
      const PetscInt p = idx[q] / 2;
      const auto r = std::upper_bound(levelStart[k].begin(), levelStart[k].end(), p) -
                     levelStart[k].begin() - 1;
      PetscInt before = 0;
      for (int kk = 0; kk < k; ++kk)
        before += levelStart[kk][r + 1] - levelStart[kk][r];
      blocks[L.offset + q] = compStart[r] + before + (p - levelStart[k][r]);
    }
  }
  IS is;
  Vec g;
  PetscCall(ISCreateBlock(comm, 2, nSlots, blocks.data(), PETSC_COPY_VALUES, &is));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2 * nSlots, &windowTemplate_));
  PetscCall(VecSetBlockSize(windowTemplate_, 2));
  PetscCall(DMGetGlobalVector(dm, &g));
  PetscCall(VecScatterCreate(g, is, windowTemplate_, nullptr, &scatter_));
  PetscCall(DMRestoreGlobalVector(dm, &g));
  PetscCall(ISDestroy(&is));
  return PETSC_SUCCESS;
}

PetscErrorCode Grid::createWindowVec(Vec *v) const {
  PetscCall(VecDuplicate(windowTemplate_, v));
  return PETSC_SUCCESS;
}

PetscErrorCode Grid::fromWindow(Vec window, Vec global, InsertMode mode) const {
  PetscCall(VecScatterBegin(scatter_, window, global, mode, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(scatter_, window, global, mode, SCATTER_REVERSE));
  return PETSC_SUCCESS;
}

PetscErrorCode Grid::toWindow(Vec global, Vec window) const {
  PetscCall(VecScatterBegin(scatter_, global, window, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(scatter_, global, window, INSERT_VALUES, SCATTER_FORWARD));
  return PETSC_SUCCESS;
}

PetscMPIInt Grid::ownerOf(double x, double y) const {
  const Level &L = levels[0];
  const PetscInt ic =
      std::clamp<PetscInt>(static_cast<PetscInt>(std::floor((x - origin[0]) / L.h)), 0, L.n[0] - 1);
  const PetscInt jc =
      std::clamp<PetscInt>(static_cast<PetscInt>(std::floor((y - origin[1]) / L.h)), 0, L.n[1] - 1);
  const auto rx = std::upper_bound(ownX_.begin(), ownX_.end(), ic) - ownX_.begin() - 1;
  const auto ry = std::upper_bound(ownY_.begin(), ownY_.end(), jc) - ownY_.begin() - 1;
  return static_cast<PetscMPIInt>(ry * (static_cast<PetscInt>(ownX_.size()) - 1) + rx); // x fastest
}

void Grid::ownedBox(PetscMPIInt r, double box[4]) const {
  const Level &L = levels[0];
  const PetscInt nrx = static_cast<PetscInt>(ownX_.size()) - 1, rx = r % nrx, ry = r / nrx;
  const double inf = std::numeric_limits<double>::infinity();
  box[0] = ownX_[rx] == 0 ? -inf : origin[0] + ownX_[rx] * L.h;
  box[1] = ownY_[ry] == 0 ? -inf : origin[1] + ownY_[ry] * L.h;
  box[2] = ownX_[rx + 1] >= L.n[0] ? inf : origin[0] + ownX_[rx + 1] * L.h;
  box[3] = ownY_[ry + 1] >= L.n[1] ? inf : origin[1] + ownY_[ry + 1] * L.h;
}

} // namespace gimp
