#include "gimp/grid.hpp"

#include "gimp/shape.hpp"

#include <petscao.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace gimp {

namespace {

std::string boxText(const Box &b) {
  return formatNumber(b[0]) + "," + formatNumber(b[1]) + "," + formatNumber(b[2]) + "," +
         formatNumber(b[3]);
}

/// floor and ceil to an integer without a libm call (the hot loop of buildStencils).
inline PetscInt ifloor(double v) {
  const PetscInt i = static_cast<PetscInt>(v);
  return i - (v < static_cast<double>(i));
}
inline PetscInt iceil(double v) {
  const PetscInt i = static_cast<PetscInt>(v);
  return i + (v > static_cast<double>(i));
}

/// Whether c / d is an integer (relative tolerance 1e-9); if so, m is set to it.
bool wholeMultiple(double c, double d, std::int64_t &m) {
  const double q = c / d;
  const double r = std::round(q);
  if (std::fabs(q - r) > 1e-9 * std::max(1.0, std::fabs(q))) return false;
  m = static_cast<std::int64_t>(r);
  return true;
}

} // namespace

Grid::~Grid() {
  for (Level &L : levels) {
    if (L.da) (void)DMDestroy(&L.da);
    if (L.da1) (void)DMDestroy(&L.da1);
  }
  if (dm) (void)DMDestroy(&dm);
  if (scatter_) (void)VecScatterDestroy(&scatter_);
  if (windowTemplate_) (void)VecDestroy(&windowTemplate_);
}

void Grid::setGeometry(const Scene &sc) {
  const size_t K = sc.levels.size();
  x0 = sc.domain[0];
  y0 = sc.domain[1];
  // Finest-lattice unit: h0 / (r1 r2 ...). Every node lies on this lattice.
  std::int64_t total = 1;
  for (size_t k = 1; k < K; ++k)
    total *= sc.levels[k].ratio;
  unit = sc.h / static_cast<double>(total);
  levels.assign(K, Level{});
  std::int64_t step = total;
  double h = sc.h;
  for (size_t k = 0; k < K; ++k) {
    Level &L = levels[k];
    if (k > 0) {
      step /= sc.levels[k].ratio;
      h /= sc.levels[k].ratio;
    }
    L.h = h;
    L.step = step;
    L.box = k == 0 ? sc.domain : sc.levels[k].box;
    const std::string opt = "option -gimp_level" + std::to_string(k) + "_box " + boxText(L.box);
    std::int64_t c[4];
    for (int d = 0; d < 4; ++d) {
      const double o = d % 2 == 0 ? x0 : y0;
      // Corners on the parent's grid lines (level 0: whole cells of h0 from the origin).
      const double parentH = k == 0 ? sc.h : levels[k - 1].h;
      std::int64_t m = 0;
      if (!wholeMultiple(L.box[d] - o, parentH, m))
        throw InputError(opt + ": corner coordinate " + formatNumber(L.box[d]) +
                         " is not on a grid line of level " + std::to_string(k ? k - 1 : 0) +
                         " (lines at " + formatNumber(o) + " + i * " + formatNumber(parentH) + ")");
      c[d] = m * (k == 0 ? total : levels[k - 1].step);
    }
    L.u0 = c[0];
    L.v0 = c[1];
    L.u1 = c[2];
    L.v1 = c[3];
    if (L.u1 <= L.u0 || L.v1 <= L.v0) throw InputError(opt + ": needs x1 > x0 and y1 > y0");
    if (k > 0) {
      const Level &P = levels[k - 1];
      if (L.u0 < P.u0 || L.v0 < P.v0 || L.u1 > P.u1 || L.v1 > P.v1)
        throw InputError(opt + ": not inside level " + std::to_string(k - 1) + "'s box " +
                         boxText(P.box) + " (levels must be nested)");
    }
    L.M = static_cast<PetscInt>((L.u1 - L.u0) / L.step) + 1;
    L.N = static_cast<PetscInt>((L.v1 - L.v0) / L.step) + 1;
  }
}

int Grid::leafLevelAt2(std::int64_t a, std::int64_t b) const {
  const Level &D = levels.front();
  if (a < 2 * D.u0 || a > 2 * D.u1 || b < 2 * D.v0 || b > 2 * D.v1) return -1;
  for (int k = static_cast<int>(levels.size()) - 1; k > 0; --k) {
    const Level &L = levels[k];
    if (a > 2 * L.u0 && a < 2 * L.u1 && b > 2 * L.v0 && b < 2 * L.v1) return k;
  }
  return 0;
}

int Grid::leafLevelAt(double x, double y) const {
  for (int k = static_cast<int>(levels.size()) - 1; k > 0; --k) {
    const Box &b = levels[k].box;
    if (x > b[0] && x < b[2] && y > b[1] && y < b[3]) return k;
  }
  return 0;
}

bool Grid::nodeActive(int k, std::int64_t i, std::int64_t j) const {
  const Level &L = levels[k];
  const std::int64_t u = L.u0 + i * L.step, v = L.v0 + j * L.step;
  // The node belongs to the finest level whose closed box contains it.
  for (int q = static_cast<int>(levels.size()) - 1; q > k; --q) {
    const Level &F = levels[q];
    if (u >= F.u0 && u <= F.u1 && v >= F.v0 && v <= F.v1) return false;
  }
  return true;
}

void Grid::zonesOf(int k, std::int64_t i, std::int64_t j, double z[4]) const {
  const Level &L = levels[k];
  const std::int64_t a = 2 * (L.u0 + i * L.step), b = 2 * (L.v0 + j * L.step);
  // Width of the leaf cell containing the point (a + da, b + db), or +inf outside the domain.
  auto width = [&](int da, int db) {
    const int q = leafLevelAt2(a + da, b + db);
    return q < 0 ? std::numeric_limits<double>::infinity() : levels[q].h;
  };
  const double side[4][2] = {{width(-1, -1), width(-1, 1)}, // Lx-
                             {width(1, -1), width(1, 1)},   // Lx+
                             {width(-1, -1), width(1, -1)}, // Ly-
                             {width(-1, 1), width(1, 1)}};  // Ly+
  for (int s = 0; s < 4; ++s) {
    const double w = std::min(side[s][0], side[s][1]);
    z[s] = std::isinf(w) ? 0.0 : w;
  }
}

std::int64_t Grid::activeNodes(int k) const {
  const Level &L = levels[k];
  std::int64_t n = 0;
  for (PetscInt j = 0; j < L.N; ++j)
    for (PetscInt i = 0; i < L.M; ++i)
      n += nodeActive(k, i, j);
  return n;
}

PetscErrorCode Grid::create(MPI_Comm comm, const Scene &sc) {
  setGeometry(sc);
  PetscMPIInt rank = 0, size = 1;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  const int K = static_cast<int>(levels.size());

  // Level 0 decides the rank layout (and owns the particles); finer levels are DMDAs of their
  // own, partitioned by PETSc: the window scatter reaches whatever nodes a rank needs.
  PetscCall(DMCompositeCreate(comm, &dm));
  for (int k = 0; k < K; ++k) {
    Level &L = levels[k];
    PetscCall(DMDACreate2d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX, L.M, L.N,
                           PETSC_DECIDE, PETSC_DECIDE, 2, 0, nullptr, nullptr, &L.da));
    if (k == 0) PetscCall(DMSetFromOptions(L.da)); // -da_processors_x/y choose the rank layout
    PetscCall(DMSetUp(L.da));
    PetscCall(DMDASetFieldName(L.da, 0, "x"));
    PetscCall(DMDASetFieldName(L.da, 1, "y"));
    PetscCall(DMDASetUniformCoordinates(L.da, L.box[0], L.box[2], L.box[1], L.box[3], 0, 0));
    PetscCall(DMDACreateCompatibleDMDA(L.da, 1, &L.da1));
    PetscCall(DMCompositeAddDM(dm, L.da));
  }
  PetscCall(DMSetUp(dm));

  // Level-0 ownership of nodes; a rank owns the cells whose lower-left node it owns.
  {
    PetscInt px = 0, py = 0;
    const PetscInt *lx = nullptr, *ly = nullptr;
    PetscCall(DMDAGetInfo(levels[0].da, nullptr, nullptr, nullptr, nullptr, &px, &py, nullptr,
                          nullptr, nullptr, nullptr, nullptr, nullptr, nullptr));
    PetscCall(DMDAGetOwnershipRanges(levels[0].da, &lx, &ly, nullptr));
    ownX_.assign(px + 1, 0);
    ownY_.assign(py + 1, 0);
    for (PetscInt r = 0; r < px; ++r)
      ownX_[r + 1] = ownX_[r] + lx[r];
    for (PetscInt r = 0; r < py; ++r)
      ownY_[r + 1] = ownY_[r] + ly[r];
  }
  PetscInt xs = 0, ys = 0, xm = 0, ym = 0;
  PetscCall(DMDAGetCorners(levels[0].da, &xs, &ys, nullptr, &xm, &ym, nullptr));
  // Window: level-0 nodes [xs - 2, xs + xm + 2) in each direction, as lattice units.
  const Level &L0 = levels[0];
  const std::int64_t wu0 = L0.u0 + std::max<std::int64_t>(xs - 2, 0) * L0.step;
  const std::int64_t wu1 = L0.u0 + std::min<std::int64_t>(xs + xm + 1, L0.M - 1) * L0.step;
  const std::int64_t wv0 = L0.v0 + std::max<std::int64_t>(ys - 2, 0) * L0.step;
  const std::int64_t wv1 = L0.v0 + std::min<std::int64_t>(ys + ym + 1, L0.N - 1) * L0.step;
  nWindow = 0;
  for (Level &L : levels) {
    auto lo = [&](std::int64_t w, std::int64_t o) {
      return static_cast<PetscInt>(std::max<std::int64_t>(0, (w - o + L.step - 1) / L.step));
    };
    L.wi0 = std::min(lo(wu0, L.u0), L.M);
    L.wj0 = std::min(lo(wv0, L.v0), L.N);
    L.wi1 = wu1 < L.u0
                ? 0
                : static_cast<PetscInt>(std::min<std::int64_t>((wu1 - L.u0) / L.step + 1, L.M));
    L.wj1 = wv1 < L.v0
                ? 0
                : static_cast<PetscInt>(std::min<std::int64_t>((wv1 - L.v0) / L.step + 1, L.N));
    if (L.wi1 < L.wi0) L.wi1 = L.wi0;
    if (L.wj1 < L.wj0) L.wj1 = L.wj0;
    L.offset = nWindow;
    nWindow += (L.wi1 - L.wi0) * (L.wj1 - L.wj0);
  }

  // Node data of the window.
  active.assign(nWindow, 0);
  regular.assign(nWindow, 0);
  flags_.assign(nWindow, 0);
  X.assign(nWindow, 0);
  Y.assign(nWindow, 0);
  zone.assign(4 * static_cast<size_t>(nWindow), 0);
  for (int k = 0; k < K; ++k) {
    const Level &L = levels[k];
    for (PetscInt j = L.wj0; j < L.wj1; ++j)
      for (PetscInt i = L.wi0; i < L.wi1; ++i) {
        const PetscInt n = L.offset + (j - L.wj0) * L.wnx() + (i - L.wi0);
        X[n] = x0 + static_cast<double>(L.u0 + i * L.step) * unit;
        Y[n] = y0 + static_cast<double>(L.v0 + j * L.step) * unit;
        active[n] = nodeActive(k, i, j);
        if (!active[n]) continue;
        zonesOf(k, i, j, &zone[4 * n]);
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
    for (PetscInt j = L.wj0; j + 2 < L.wj1; ++j)
      for (PetscInt i = L.wi0; i + 2 < L.wi1; ++i) {
        bool ok = true;
        for (PetscInt b = 0; b < 3; ++b)
          for (PetscInt a = 0; a < 3; ++a)
            ok = ok && regular[L.offset + (j + b - L.wj0) * L.wnx() + (i + a - L.wi0)];
        block3_[L.offset + (j - L.wj0) * L.wnx() + (i - L.wi0)] = ok;
      }
  }

  // Scatter between the composite global Vec and the window: composite index of each window
  // node. A composite's local part is rank r's owned part of level 0, then of level 1, ...
  std::vector<std::vector<PetscInt>> levelStart(K); // level node ownership starts per rank
  std::vector<PetscInt> compStart(size + 1, 0);
  for (int k = 0; k < K; ++k) {
    Vec g;
    const PetscInt *ranges = nullptr;
    PetscCall(DMGetGlobalVector(levels[k].da, &g));
    PetscCall(VecGetOwnershipRanges(g, &ranges));
    levelStart[k].assign(ranges, ranges + size + 1);
    for (auto &v : levelStart[k])
      v /= 2;
    PetscCall(DMRestoreGlobalVector(levels[k].da, &g));
  }
  for (int r = 0; r < size; ++r) {
    PetscInt s = 0;
    for (int k = 0; k < K; ++k)
      s += levelStart[k][r + 1] - levelStart[k][r];
    compStart[r + 1] = compStart[r] + s;
  }
  std::vector<PetscInt> blocks(nWindow);
  for (int k = 0; k < K; ++k) {
    const Level &L = levels[k];
    const PetscInt n = (L.wi1 - L.wi0) * (L.wj1 - L.wj0);
    std::vector<PetscInt> idx(n);
    for (PetscInt j = L.wj0; j < L.wj1; ++j)
      for (PetscInt i = L.wi0; i < L.wi1; ++i)
        idx[(j - L.wj0) * L.wnx() + (i - L.wi0)] = 2 * (j * L.M + i); // the AO counts dofs
    AO ao;
    PetscCall(DMDAGetAO(L.da, &ao));
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
  PetscCall(ISCreateBlock(comm, 2, nWindow, blocks.data(), PETSC_COPY_VALUES, &is));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2 * nWindow, &windowTemplate_));
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

PetscErrorCode Grid::toWindow(Vec global, Vec window) const {
  PetscCall(VecScatterBegin(scatter_, global, window, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(scatter_, global, window, INSERT_VALUES, SCATTER_FORWARD));
  return PETSC_SUCCESS;
}

PetscErrorCode Grid::addFromWindow(Vec window, Vec global) const {
  PetscCall(VecScatterBegin(scatter_, window, global, ADD_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(scatter_, window, global, ADD_VALUES, SCATTER_REVERSE));
  return PETSC_SUCCESS;
}

PetscMPIInt Grid::ownerOf(double x, double y) const {
  const Level &L = levels[0];
  const PetscInt ic =
      std::clamp<PetscInt>(static_cast<PetscInt>(std::floor((x - x0) / L.h)), 0, L.M - 1);
  const PetscInt jc =
      std::clamp<PetscInt>(static_cast<PetscInt>(std::floor((y - y0) / L.h)), 0, L.N - 1);
  const auto rx = std::upper_bound(ownX_.begin(), ownX_.end(), ic) - ownX_.begin() - 1;
  const auto ry = std::upper_bound(ownY_.begin(), ownY_.end(), jc) - ownY_.begin() - 1;
  return static_cast<PetscMPIInt>(ry * (static_cast<PetscInt>(ownX_.size()) - 1) + rx); // x fastest
}

void Grid::ownedBox(PetscMPIInt r, double box[4]) const {
  const Level &L = levels[0];
  const PetscInt nrx = static_cast<PetscInt>(ownX_.size()) - 1, rx = r % nrx, ry = r / nrx;
  const double inf = std::numeric_limits<double>::infinity();
  box[0] = ownX_[rx] == 0 ? -inf : x0 + ownX_[rx] * L.h;
  box[1] = ownY_[ry] == 0 ? -inf : y0 + ownY_[ry] * L.h;
  box[2] = ownX_[rx + 1] >= L.M ? inf : x0 + ownX_[rx + 1] * L.h;
  box[3] = ownY_[ry + 1] >= L.N ? inf : y0 + ownY_[ry + 1] * L.h;
}

void Grid::buildStencils(PetscInt n, const double *x, const double *l, Stencils &s) const {
  s.start.resize(static_cast<size_t>(n) + 1);
  size_t m = 0;
  auto reserve = [&s](size_t want) {
    if (s.node.size() >= want) return;
    const size_t cap = std::max(want, s.node.size() + s.node.size() / 2);
    s.node.resize(cap);
    s.wx.resize(cap);
    s.wy.resize(cap);
    s.gx.resize(cap);
    s.gy.resize(cap);
  };
  reserve(10 * static_cast<size_t>(n)); // grows below if a step needs more
  const int K = static_cast<int>(levels.size());
  const double hmax = levels[0].h;
  // A candidate range spans at most 2 (l + Z) / h + 1 nodes with l, Z <= h0 (l is checked
  // every step): size the scratch for the finest level.
  const PetscInt maxRange = static_cast<PetscInt>(4.0 * hmax / levels.back().h) + 4;
  std::vector<double> scratch(4 * static_cast<size_t>(maxRange));
  double *rwx = scratch.data(), *rgx = rwx + maxRange, *rwy = rgx + maxRange, *rgy = rwy + maxRange;
  for (PetscInt k = 0; k < n; ++k) {
    s.start[k] = static_cast<PetscInt>(m);
    const double xp = x[2 * k], yp = x[2 * k + 1], lx = l[2 * k], ly = l[2 * k + 1];
    for (int q = 0; q < K; ++q) {
      const Level &L = levels[q];
      if (L.wi1 <= L.wi0 || L.wj1 <= L.wj0) continue;
      // Inside its box a level's nodes reach a particle by at most h; from outside, its
      // boundary nodes reach out by the coarse cell width (at most h0).
      const bool inside = xp >= L.box[0] && xp <= L.box[2] && yp >= L.box[1] && yp <= L.box[3];
      const double Z = inside ? L.h : hmax;
      const double ax = xp - lx - Z, bx = xp + lx + Z, ay = yp - ly - Z, by = yp + ly + Z;
      if (q + 1 < K) { // everything in reach covered by the finer box: no active node here
        const Box &f = levels[q + 1].box;
        if (ax >= f[0] && bx <= f[2] && ay >= f[1] && by <= f[3]) continue;
      }
      const double ox = L.box[0], oy = L.box[1], ih = 1.0 / L.h;
      const PetscInt ir = ifloor((ax - ox) * ih) + 1, jr = ifloor((ay - oy) * ih) + 1;
      const PetscInt i0 = std::max(ir, L.wi0);
      const PetscInt i1 = std::min(iceil((bx - ox) * ih) - 1, L.wi1 - 1);
      const PetscInt j0 = std::max(jr, L.wj0);
      const PetscInt j1 = std::min(iceil((by - oy) * ih) - 1, L.wj1 - 1);
      if (i1 < i0 || j1 < j0) continue;
      if (inside && ir == i0 && jr == j0 && i1 - i0 <= 2 && j1 - j0 <= 2 && i0 + 2 < L.wi1 &&
          j0 + 2 < L.wj1 && lx <= 0.5 * L.h && ly <= 0.5 * L.h &&
          block3_[L.offset + (j0 - L.wj0) * L.wnx() + (i0 - L.wi0)]) {
        // A regular 3 x 3 block of this level: closed-form weights, the same node set.
        double fwx[3], fgx[3], fwy[3], fgy[3];
        const double lamx = lx * ih, lamy = ly * ih, i2lx = 0.5 / lamx, i2ly = 0.5 / lamy;
        shape::uniformWeights3((xp - (ox + i0 * L.h)) * ih, lamx, i2lx, i2lx * ih, fwx, fgx);
        shape::uniformWeights3((yp - (oy + j0 * L.h)) * ih, lamy, i2ly, i2ly * ih, fwy, fgy);
        reserve(m + 9);
        PetscInt *node = s.node.data();
        double *wxs = s.wx.data(), *wys = s.wy.data(), *gxs = s.gx.data(), *gys = s.gy.data();
        for (PetscInt j = j0; j <= j1; ++j) {
          const PetscInt row = L.offset + (j - L.wj0) * L.wnx() - L.wi0;
          for (PetscInt i = i0; i <= i1; ++i) {
            node[m] = row + i;
            wxs[m] = fwx[i - i0];
            gxs[m] = fgx[i - i0];
            wys[m] = fwy[j - j0];
            gys[m] = fgy[j - j0];
            ++m;
          }
        }
        continue;
      }
      if (i1 - i0 >= maxRange || j1 - j0 >= maxRange) // only for a particle larger than h0
        throw InputError("particle at (" + formatNumber(xp) + ", " + formatNumber(yp) +
                         ") with half-size (" + formatNumber(lx) + ", " + formatNumber(ly) +
                         ") is larger than a level-0 cell");
      const double i2lx = 0.5 / lx, i2ly = 0.5 / ly;
      for (PetscInt i = i0; i <= i1; ++i)
        shape::weightAndGradientUniform(xp - (ox + i * L.h), lx, L.h, ih, i2lx, rwx[i - i0],
                                        rgx[i - i0]);
      for (PetscInt j = j0; j <= j1; ++j)
        shape::weightAndGradientUniform(yp - (oy + j * L.h), ly, L.h, ih, i2ly, rwy[j - j0],
                                        rgy[j - j0]);
      reserve(m + static_cast<size_t>((i1 - i0 + 1) * (j1 - j0 + 1)));
      PetscInt *node = s.node.data();
      double *wxs = s.wx.data(), *wys = s.wy.data(), *gxs = s.gx.data(), *gys = s.gy.data();
      for (PetscInt j = j0; j <= j1; ++j) {
        const PetscInt row = L.offset + (j - L.wj0) * L.wnx() - L.wi0;
        for (PetscInt i = i0; i <= i1; ++i) {
          const PetscInt nd = row + i;
          const std::uint8_t f = flags_[nd];
          double wx, gx, wy, gy;
          if (f == (kActive | kRegular) && inside) {
            // Inside the box the candidate range is exactly the overlap range.
            wx = rwx[i - i0];
            gx = rgx[i - i0];
            wy = rwy[j - j0];
            gy = rgy[j - j0];
          } else if (f & kActive) {
            const double dx = xp - X[nd], dy = yp - Y[nd];
            const double *z = &zone[4 * nd];
            if (!shape::overlaps(dx, lx, z[0], z[1]) || !shape::overlaps(dy, ly, z[2], z[3]))
              continue;
            if (f & kRegular) {
              wx = rwx[i - i0];
              gx = rgx[i - i0];
              wy = rwy[j - j0];
              gy = rgy[j - j0];
            } else {
              shape::weightAndGradient(dx, lx, z[0], z[1], wx, gx);
              shape::weightAndGradient(dy, ly, z[2], z[3], wy, gy);
            }
          } else {
            continue;
          }
          node[m] = nd;
          wxs[m] = wx;
          wys[m] = wy;
          gxs[m] = gx;
          gys[m] = gy;
          ++m;
        }
      }
    }
  }
  s.start[n] = static_cast<PetscInt>(m);
}

PetscInt Grid::lineIndex(int axis, double c) const {
  const Level &L = levels[0];
  const double o = axis == 0 ? x0 : y0;
  const PetscInt n = axis == 0 ? L.M : L.N;
  std::int64_t i = 0;
  if (!wholeMultiple(c - o, L.h, i) || i < 0 || i >= n) return -1;
  return static_cast<PetscInt>(i);
}

PetscErrorCode Grid::dump(MPI_Comm comm, const std::string &file) const {
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank != 0) return PETSC_SUCCESS;
  FILE *f = std::fopen(file.c_str(), "w");
  if (!f) throw InputError("option -gimp_grid_dump " + file + ": cannot open the file for writing");
  std::fprintf(f, "level,x,y,Lxm,Lxp,Lym,Lyp\n");
  for (int k = 0; k < static_cast<int>(levels.size()); ++k) {
    const Level &L = levels[k];
    for (PetscInt j = 0; j < L.N; ++j)
      for (PetscInt i = 0; i < L.M; ++i) {
        if (!nodeActive(k, i, j)) continue;
        double z[4];
        zonesOf(k, i, j, z);
        std::fprintf(f, "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", k,
                     x0 + static_cast<double>(L.u0 + i * L.step) * unit,
                     y0 + static_cast<double>(L.v0 + j * L.step) * unit, z[0], z[1], z[2], z[3]);
      }
  }
  std::fclose(f);
  return PETSC_SUCCESS;
}

} // namespace gimp
