#include "gimp/grid/grid.hpp"

#include <petscao.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace gimp {

template <int D> Grid<D>::~Grid() {
  destroyPetsc();
}

template <int D> void Grid<D>::destroyPetsc() {
  for (DM &d : da)
    if (d) (void)DMDestroy(&d);
  for (DM &d : da1)
    if (d) (void)DMDestroy(&d);
  if (crackDm) (void)DMDestroy(&crackDm);
  if (dm) (void)DMDestroy(&dm);
  if (scatter_) (void)VecScatterDestroy(&scatter_);
  if (windowTemplate_) (void)VecDestroy(&windowTemplate_);
  for (VecScatter &sc : suffixScatter_)
    if (sc) (void)VecScatterDestroy(&sc);
  for (Vec &w : suffixWindow_)
    if (w) (void)VecDestroy(&w);
  suffixScatter_.clear();
  suffixWindow_.clear();
}

template <int D> void Grid<D>::clear() {
  destroyPetsc();
  static_cast<Lattice<D> &>(*this) = Lattice<D>();
  static_cast<WindowNodes &>(*this) = WindowNodes();
  da.clear();
  da1.clear();
  flags_.clear();
  patterns_.forget();
  threeNodeBlocks_.clear();
  fourNodeBlocks_.clear();
  crackFreeThree_.clear();
  crackFreeFour_.clear();
  outwardReach_.clear();
  own_ = {};
  cracked_.clear();
  crackedOfSlot_.clear();
  crackCount_.clear();
  localLevelStart_.clear();
}

template <int D>
PetscErrorCode Grid<D>::create(MPI_Comm comm, double h0, const std::vector<LevelBox<D>> &boxes,
                               const std::vector<CrackOf<D>> &cracks) {
  this->setLevels(h0, boxes);
  PetscCall(build(comm, cracks));
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Grid<D>::build(MPI_Comm comm, const std::vector<CrackOf<D>> &cracks) {
  const int K = static_cast<int>(levels.size());
  static const char *const axis[3] = {"x", "y", "z"};

  // Level 0 decides the rank layout (and owns the particles); finer levels are DMDAs of their
  // own, partitioned by PETSc: the window scatter reaches whatever nodes a rank needs.
  da.assign(K, nullptr);
  da1.assign(K, nullptr);
  PetscCall(DMCompositeCreate(comm, &dm));
  for (int k = 0; k < K; ++k) {
    Level<D> &L = levels[k];
    if constexpr (D == 2)
      PetscCall(DMDACreate2d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX, L.n[0],
                             L.n[1], PETSC_DECIDE, PETSC_DECIDE, D, 0, nullptr, nullptr, &da[k]));
    else
      PetscCall(DMDACreate3d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE,
                             DMDA_STENCIL_BOX, L.n[0], L.n[1], L.n[2], PETSC_DECIDE, PETSC_DECIDE,
                             PETSC_DECIDE, D, 0, nullptr, nullptr, nullptr, &da[k]));
    if (k == 0) PetscCall(DMSetFromOptions(da[k])); // -da_processors_x/y/z choose the rank layout
    PetscCall(DMSetUp(da[k]));
    if (k == 0 && cellWork) PetscCall(balanceLevel0(comm));
    for (int a = 0; a < D; ++a)
      PetscCall(DMDASetFieldName(da[k], a, axis[a]));
    PetscCall(DMDASetUniformCoordinates(da[k], L.box[0], L.box[D], L.box[1], L.box[D + 1],
                                        D == 3 ? L.box[2] : 0, D == 3 ? L.box[D + 2] : 0));
    PetscCall(DMDACreateCompatibleDMDA(da[k], 1, &da1[k]));
    PetscCall(DMCompositeAddDM(dm, da[k]));
  }
  // How far each level's nodes reach outside its box: the largest outward zone of its boundary
  // nodes (the width of the coarser leaf cells next to the box; h0 for level 0, whose box is
  // the domain).
  outwardReach_.assign(K, levels[0].h);
  for (int k = 1; k < K; ++k) {
    const Level<D> &L = levels[k];
    double reach = L.h;
    for (int a = 0; a < D; ++a) // the nodes of the box's two faces across axis a
      for (const PetscInt side : {PetscInt{0}, L.n[a] - 1}) {
        std::array<PetscInt, D> face = L.n;
        face[a] = 1;
        forEachIndex<D>(face, [&](const Index &f) {
          Index i = f;
          i[a] = side;
          if (!this->nodeActive(k, i)) return;
          double z[2 * D];
          this->zonesOf(k, i, z);
          for (int s = 0; s < 2 * D; ++s)
            reach = std::max(reach, z[s]);
        });
      }
    outwardReach_[k] = reach;
  }
  PetscCall(setWindow());
  fillWindowNodes();
  // One slot per window node; with cracks, second fields after them.
  PetscMPIInt size = 1;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  nSlots = nWindow;
  slotNode.resize(nWindow);
  for (PetscInt n = 0; n < nWindow; ++n)
    slotNode[n] = n;
  crackSlot.assign(nWindow, -1);
  liveSlot.clear();
  crackCount_.assign(size, 0);
  PetscCall(addCrackFields(comm, cracks));
  markLiveCracks(cracks, this->h0());
  PetscCall(DMSetUp(dm));
  PetscCall(createScatter(comm));
  return PETSC_SUCCESS;
}

template <int D> std::vector<std::vector<double>> Grid<D>::workAlongAxes() const {
  // Every leaf cell's work, added to the level-0 cell holding its centre, per axis.
  const Level<D> &L0 = levels[0];
  std::vector<std::vector<double>> w(D);
  for (int a = 0; a < D; ++a)
    w[a].assign(static_cast<size_t>(L0.n[a] - 1), 0.0);
  for (int k = 0; k < static_cast<int>(levels.size()); ++k) {
    const Level<D> &L = levels[k];
    std::array<PetscInt, D> cells;
    for (int a = 0; a < D; ++a)
      cells[a] = L.n[a] - 1;
    forEachIndex<D>(cells, [&](const Index &c) {
      double centre[D];
      for (int a = 0; a < D; ++a)
        centre[a] = this->nodeCoordinate(k, a, c[a]) + 0.5 * L.h;
      if (this->leafLevelAt(centre) != k) return;
      const double work = cellWork(centre, L.h);
      if (!(work > 0)) return;
      for (int a = 0; a < D; ++a) {
        const auto i = static_cast<std::int64_t>(std::floor((centre[a] - L0.box[a]) * L0.ih));
        w[a][static_cast<size_t>(std::clamp<std::int64_t>(i, 0, L0.n[a] - 2))] += work;
      }
    });
  }
  return w;
}

std::vector<PetscInt> balancedRanges(const std::vector<double> &work, PetscInt nodes, PetscInt np) {
  // Rank r owns the cells whose lowest node it owns: its first node s_r is where the cumulative
  // work of the cells before it comes nearest r / np of the total, at least one node apart.
  std::vector<double> cum(work.size() + 1, 0.0);
  for (size_t i = 0; i < work.size(); ++i)
    cum[i + 1] = cum[i] + work[i];
  const double total = cum.back();
  std::vector<PetscInt> start(static_cast<size_t>(np) + 1, 0);
  start[static_cast<size_t>(np)] = nodes;
  for (PetscInt r = 1; r < np; ++r) {
    const double target = total * static_cast<double>(r) / static_cast<double>(np);
    PetscInt best = start[static_cast<size_t>(r) - 1] + 1;
    for (PetscInt s = best; s <= nodes - (np - r); ++s)
      if (std::fabs(cum[static_cast<size_t>(std::min<PetscInt>(s, nodes - 1))] - target) <
          std::fabs(cum[static_cast<size_t>(std::min<PetscInt>(best, nodes - 1))] - target))
        best = s;
    start[static_cast<size_t>(r)] = best;
  }
  std::vector<PetscInt> ranges(static_cast<size_t>(np));
  for (PetscInt r = 0; r < np; ++r)
    ranges[static_cast<size_t>(r)] =
        start[static_cast<size_t>(r) + 1] - start[static_cast<size_t>(r)];
  return ranges;
}

template <int D> PetscErrorCode Grid<D>::balanceLevel0(MPI_Comm comm) {
  // PETSc chose the layout (or -da_processors_*); a second DMDA keeps it with the nodes of each
  // axis split by work instead of evenly. Every rank computes the same ranges.
  PetscInt np[3] = {1, 1, 1};
  PetscCall(DMDAGetInfo(da[0], nullptr, nullptr, nullptr, nullptr, &np[0], &np[1], &np[2], nullptr,
                        nullptr, nullptr, nullptr, nullptr, nullptr));
  if (np[0] * np[1] * np[2] == 1) return PETSC_SUCCESS;
  const std::vector<std::vector<double>> work = workAlongAxes();
  std::vector<PetscInt> ranges[3];
  for (int a = 0; a < D; ++a)
    ranges[a] = balancedRanges(work[static_cast<size_t>(a)], levels[0].n[a], np[a]);
  DM balanced = nullptr;
  const Level<D> &L = levels[0];
  if constexpr (D == 2)
    PetscCall(DMDACreate2d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX, L.n[0],
                           L.n[1], np[0], np[1], D, 0, ranges[0].data(), ranges[1].data(),
                           &balanced));
  else
    PetscCall(DMDACreate3d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE,
                           DMDA_STENCIL_BOX, L.n[0], L.n[1], L.n[2], np[0], np[1], np[2], D, 0,
                           ranges[0].data(), ranges[1].data(), ranges[2].data(), &balanced));
  PetscCall(DMSetUp(balanced));
  PetscCall(DMDestroy(&da[0]));
  da[0] = balanced;
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Grid<D>::setWindow() {
  // Level-0 ownership of nodes; a rank owns the cells whose lowest node it owns.
  PetscInt np[3] = {1, 1, 1}, corner[3] = {0, 0, 0}, width[3] = {0, 0, 0};
  const PetscInt *ranges[3] = {nullptr, nullptr, nullptr};
  PetscCall(DMDAGetInfo(da[0], nullptr, nullptr, nullptr, nullptr, &np[0], &np[1], &np[2], nullptr,
                        nullptr, nullptr, nullptr, nullptr, nullptr));
  PetscCall(DMDAGetOwnershipRanges(da[0], &ranges[0], &ranges[1], &ranges[2]));
  PetscCall(
      DMDAGetCorners(da[0], &corner[0], &corner[1], &corner[2], &width[0], &width[1], &width[2]));
  std::int64_t wlo[D], whi[D];
  const Level<D> &L0 = levels[0];
  for (int a = 0; a < D; ++a) {
    own_[a].assign(np[a] + 1, 0);
    for (PetscInt r = 0; r < np[a]; ++r)
      own_[a][r + 1] = own_[a][r] + ranges[a][r];
    // Window: level-0 nodes [first - 2, last + 2] of the owned ones on each axis, as lattice
    // units.
    wlo[a] = L0.lo[a] + std::max<std::int64_t>(corner[a] - 2, 0) * L0.step;
    whi[a] = L0.lo[a] + std::min<std::int64_t>(corner[a] + width[a] + 1, L0.n[a] - 1) * L0.step;
  }
  nWindow = 0;
  for (Level<D> &L : levels) {
    for (int a = 0; a < D; ++a) {
      const std::int64_t first = (wlo[a] - L.lo[a] + L.step - 1) / L.step;
      L.w0[a] = std::min(static_cast<PetscInt>(std::max<std::int64_t>(0, first)), L.n[a]);
      L.w1[a] = whi[a] < L.lo[a] ? 0
                                 : static_cast<PetscInt>(std::min<std::int64_t>(
                                       (whi[a] - L.lo[a]) / L.step + 1, L.n[a]));
      if (L.w1[a] < L.w0[a]) L.w1[a] = L.w0[a];
    }
    L.offset = nWindow;
    nWindow += L.windowNodes();
  }
  return PETSC_SUCCESS;
}

template <int D> void Grid<D>::fillWindowNodes() {
  const int K = static_cast<int>(levels.size());
  patterns_.forget();
  // Node data of the window.
  active.assign(nWindow, 0);
  regular.assign(nWindow, 0);
  flags_.assign(nWindow, 0);
  X.assign(nWindow, 0);
  Y.assign(nWindow, 0);
  Z.assign(D == 3 ? nWindow : 0, 0);
  std::vector<double> *coord[3] = {&X, &Y, &Z};
  zone.assign(2 * D * static_cast<size_t>(nWindow), 0);
  for (int k = 0; k < K; ++k) {
    const Level<D> &L = levels[k];
    std::array<PetscInt, D> wn;
    for (int a = 0; a < D; ++a)
      wn[a] = L.wn(a);
    PetscInt n = L.offset; // window nodes in order, x fastest
    forEachIndex<D>(wn, [&](const Index &w) {
      Index i;
      for (int a = 0; a < D; ++a) {
        i[a] = w[a] + L.w0[a];
        (*coord[a])[n] = this->nodeCoordinate(k, a, i[a]);
      }
      active[n] = this->nodeActive(k, i);
      if (active[n]) {
        double *z = &zone[2 * D * n];
        this->zonesOf(k, i, z);
        bool reg = true;
        for (int s = 0; s < 2 * D; ++s)
          reg = reg && z[s] == L.h;
        regular[n] = reg;
        flags_[n] = static_cast<std::uint8_t>(kActive | (reg ? kRegular : 0));
      }
      ++n;
    });
  }

  // threeNodeBlocks_[n]: the 3^D block of n's level starting at n (n and the two nodes after it
  // along every axis) lies in the window, its nodes are active, and their zones are h on every
  // side a block particle can overlap: buildStencils takes its closed-form path there.
  // fourNodeBlocks_ the same for the 4^D block (2D: particles of half-size up to h).
  // A block particle's domain lies between the block's first and last node along each axis (its
  // left end in [x_i0, x_i0 + h), its half-size at most h/2 for 3 nodes and h for 4), so it
  // overlaps only the + side of the first node's tent, only the - side of the last node's and
  // both sides of the nodes between: a node on a finer box's face (its outward zone the coarser
  // cell) or on the domain's edge (zone 0 outside) gives such a particle the weights of a
  // regular node, and may be in a block whose particles lie on its regular side.
  auto regularBlocks = [&](PetscInt side, std::vector<std::uint8_t> &flag) {
    flag.assign(nWindow, 0);
    for (int k = 0; k < K; ++k) {
      const Level<D> &L = levels[k];
      std::array<PetscInt, D> wn;
      bool any = true;
      for (int a = 0; a < D; ++a) {
        wn[a] = L.wn(a) - (side - 1);
        any = any && wn[a] > 0;
      }
      if (!any) continue;
      forEachIndex<D>(wn, [&](const Index &w) {
        PetscInt i[D];
        for (int a = 0; a < D; ++a)
          i[a] = w[a] + L.w0[a];
        bool ok = true;
        std::array<PetscInt, D> block;
        block.fill(side);
        forEachIndex<D>(block, [&](const Index &b) {
          PetscInt j[D];
          for (int a = 0; a < D; ++a)
            j[a] = i[a] + b[a];
          const PetscInt n = windowSlot(k, j);
          ok = ok && active[n];
          const double *z = &zone[2 * D * static_cast<size_t>(n)];
          for (int a = 0; a < D && ok; ++a)
            ok = (b[a] == 0 || z[2 * a] == L.h) && (b[a] == side - 1 || z[2 * a + 1] == L.h);
        });
        flag[windowSlot(k, i)] = ok;
      });
    }
  };
  regularBlocks(3, threeNodeBlocks_);
  if (D == 2) regularBlocks(4, fourNodeBlocks_);
  // The distinct zones of the active nodes (a few: 0, each level's h, the outward zones).
  zoneValues_.clear();
  for (PetscInt n = 0; n < nWindow; ++n)
    if (active[n])
      for (int c = 0; c < 2 * D; ++c)
        zoneValues_.push_back(zone[2 * D * static_cast<size_t>(n) + c]);
  std::sort(zoneValues_.begin(), zoneValues_.end());
  zoneValues_.erase(std::unique(zoneValues_.begin(), zoneValues_.end()), zoneValues_.end());
  if (zoneValues_.size() > 255) zoneValues_.clear();
}

template <int D>
PetscErrorCode Grid<D>::compositeBlocks(MPI_Comm comm, std::vector<PetscInt> &blocks,
                                        std::vector<PetscInt> *localStart) const {
  PetscMPIInt size = 1, rank = 0;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
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
      v /= D;
    PetscCall(DMRestoreGlobalVector(da[k], &g));
  }
  std::vector<PetscInt> levelsOwned(size, 0);
  for (int r = 0; r < size; ++r) {
    for (int k = 0; k < K; ++k)
      levelsOwned[r] += levelStart[k][r + 1] - levelStart[k][r];
    compStart[r + 1] = compStart[r] + levelsOwned[r] + (crackDm ? crackCount_[r] : 0);
  }
  if (localStart) { // this rank's part of each level in its part of the composite, in values
    localStart->assign(K + 1, 0);
    for (int k = 0; k < K; ++k)
      (*localStart)[k + 1] = (*localStart)[k] + D * (levelStart[k][rank + 1] - levelStart[k][rank]);
  }
  blocks.assign(nSlots, 0);
  // A composite's rank-r part ends with its cracked nodes' second fields, in cracked_ order.
  for (PetscInt s = nWindow; s < nSlots; ++s) {
    const CrackedNode &c = cracked_[crackedOfSlot_[s - nWindow]];
    blocks[s] = compStart[c.owner] + levelsOwned[c.owner] + c.ownerPos;
  }
  for (int k = 0; k < K; ++k) {
    const Level<D> &L = levels[k];
    const PetscInt n = L.windowNodes();
    std::vector<PetscInt> idx(n);
    std::array<PetscInt, D> wn;
    for (int a = 0; a < D; ++a)
      wn[a] = L.wn(a);
    PetscInt q = 0;
    forEachIndex<D>(wn, [&](const Index &w) {
      PetscInt natural = 0; // the level's natural (x fastest) node number
      for (int a = D - 1; a >= 0; --a)
        natural = natural * L.n[a] + (w[a] + L.w0[a]);
      idx[q++] = D * natural; // the AO counts dofs
    });
    AO ao;
    PetscCall(DMDAGetAO(da[k], &ao));
    PetscCall(AOApplicationToPetsc(ao, n, idx.data()));
    for (q = 0; q < n; ++q) {
      const PetscInt p = idx[q] / D;
      const auto r = std::upper_bound(levelStart[k].begin(), levelStart[k].end(), p) -
                     levelStart[k].begin() - 1;
      PetscInt before = 0;
      for (int kk = 0; kk < k; ++kk)
        before += levelStart[kk][r + 1] - levelStart[kk][r];
      blocks[L.offset + q] = compStart[r] + before + (p - levelStart[k][r]);
    }
  }
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Grid<D>::createScatter(MPI_Comm comm) {
  std::vector<PetscInt> blocks;
  PetscCall(compositeBlocks(comm, blocks, &localLevelStart_));
  IS is;
  Vec g;
  PetscCall(ISCreateBlock(comm, D, nSlots, blocks.data(), PETSC_COPY_VALUES, &is));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, D * nSlots, &windowTemplate_));
  PetscCall(VecSetBlockSize(windowTemplate_, D));
  PetscCall(DMGetGlobalVector(dm, &g));
  PetscCall(VecScatterCreate(g, is, windowTemplate_, nullptr, &scatter_));
  // One rank holding every node: the window is the global Vec's array slot for slot, and a move
  // is a loop over the two arrays (the same sums, in the same order, as the scatter's).
  PetscInt lo = 0, hi = 0;
  PetscCall(VecGetOwnershipRange(g, &lo, &hi));
  int same = hi - lo == D * nSlots;
  for (PetscInt i = 0; i < nSlots && same; ++i)
    same = blocks[i] == lo / D + i;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &same, 1, MPI_INT, MPI_LAND, comm));
  windowIsLocal_ = same != 0;
  PetscCall(DMRestoreGlobalVector(dm, &g));
  PetscCall(ISDestroy(&is));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Grid<D>::suffixScatter(int from, VecScatter *sc, Vec *w) const {
  const size_t K = levels.size();
  if (suffixScatter_.size() != K) {
    suffixScatter_.assign(K, nullptr);
    suffixWindow_.assign(K, nullptr);
  }
  if (!suffixScatter_[from]) {
    MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(dm));
    std::vector<PetscInt> blocks;
    PetscCall(compositeBlocks(comm, blocks, nullptr));
    const PetscInt first = levels[from].offset, n = nSlots - first;
    IS is;
    Vec g;
    PetscCall(ISCreateBlock(comm, D, n, blocks.data() + first, PETSC_COPY_VALUES, &is));
    PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, D, D * n, nullptr, &suffixWindow_[from]));
    PetscCall(DMGetGlobalVector(dm, &g));
    PetscCall(VecScatterCreate(g, is, suffixWindow_[from], nullptr, &suffixScatter_[from]));
    PetscCall(DMRestoreGlobalVector(dm, &g));
    PetscCall(ISDestroy(&is));
  }
  *sc = suffixScatter_[from];
  *w = suffixWindow_[from];
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Grid<D>::createWindowVec(Vec *v) const {
  PetscCall(VecDuplicate(windowTemplate_, v));
  return PETSC_SUCCESS;
}

PetscErrorCode zeroValues(Vec v, PetscInt from, PetscInt to) {
  PetscInt n = 0;
  PetscCall(VecGetLocalSize(v, &n));
  to = to < 0 ? n : std::min(to, n);
  if (from >= to) return PETSC_SUCCESS;
  PetscScalar *a = nullptr;
  PetscCall(VecGetArray(v, &a));
  std::fill(a + from, a + to, 0.0);
  PetscCall(VecRestoreArray(v, &a));
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Grid<D>::startSum(Vec window, Vec global, Vec *sum, int from,
                                 PetscInt zeroFrom_) const {
  PetscCall(zeroValues(global, zeroFrom_ >= 0 ? zeroFrom_ : localLevelStart(from)));
  *sum = windowIsLocal_ ? global : window;
  if (!windowIsLocal_) PetscCall(zeroValues(window, windowLevelStart(from)));
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Grid<D>::endSum(Vec window, Vec global, int from) const {
  if (!windowIsLocal_) PetscCall(addFromWindow(window, global, from));
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Grid<D>::fromWindow(Vec window, Vec global, InsertMode mode, int from) const {
  return move(window, global, mode, SCATTER_REVERSE, from);
}

template <int D> PetscErrorCode Grid<D>::toWindow(Vec global, Vec window, int from) const {
  return move(window, global, INSERT_VALUES, SCATTER_FORWARD, from);
}

template <int D>
PetscErrorCode Grid<D>::move(Vec window, Vec global, InsertMode mode, ScatterMode dir,
                             int from) const {
  const bool forward = dir == SCATTER_FORWARD;
  if (windowIsLocal_ && (mode == INSERT_VALUES || mode == ADD_VALUES)) {
    const PetscInt i0 = windowLevelStart(from), n = D * nSlots;
    const PetscScalar *x = nullptr;
    PetscScalar *y = nullptr;
    PetscInt nw = 0, ng = 0;
    PetscCall(VecGetLocalSize(window, &nw));
    PetscCall(VecGetLocalSize(global, &ng));
    PetscCheck(nw == n && ng == n, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ,
               "a move between the window and a global Vec of another layout");
    PetscCall(VecGetArrayRead(forward ? global : window, &x));
    PetscCall(VecGetArray(forward ? window : global, &y));
    if (mode == INSERT_VALUES)
      std::copy(x + i0, x + n, y + i0);
    else
      for (PetscInt i = i0; i < n; ++i)
        y[i] += x[i];
    PetscCall(VecRestoreArray(forward ? window : global, &y));
    PetscCall(VecRestoreArrayRead(forward ? global : window, &x));
    return PETSC_SUCCESS;
  }
  if (from == 0) {
    PetscCall(
        VecScatterBegin(scatter_, forward ? global : window, forward ? window : global, mode, dir));
    PetscCall(
        VecScatterEnd(scatter_, forward ? global : window, forward ? window : global, mode, dir));
    return PETSC_SUCCESS;
  }
  // Levels from, from + 1, ...: their scatter, its window Vec on this window's array from there.
  VecScatter sc = nullptr;
  Vec w = nullptr;
  PetscCall(suffixScatter(from, &sc, &w));
  PetscScalar *a = nullptr;
  PetscCall(VecGetArray(window, &a));
  PetscCall(VecPlaceArray(w, a + windowLevelStart(from)));
  PetscCall(VecScatterBegin(sc, forward ? global : w, forward ? w : global, mode, dir));
  PetscCall(VecScatterEnd(sc, forward ? global : w, forward ? w : global, mode, dir));
  PetscCall(VecResetArray(w));
  PetscCall(VecRestoreArray(window, &a));
  return PETSC_SUCCESS;
}

template <int D> PetscMPIInt Grid<D>::ownerOf(const double *x) const {
  const Level<D> &L = levels[0];
  PetscInt rank = 0;
  for (int a = D - 1; a >= 0; --a) { // ranks are numbered x fastest
    const PetscInt c = std::clamp<PetscInt>(
        static_cast<PetscInt>(std::floor((x[a] - origin[a]) / L.h)), 0, L.n[a] - 1);
    const auto r = std::upper_bound(own_[a].begin(), own_[a].end(), c) - own_[a].begin() - 1;
    rank = rank * (static_cast<PetscInt>(own_[a].size()) - 1) + r;
  }
  return static_cast<PetscMPIInt>(rank);
}

template <int D> void Grid<D>::ownedBox(PetscMPIInt r, double box[2 * D]) const {
  const Level<D> &L = levels[0];
  const double inf = std::numeric_limits<double>::infinity();
  PetscInt rest = r;
  for (int a = 0; a < D; ++a) {
    const PetscInt nr = static_cast<PetscInt>(own_[a].size()) - 1, ra = rest % nr;
    rest /= nr;
    box[a] = own_[a][ra] == 0 ? -inf : origin[a] + own_[a][ra] * L.h;
    box[D + a] = own_[a][ra + 1] >= L.n[a] ? inf : origin[a] + own_[a][ra + 1] * L.h;
  }
}

template class Grid<2>;
template class Grid<3>;

} // namespace gimp
