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

bool Grid::buildStencils(PetscInt n, const double *x, const double *l, Stencils<kDim> &s) const {
  s.start.resize(static_cast<size_t>(n) + 1);
  size_t m = 0;
  s.reserve(10 * static_cast<size_t>(n)); // grows below if a step needs more
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
        s.reserve(m + 9);
        PetscInt *node = s.node.data();
        double *wxs = s.w[0].data(), *wys = s.w[1].data(), *gxs = s.g[0].data(),
               *gys = s.g[1].data();
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
      if (i1 - i0 >= maxRange || j1 - j0 >= maxRange) { // only for a particle larger than h0
        s.start[k + 1] = static_cast<PetscInt>(m);
        return false;
      }
      const double i2lx = 0.5 / lx, i2ly = 0.5 / ly;
      for (PetscInt i = i0; i <= i1; ++i)
        shape::weightAndGradientUniform(xp - (ox + i * L.h), lx, L.h, ih, i2lx, rwx[i - i0],
                                        rgx[i - i0]);
      for (PetscInt j = j0; j <= j1; ++j)
        shape::weightAndGradientUniform(yp - (oy + j * L.h), ly, L.h, ih, i2ly, rwy[j - j0],
                                        rgy[j - j0]);
      s.reserve(m + static_cast<size_t>((i1 - i0 + 1) * (j1 - j0 + 1)));
      PetscInt *node = s.node.data();
      double *wxs = s.w[0].data(), *wys = s.w[1].data(), *gxs = s.g[0].data(), *gys = s.g[1].data();
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
  return true;
}

} // namespace gimp
