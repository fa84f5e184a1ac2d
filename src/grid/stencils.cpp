// Stencils of particles on the composite grid: for each particle the active nodes whose support
// overlaps it, with the 1D GIMP weights and gradients of Eq. 15 along x and y.
#include "gimp/grid/grid.hpp"
#include "gimp/grid/shape.hpp"

#include <algorithm>
#include <vector>

namespace gimp {

namespace {

/// floor and ceil to an integer without a libm call (the hot loop of buildStencils).
inline PetscInt ifloor(double v) {
  const PetscInt i = static_cast<PetscInt>(v);
  return i - (v < static_cast<double>(i));
}
inline PetscInt iceil(double v) {
  const PetscInt i = static_cast<PetscInt>(v);
  return i + (v > static_cast<double>(i));
}

} // namespace

bool Grid::levelReach(int q, double xp, double yp, double lx, double ly, Reach &r) const {
  const Level &L = levels[q];
  if (L.w1[0] <= L.w0[0] || L.w1[1] <= L.w0[1]) return false;
  // Inside its box a level's nodes reach a particle by at most h; from outside, its boundary
  // nodes reach out by the coarse cell width (at most h0).
  r.inside = xp >= L.box[0] && xp <= L.box[2] && yp >= L.box[1] && yp <= L.box[3];
  const double Z = r.inside ? L.h : levels[0].h;
  const double ax = xp - lx - Z, bx = xp + lx + Z, ay = yp - ly - Z, by = yp + ly + Z;
  if (q + 1 < static_cast<int>(levels.size())) {
    // Everything in reach covered by the finer box: no active node of this level.
    const Box &f = levels[q + 1].box;
    if (ax >= f[0] && bx <= f[2] && ay >= f[1] && by <= f[3]) return false;
  }
  const double ox = L.box[0], oy = L.box[1], ih = L.ih;
  const PetscInt ir = ifloor((ax - ox) * ih) + 1, jr = ifloor((ay - oy) * ih) + 1;
  r.i0 = std::max(ir, L.w0[0]);
  r.i1 = std::min(iceil((bx - ox) * ih) - 1, L.w1[0] - 1);
  r.j0 = std::max(jr, L.w0[1]);
  r.j1 = std::min(iceil((by - oy) * ih) - 1, L.w1[1] - 1);
  if (r.i1 < r.i0 || r.j1 < r.j0) return false;
  r.block3 = r.inside && ir == r.i0 && jr == r.j0 && r.i1 - r.i0 <= 2 && r.j1 - r.j0 <= 2 &&
             r.i0 + 2 < L.w1[0] && r.j0 + 2 < L.w1[1] && lx <= 0.5 * L.h && ly <= 0.5 * L.h &&
             block3_[L.offset + (r.j0 - L.w0[1]) * L.wnx() + (r.i0 - L.w0[0])];
  return true;
}

void Grid::appendBlock3(const Level &L, const Reach &r, double xp, double yp, double lx, double ly,
                        Stencils<kDim> &s, size_t &m) const {
  // A regular 3 x 3 block of this level: closed-form weights, the same node set.
  const double ih = L.ih, ox = L.box[0], oy = L.box[1];
  double fwx[3], fgx[3], fwy[3], fgy[3];
  const double lamx = lx * ih, lamy = ly * ih, i2lx = 0.5 / lamx, i2ly = 0.5 / lamy;
  shape::uniformWeights3((xp - (ox + r.i0 * L.h)) * ih, lamx, i2lx, i2lx * ih, fwx, fgx);
  shape::uniformWeights3((yp - (oy + r.j0 * L.h)) * ih, lamy, i2ly, i2ly * ih, fwy, fgy);
  s.reserve(m + 9);
  PetscInt *node = s.node.data();
  double *wxs = s.w[0].data(), *wys = s.w[1].data(), *gxs = s.g[0].data(), *gys = s.g[1].data();
  for (PetscInt j = r.j0; j <= r.j1; ++j) {
    const PetscInt row = L.offset + (j - L.w0[1]) * L.wnx() - L.w0[0];
    for (PetscInt i = r.i0; i <= r.i1; ++i) {
      node[m] = row + i;
      wxs[m] = fwx[i - r.i0];
      gxs[m] = fgx[i - r.i0];
      wys[m] = fwy[j - r.j0];
      gys[m] = fgy[j - r.j0];
      ++m;
    }
  }
}

void Grid::appendNodes(const Level &L, const Reach &r, double xp, double yp, double lx, double ly,
                       double *scratch, PetscInt maxRange, Stencils<kDim> &s, size_t &m) const {
  // Any range of nodes: 1D weights of a regular stretch for every candidate, replaced by the
  // node's own zones where it is irregular; nodes whose support misses the particle are left out.
  double *rwx = scratch, *rgx = rwx + maxRange, *rwy = rgx + maxRange, *rgy = rwy + maxRange;
  const double ox = L.box[0], oy = L.box[1], ih = L.ih;
  const double i2lx = 0.5 / lx, i2ly = 0.5 / ly;
  for (PetscInt i = r.i0; i <= r.i1; ++i)
    shape::weightAndGradientUniform(xp - (ox + i * L.h), lx, L.h, ih, i2lx, rwx[i - r.i0],
                                    rgx[i - r.i0]);
  for (PetscInt j = r.j0; j <= r.j1; ++j)
    shape::weightAndGradientUniform(yp - (oy + j * L.h), ly, L.h, ih, i2ly, rwy[j - r.j0],
                                    rgy[j - r.j0]);
  s.reserve(m + static_cast<size_t>((r.i1 - r.i0 + 1) * (r.j1 - r.j0 + 1)));
  PetscInt *node = s.node.data();
  double *wxs = s.w[0].data(), *wys = s.w[1].data(), *gxs = s.g[0].data(), *gys = s.g[1].data();
  for (PetscInt j = r.j0; j <= r.j1; ++j) {
    const PetscInt row = L.offset + (j - L.w0[1]) * L.wnx() - L.w0[0];
    for (PetscInt i = r.i0; i <= r.i1; ++i) {
      const PetscInt nd = row + i;
      const std::uint8_t f = flags_[nd];
      double wx = rwx[i - r.i0], gx = rgx[i - r.i0], wy = rwy[j - r.j0], gy = rgy[j - r.j0];
      if (!(f & kActive)) continue;
      if (f != (kActive | kRegular) || !r.inside) {
        // Outside the box the candidate range is wider than the overlap range.
        const double dx = xp - X[nd], dy = yp - Y[nd];
        const double *z = &zone[4 * nd];
        if (!shape::overlaps(dx, lx, z[0], z[1]) || !shape::overlaps(dy, ly, z[2], z[3])) continue;
        if (!(f & kRegular)) {
          shape::weightAndGradient(dx, lx, z[0], z[1], wx, gx);
          shape::weightAndGradient(dy, ly, z[2], z[3], wy, gy);
        }
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

bool Grid::buildStencils(PetscInt n, const double *x, const double *l, Stencils<kDim> &s,
                         bool compact) const {
  const int K = static_cast<int>(levels.size());
  s.start.resize(static_cast<size_t>(n) + 1);
  s.general = false;
  s.compact = compact;
  if (compact) {
    s.blockOf.resize(static_cast<size_t>(n));
    s.nBlocks = 0;
  }
  size_t m = 0;
  // Rows: room for the previous step's entries (or 10 per particle); grows below if needed.
  if (!compact) s.reserve(10 * static_cast<size_t>(n));
  // A candidate range spans at most 2 (l + Z) / h + 1 nodes with l, Z <= h0 (l is checked
  // every step): size the scratch for the finest level.
  const PetscInt maxRange = static_cast<PetscInt>(4.0 * levels[0].h / levels.back().h) + 4;
  std::vector<double> scratch(4 * static_cast<size_t>(maxRange));
  std::vector<Reach> reach(K);
  std::vector<char> reaches(K);
  for (PetscInt k = 0; k < n; ++k) {
    s.start[k] = static_cast<PetscInt>(m);
    const double xp = x[2 * k], yp = x[2 * k + 1], lx = l[2 * k], ly = l[2 * k + 1];
    int nReach = 0, last = -1;
    for (int q = 0; q < K; ++q) {
      reaches[q] = levelReach(q, xp, yp, lx, ly, reach[q]);
      if (reaches[q]) ++nReach, last = q;
    }
    if (compact) {
      s.blockOf[k] = -1;
      if (nReach == 1 && reach[last].block3) {
        // One level's regular 3 x 3 block: the arguments appendBlock3 gives
        // shape::uniformWeights3, so the factors are those the rows would hold.
        const Level &L = levels[last];
        const Reach &r = reach[last];
        const double xi[2] = {(xp - (L.box[0] + r.i0 * L.h)) * L.ih,
                              (yp - (L.box[1] + r.j0 * L.h)) * L.ih};
        const double lam[2] = {lx * L.ih, ly * L.ih};
        const PetscInt stride[2] = {1, L.wnx()};
        s.setBlock(k, L.offset + (r.j0 - L.w0[1]) * L.wnx() + (r.i0 - L.w0[0]), stride, xi, lam,
                   L.ih);
        continue;
      }
    }
    for (int q = 0; q < K; ++q) {
      if (!reaches[q]) continue;
      const Reach &r = reach[q];
      if (r.block3) {
        appendBlock3(levels[q], r, xp, yp, lx, ly, s, m);
        continue;
      }
      if (r.i1 - r.i0 >= maxRange || r.j1 - r.j0 >= maxRange) { // a particle larger than h0
        s.start[k + 1] = static_cast<PetscInt>(m);
        return false;
      }
      appendNodes(levels[q], r, xp, yp, lx, ly, scratch.data(), maxRange, s, m);
    }
  }
  s.start[n] = static_cast<PetscInt>(m);
  return true;
}

} // namespace gimp
