// Stencils kept as rows of entries (grid/stencils.hpp): a GIMP particle's rows on one level,
// for the particles that Grid::buildStencils (grid/stencils.cpp) keeps no block for
// (appendThreeNodeBlock, appendNodes), and the general entries of point and CPDI stencils.
//
// CPDI stencils (Sadeghirad et al. 2011, 2013): a particle's domain is the quadrilateral (2D) or
// hexahedron (3D) of its 2^D corners; its weights average the composite grid's point shape
// functions over it through the cell's bilinear or trilinear map, so they hold for rotated and
// sheared domains, which GIMP's axis-aligned boxes cannot represent.
#include "gimp/grid/cpdi_cells.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/grid/rounding.hpp"
#include "gimp/grid/shape.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace gimp {

namespace {

/// The tent of Eq. 14 at a point, with a point that lies on a domain-edge node (zone 0 on that
/// side) up to round-off put on it (the value from inside the domain).
inline double pointTent(double s, double Lm, double Lp, double eps) {
  if (Lp == 0.0 && s > 0.0 && s < eps) s = 0.0;
  if (Lm == 0.0 && s < 0.0 && s > -eps) s = 0.0;
  return shape::tent(s, Lm, Lp);
}

/// The quad's corner integrals: w[c] = integral of the bilinear corner function M_c over the
/// quad (2 x 2 Gauss on the map, exact: M_c det J is bi-quadratic in the reference square),
/// G[2c + a] = integral of d M_c / d x_a = half the outward normal times length of the two
/// edges at c. Returns the area.
double quadIntegrals(const double *c, double w[4], double G[8]) {
  static const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
  const double gp = 1.0 / std::sqrt(3.0);
  double area = 0;
  for (int q = 0; q < 4; ++q)
    w[q] = 0;
  for (int gx = 0; gx < 2; ++gx)
    for (int gy = 0; gy < 2; ++gy) {
      const double xi = gx ? gp : -gp, eta = gy ? gp : -gp;
      double J[4] = {0, 0, 0, 0}; // dx/dxi, dx/deta, dy/dxi, dy/deta
      for (int q = 0; q < 4; ++q) {
        const double dxi = 0.25 * sx[q] * (1 + sy[q] * eta), deta = 0.25 * sy[q] * (1 + sx[q] * xi);
        J[0] += dxi * c[2 * q];
        J[1] += deta * c[2 * q];
        J[2] += dxi * c[2 * q + 1];
        J[3] += deta * c[2 * q + 1];
      }
      const double det = J[0] * J[3] - J[1] * J[2];
      if (!(det > 0)) return 0; // inverted or collapsed somewhere
      for (int q = 0; q < 4; ++q)
        w[q] += 0.25 * (1 + sx[q] * xi) * (1 + sy[q] * eta) * det;
      area += det;
    }
  for (int q = 0; q < 4; ++q) {
    const int next = (q + 1) % 4, prev = (q + 3) % 4;
    G[2 * q] = 0.5 * (c[2 * next + 1] - c[2 * prev + 1]);
    G[2 * q + 1] = 0.5 * (c[2 * prev] - c[2 * next]);
  }
  return area;
}

/// The trilinear corner functions and their reference gradients at the 2 x 2 x 2 Gauss points
/// ([Gauss point][corner]): they depend on neither the corners nor the particle, so they are
/// tabulated once, with the expressions they were evaluated with.
struct HexGauss {
  double M[8][8], dM[8][8][3];
};
const HexGauss &hexGauss() {
  static const HexGauss T = [] {
    HexGauss t{};
    const double gp = 1.0 / std::sqrt(3.0);
    for (int g = 0; g < 8; ++g) {
      const double xi[3] = {g & 1 ? gp : -gp, g & 2 ? gp : -gp, g & 4 ? gp : -gp};
      for (int q = 0; q < 8; ++q) {
        double f[3], s[3];
        for (int a = 0; a < 3; ++a) {
          s[a] = cpdi::cornerSign<3>(q, a);
          f[a] = 0.5 * (1 + s[a] * xi[a]);
        }
        t.M[g][q] = f[0] * f[1] * f[2];
        t.dM[g][q][0] = 0.5 * s[0] * f[1] * f[2];
        t.dM[g][q][1] = 0.5 * s[1] * f[0] * f[2];
        t.dM[g][q][2] = 0.5 * s[2] * f[0] * f[1];
      }
    }
    return t;
  }();
  return T;
}

/// J[i][j] = dx_i / dxi_j of the map of corners c at a Gauss point (dM: its table row).
inline void hexJacobian(const double *c, const double (&dM)[8][3], double (&J)[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      J[i][j] = 0;
  for (int q = 0; q < 8; ++q)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        J[i][j] += c[3 * q + i] * dM[q][j];
}

/// The cofactor of J[i][j]; det J J^-T = cof.
inline double cofactor(const double (&J)[3][3], int i, int j) {
  const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
  return J[i1][j1] * J[i2][j2] - J[i1][j2] * J[i2][j1];
}

/// The hexahedron's corner integrals (corners in the order of cpdi::cornerSign<3>): the same
/// as quadIntegrals for the trilinear map, by 2 x 2 x 2 Gauss points, exact: M_c det J and
/// cof(J) grad_xi M_c (= det J grad_x M_c) are at most cubic in each reference coordinate.
/// w[c] = integral of M_c, G[3c + a] = integral of d M_c / d x_a; returns the volume, 0 when
/// the map folds (det J <= 0 at a Gauss point).
double hexIntegrals(const double *c, double w[8], double G[24]) {
  const HexGauss &T = hexGauss();
  double volume = 0;
  for (int q = 0; q < 8; ++q)
    w[q] = 0;
  for (int e = 0; e < 24; ++e)
    G[e] = 0;
  for (int g = 0; g < 8; ++g) {
    const double(&M)[8] = T.M[g];
    const double(&dM)[8][3] = T.dM[g];
    double J[3][3], cof[3][3];
    hexJacobian(c, dM, J);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        cof[i][j] = cofactor(J, i, j);
    const double det = J[0][0] * cof[0][0] + J[0][1] * cof[0][1] + J[0][2] * cof[0][2];
    if (!(det > 0)) return 0;
    volume += det;
    for (int q = 0; q < 8; ++q) {
      w[q] += M[q] * det;
      for (int i = 0; i < 3; ++i)
        G[3 * q + i] += cof[i][0] * dM[q][0] + cof[i][1] * dM[q][1] + cof[i][2] * dM[q][2];
    }
  }
  return volume;
}

/// The corner integrals of a particle's CPDI domain in D dimensions.
template <int D> double cellIntegrals(const double *c, double *w, double *G) {
  if constexpr (D == 2)
    return quadIntegrals(c, w, G);
  else
    return hexIntegrals(c, w, G);
}

/// appendNodes' 1D factors of irregular nodes. An irregular node's weight and gradient along axis
/// a depend on its index along a and its two zones there only, and the nodes of a transition
/// face share them: each (axis, index, zones) is weighed once (the values weightAndGradient
/// gives). Room: 4 D maxRange doubles.
template <int D> struct ZoneMemo {
  double *z[D], *w[D], *g[D];
  PetscInt n[D];
  bool ready = false; // (the zones' table is cleared at the first irregular factor)
  ZoneMemo(double *room, PetscInt maxRange, const PetscInt *i0, const PetscInt *i1) {
    for (int a = 0; a < D; ++a) {
      z[a] = room + 4 * a * maxRange;
      w[a] = z[a] + 2 * maxRange;
      g[a] = w[a] + maxRange;
      n[a] = i1[a] - i0[a] + 1;
    }
  }
  /// The factor along axis a of candidate index c at offset d, half-size l, zones za[0..1].
  bool mixed = false; // an index weighed for two sets of zones (not a tensor product)
  void factor(int a, PetscInt c, double d, double l, const double *za, double &wa, double &ga) {
    if (!ready) {
      for (int b = 0; b < D; ++b)
        std::fill(z[b], z[b] + 2 * n[b], -1.0); // (no zone is negative)
      ready = true;
    }
    double *m = z[a] + 2 * c;
    if (m[0] != za[0] || m[1] != za[1]) {
      mixed = mixed || m[0] >= 0;
      shape::weightAndGradient(d, l, za[0], za[1], w[a][c], g[a][c]);
      m[0] = za[0];
      m[1] = za[1];
    }
    wa = w[a][c];
    ga = g[a][c];
  }
};

/// A level block: the entries `mask` (bit c0 + 4 c1 + 16 c2) of a candidate box from window slot
/// `base` (row strides sy, sz), whose indices along axis a that hold an entry (bits of any[a])
/// have the factors fw[a][c], fg[a][c]; the block starts at the first of them along each axis.
template <int D>
void setLevelBlock(LevelBlock<D> &b, std::uint64_t mask, PetscInt base, PetscInt sy, PetscInt sz,
                   const unsigned *any, const double (*fw)[4], const double (*fg)[4]) {
  b.base = base;
  int lo[D];
  for (int a = 0; a < D; ++a) {
    lo[a] = __builtin_ctz(any[a]);
    const int hi = 31 - __builtin_clz(any[a]);
    for (int i = 0; i < 4; ++i) {
      const int ca = lo[a] + i;
      const bool entry = ca <= hi && ((any[a] >> ca) & 1u);
      b.w[a][i] = entry ? fw[a][ca] : 0.0;
      b.g[a][i] = entry ? fg[a][ca] : 0.0;
    }
    b.n[a] = static_cast<std::uint8_t>(hi - lo[a] + 1);
    b.base += lo[a] * (a == 0 ? 1 : a == 1 ? sy : sz);
    if (a > 0) b.stride[a - 1] = a == 1 ? sy : sz;
  }
  b.mask = mask >> (lo[0] + 4 * lo[1] + (D == 3 ? 16 * lo[D - 1] : 0));
  b.last = 0;
}

} // namespace

namespace cpdi {

double hexVolume(const double *c) {
  // hexIntegrals' volume (the same sums in the same order) without its corner integrals
  const HexGauss &T = hexGauss();
  double volume = 0;
  for (int g = 0; g < 8; ++g) {
    double J[3][3];
    hexJacobian(c, T.dM[g], J);
    const double det =
        J[0][0] * cofactor(J, 0, 0) + J[0][1] * cofactor(J, 0, 1) + J[0][2] * cofactor(J, 0, 2);
    if (!(det > 0)) return 0;
    volume += det;
  }
  return volume;
}

} // namespace cpdi

template <int D>
int Grid<D>::appendThreeNodeBlock(int q, const Reach &r, const double *x, const double *l,
                                  Stencils<D> &s, size_t &m, LevelBlock<D> *block) const {
  // A regular 3^D block of this level: closed-form weights, the same node set.
  const Level<D> &L = levels[q];
  const double ih = L.ih;
  double fw[D][3], fg[D][3];
  PetscInt n[D];
  for (int a = 0; a < D; ++a) {
    const double lam = l[a] * ih, i2l = 0.5 / lam;
    shape::threeNodeWeights((x[a] - (L.box[a] + r.i0[a] * L.h)) * ih, lam, i2l, i2l * ih, fw[a],
                            fg[a]);
    n[a] = r.i1[a] - r.i0[a] + 1;
  }
  const PetscInt base = windowSlot(q, r.i0), sy = L.wn(0), sz = D == 3 ? sy * L.wn(1) : 0;
  if (block) { // every node of the n[0] x n[1] (x n[2]) block
    LevelBlock<D> &b = *block;
    b.mask = 0;
    for (PetscInt c = 0; c < (D == 3 ? n[D - 1] : 1); ++c)
      for (PetscInt j = 0; j < n[1]; ++j)
        for (PetscInt i = 0; i < n[0]; ++i) {
          if (nSlots != nWindow && liveSlot[base + i + j * sy + c * sz] >= 0) return -1;
          b.mask |= std::uint64_t{1} << (i + 4 * j + 16 * c);
        }
    for (int a = 0; a < D; ++a) {
      for (int c = 0; c < 3; ++c) {
        b.w[a][c] = c < n[a] ? fw[a][c] : 0.0;
        b.g[a][c] = c < n[a] ? fg[a][c] : 0.0;
      }
      b.w[a][3] = b.g[a][3] = 0.0;
      b.n[a] = static_cast<std::uint8_t>(n[a]);
      if (a > 0) b.stride[a - 1] = a == 1 ? sy : sz;
    }
    b.base = base;
    b.last = 0;
    return 1;
  }
  size_t count = 1;
  for (int a = 0; a < D; ++a)
    count *= static_cast<size_t>(n[a]);
  s.reserve(m + count);
  PetscInt *node = s.node.data();
  double *ws[D], *gs[D];
  for (int a = 0; a < D; ++a) {
    ws[a] = s.w[a].data();
    gs[a] = s.g[a].data();
  }
  // x fastest, then y, then z (forEachIndex's order), the slots by the window's strides
  for (PetscInt c = 0; c < (D == 3 ? n[D - 1] : 1); ++c)
    for (PetscInt j = 0; j < n[1]; ++j)
      for (PetscInt i = 0; i < n[0]; ++i) {
        node[m] = base + i + j * sy + c * sz;
        ws[0][m] = fw[0][i];
        gs[0][m] = fg[0][i];
        ws[1][m] = fw[1][j];
        gs[1][m] = fg[1][j];
        ws[D - 1][m] = fw[D - 1][D == 3 ? c : j];
        gs[D - 1][m] = fg[D - 1][D == 3 ? c : j];
        ++m;
      }
  return 0;
}

template <int D>
const typename Grid<D>::NodePattern &Grid<D>::patternOf(int q, const Reach &r,
                                                        PatternCache &cache) const {
  const Level<D> &L = levels[q];
  const PetscInt base = windowSlot(q, r.i0), sy = L.wn(0), sz = D == 3 ? sy * L.wn(1) : 0;
  int n[3] = {1, 1, 1};
  std::uint64_t key =
      (static_cast<std::uint64_t>(base) << 12) | (static_cast<std::uint64_t>(q) << 6);
  for (int a = 0; a < D; ++a) {
    n[a] = static_cast<int>(r.i1[a] - r.i0[a] + 1);
    key |= static_cast<std::uint64_t>(n[a] - 1) << (2 * a);
  }
  // The particle's patterns of the last build, in order (it meets its boxes in the same order
  // unless it moved to others), then the table.
  std::vector<NodePattern> &out = *cache.out;
  for (const NodePattern *e = cache.last; e != cache.lastEnd; ++e)
    if (e->key == key) {
      cache.last = e + 1;
      out.push_back(*e);
      return out.back();
    }
  NodePattern &p = cache.entry(key);
  if (p.key == key) {
    out.push_back(p);
    return out.back();
  }
  p.key = key;
  p.tensor = !zoneValues_.empty();
  p.active = p.regular = p.live = 0;
  bool seen[D][4] = {};
  const bool cracked = nSlots != nWindow;
  const auto code = [&](double z) {
    return static_cast<std::uint8_t>(std::lower_bound(zoneValues_.begin(), zoneValues_.end(), z) -
                                     zoneValues_.begin());
  };
  for (int c2 = 0; c2 < n[2] && p.tensor; ++c2)
    for (int c1 = 0; c1 < n[1]; ++c1)
      for (int c0 = 0; c0 < n[0]; ++c0) {
        const PetscInt nd = base + c0 + c1 * sy + c2 * sz;
        const std::uint8_t f = flags_[nd];
        if (!(f & kActive)) continue;
        const std::uint64_t bit = std::uint64_t{1} << (c0 + 4 * c1 + 16 * c2);
        p.active |= bit;
        if (f == (kActive | kRegular)) p.regular |= bit;
        if (cracked && liveSlot[nd] >= 0) p.live |= bit;
        const int c[3] = {c0, c1, c2};
        const double *z = &zone[2 * D * nd];
        for (int a = 0; a < D; ++a) {
          std::uint8_t *Z = p.Z[a][c[a]];
          if (!seen[a][c[a]]) {
            seen[a][c[a]] = true;
            Z[0] = code(z[2 * a]);
            Z[1] = code(z[2 * a + 1]);
          } else if (zoneValues_[Z[0]] != z[2 * a] || zoneValues_[Z[1]] != z[2 * a + 1]) {
            p.tensor = false;
          }
        }
      }
  // (an index no active node has holds no entry: its zones, never used for one, are any value
  // of the window's; the first, which exists whenever the pattern is a tensor product)
  for (int a = 0; a < D; ++a)
    for (int c = 0; c < 4; ++c)
      if (c >= n[a] || !seen[a][c]) p.Z[a][c][0] = p.Z[a][c][1] = 0;
  out.push_back(p);
  return out.back();
}

template <int D>
int Grid<D>::appendFromPattern(const NodePattern &p, int q, const Reach &r, const double *x,
                               const double *l, Stencils<D> &s, size_t &m,
                               LevelBlock<D> *block) const {
  // appendNodes' rules, axis by axis: a node is an entry when it is active and either regular
  // with the particle's centre in the box (not tested) or its support overlaps the particle
  // along every axis (its zones there are Z[a][c]); its factor along an axis is its own (the
  // zones') where those are not h, the regular stretch's otherwise (appendNodes' expressions),
  // computed for the indices that hold an entry.
  const Level<D> &L = levels[q];
  const PetscInt base = windowSlot(q, r.i0), sy = L.wn(0), sz = D == 3 ? sy * L.wn(1) : 0;
  const PetscInt step[3] = {1, sy, sz};
  const std::vector<double> *coord[3] = {&X, &Y, &Z};
  int n[3] = {1, 1, 1};
  double d[D][4];
  unsigned ov[3] = {1u, 1u, 1u};
  for (int a = 0; a < D; ++a) {
    n[a] = static_cast<int>(r.i1[a] - r.i0[a] + 1);
    ov[a] = 0;
    for (int c = 0; c < n[a]; ++c) {
      // (a node's coordinate along a depends on its level and index there alone)
      d[a][c] = x[a] - (*coord[a])[base + c * step[a]];
      if (shape::overlaps(d[a][c], l[a], zoneValues_[p.Z[a][c][0]], zoneValues_[p.Z[a][c][1]]))
        ov[a] |= 1u << c;
    }
  }
  std::uint64_t overlap = 0;
  for (int c2 = 0; c2 < n[2]; ++c2)
    if ((ov[2] >> c2) & 1u)
      for (int c1 = 0; c1 < n[1]; ++c1)
        if ((ov[1] >> c1) & 1u) overlap |= static_cast<std::uint64_t>(ov[0]) << (4 * c1 + 16 * c2);
  const std::uint64_t mask = p.active & ((r.inside ? p.regular : 0) | overlap);
  if (block && (mask & p.live)) return -1;
  if (!mask) return 0;
  // The indices along each axis that hold an entry: the mask's 4-bit rows (along x) or'd, its
  // rows j of every layer, its layers q.
  unsigned any[3] = {0, 0, 0};
  for (int c = 0; c < 4; ++c) {
    const std::uint64_t layer = (mask >> (16 * c)) & 0xFFFFu;
    any[0] |= static_cast<unsigned>(layer | layer >> 4 | layer >> 8 | layer >> 12) & 0xFu;
    any[1] |= static_cast<unsigned>((mask >> (4 * c)) & 0x000F000F000F000Full ? 1u << c : 0u);
    any[2] |= layer ? 1u << c : 0u;
  }
  double fw[D][4], fg[D][4];
  for (int a = 0; a < D; ++a) {
    const double i2l = 0.5 / l[a];
    for (int c = 0; c < n[a]; ++c) {
      if (!((any[a] >> c) & 1u)) continue;
      const double z0 = zoneValues_[p.Z[a][c][0]], z1 = zoneValues_[p.Z[a][c][1]];
      if (z0 != L.h || z1 != L.h)
        shape::weightAndGradient(d[a][c], l[a], z0, z1, fw[a][c], fg[a][c]);
      else
        shape::weightAndGradientUniform(x[a] - (L.box[a] + (r.i0[a] + c) * L.h), l[a], L.h, L.ih,
                                        i2l, fw[a][c], fg[a][c]);
    }
  }
  if (!block) { // rows, x fastest, then y, then z
    s.reserve(m + static_cast<size_t>(__builtin_popcountll(mask)));
    PetscInt *node = s.node.data();
    for (std::uint64_t left = mask; left; left &= left - 1) {
      const int bit = __builtin_ctzll(left), c[3] = {bit & 3, (bit >> 2) & 3, bit >> 4};
      node[m] = base + c[0] + c[1] * sy + c[2] * sz;
      for (int a = 0; a < D; ++a) {
        s.w[a][m] = fw[a][c[a]];
        s.g[a][m] = fg[a][c[a]];
      }
      ++m;
    }
    return 0;
  }
  setLevelBlock<D>(*block, mask, base, sy, sz, any, fw, fg);
  return 1;
}

template <int D>
int Grid<D>::appendNodes(int q, const Reach &reach, const double *x, const double *l,
                         double *scratch, PetscInt maxRange, Stencils<D> &s, size_t &m,
                         LevelBlock<D> *block, PatternCache *cache) const {
  // Any range of nodes: 1D weights of a regular stretch for every candidate, replaced by the
  // node's own zones where it is irregular; nodes whose support misses the particle are left out.
  const Level<D> &L = levels[q];
  const double ih = L.ih;
  // Along an axis where the particle's centre lies outside the box, levelReach's candidates reach
  // out by the boundary nodes' outward zone; only the boundary face has it, the nodes behind it
  // face the particle with zones of h or less (levelReach's own rule inside the box). Those out
  // of reach are dropped here: the same entries, in the same order, from fewer candidates.
  Reach r = reach;
  for (int a = 0; a < D; ++a) {
    // (a node more than the exact bound, against rounding)
    if (x[a] < L.box[a])
      r.i1[a] = std::min(r.i1[a], static_cast<PetscInt>(std::max(
                                      0.0, std::ceil((x[a] + l[a] + L.h - L.box[a]) * ih))));
    else if (x[a] > L.box[D + a])
      r.i0[a] = std::max(r.i0[a], static_cast<PetscInt>(
                                      std::min(static_cast<double>(L.n[a] - 1),
                                               std::floor((x[a] - l[a] - L.h - L.box[a]) * ih))));
    if (r.i1[a] < r.i0[a]) return 0;
  }
  bool narrow = true; // (at most 4 candidates along every axis: a pattern's box)
  for (int a = 0; a < D; ++a)
    narrow = narrow && r.i1[a] - r.i0[a] < 4;
  if (cache && narrow) {
    const NodePattern &p = patternOf(q, r, *cache);
    if (p.tensor) return appendFromPattern(p, q, r, x, l, s, m, block);
  }
  double *rw[D], *rg[D];
  size_t count = 1;
  for (int a = 0; a < D; ++a) {
    rw[a] = scratch + 2 * a * maxRange;
    rg[a] = rw[a] + maxRange;
    count *= static_cast<size_t>(r.i1[a] - r.i0[a] + 1);
  }
  if constexpr (D == 2) { // both axes at once, the i-th candidate of each (simd::Pair)
    using simd::Pair;
    const PetscInt n0 = r.i1[0] - r.i0[0] + 1, n1 = r.i1[1] - r.i0[1] + 1;
    const Pair x2 = {x[0], x[1]}, l2 = {l[0], l[1]}, box = {L.box[0], L.box[1]};
    const Pair h = simd::splat(L.h), ih2 = simd::splat(ih), i2l = 0.5 / l2;
    for (PetscInt c = 0; c < std::max(n0, n1); ++c) {
      const Pair i = {static_cast<double>(r.i0[0] + c), static_cast<double>(r.i0[1] + c)};
      Pair w, g;
      shape::weightAndGradientUniform(x2 - (box + i * h), l2, h, ih2, i2l, w, g);
      if (c < n0) rw[0][c] = w[0], rg[0][c] = g[0];
      if (c < n1) rw[1][c] = w[1], rg[1][c] = g[1];
    }
  } else {
    for (int a = 0; a < D; ++a) {
      const double i2l = 0.5 / l[a];
      for (PetscInt i = r.i0[a]; i <= r.i1[a]; ++i)
        shape::weightAndGradientUniform(x[a] - (L.box[a] + i * L.h), l[a], L.h, ih, i2l,
                                        rw[a][i - r.i0[a]], rg[a][i - r.i0[a]]);
    }
  }
  PetscInt *node = nullptr;
  double *ws[D] = {}, *gs[D] = {};
  if (!block) {
    s.reserve(m + count);
    node = s.node.data();
    for (int a = 0; a < D; ++a) {
      ws[a] = s.w[a].data();
      gs[a] = s.g[a].data();
    }
  }
  const std::vector<double> *coord[3] = {&X, &Y, &Z};
  ZoneMemo<D> memo(scratch + 2 * D * maxRange, maxRange, r.i0, r.i1);
  // With `block` (candidates at most 4 along each axis): per axis the candidate indices whose
  // factor came from the regular stretch (bit c of regularAt[a]) and from a node's own zones
  // (ownAt[a]; ZoneMemo notes an index weighed for two sets of zones), the entries' nodes (bit
  // c0 + 4 c1 + 16 c2), and whether any is a live cracked node.
  unsigned regularAt[D] = {}, ownAt[D] = {};
  std::uint64_t mask = 0;
  bool live = false;
  const bool cracked = nSlots != nWindow;
  if (block)
    for (int a = 0; a < D; ++a)
      if (r.i1[a] - r.i0[a] >= 4) return -1;
  // One candidate node: window slot nd, offsets c[a] into the 1D tables.
  auto add = [&](PetscInt nd, const PetscInt *c) {
    const std::uint8_t f = flags_[nd];
    if (!(f & kActive)) return;
    double w[D], g[D]; // (a level block takes its factors per index below, not per node)
    if (!block)
      for (int a = 0; a < D; ++a) {
        w[a] = rw[a][c[a]];
        g[a] = rg[a][c[a]];
      }
    const double *z = nullptr;
    if (f != (kActive | kRegular) || !r.inside) {
      // Outside the box the candidate range is wider than the overlap range.
      z = &zone[2 * D * nd];
      double d[D];
      for (int a = 0; a < D; ++a) {
        d[a] = x[a] - (*coord[a])[nd];
        if (!shape::overlaps(d[a], l[a], z[2 * a], z[2 * a + 1])) return;
      }
      // (along an axis where the node's zones are both h it keeps the regular stretch's factor,
      // so every node at one index along an axis has the same factor there: level blocks)
      if (!(f & kRegular))
        for (int a = 0; a < D; ++a)
          if (z[2 * a] != L.h || z[2 * a + 1] != L.h)
            memo.factor(a, c[a], d[a], l[a], z + 2 * a, w[a], g[a]);
    }
    if (block) {
      if (z && !(f & kRegular)) {
        for (int a = 0; a < D; ++a)
          ((z[2 * a] != L.h || z[2 * a + 1] != L.h) ? ownAt : regularAt)[a] |= 1u << c[a];
      } else {
        for (int a = 0; a < D; ++a)
          regularAt[a] |= 1u << c[a];
      }
      live = live || (cracked && liveSlot[nd] >= 0);
      mask |= std::uint64_t{1} << (c[0] + 4 * c[1] + 16 * c[2]);
      return;
    }
    node[m] = nd;
    for (int a = 0; a < D; ++a) {
      ws[a][m] = w[a];
      gs[a][m] = g[a];
    }
    ++m;
  };
  // x fastest, then y, then z (forEachIndex's order), the slots by the window's strides
  const PetscInt base = windowSlot(q, r.i0), sy = L.wn(0), sz = D == 3 ? sy * L.wn(1) : 0;
  const PetscInt nz = D == 3 ? r.i1[D - 1] - r.i0[D - 1] + 1 : 1;
  PetscInt c[3] = {0, 0, 0};
  for (c[2] = 0; c[2] < nz; ++c[2])
    for (c[1] = 0; c[1] <= r.i1[1] - r.i0[1]; ++c[1]) {
      const PetscInt row = base + c[1] * sy + c[2] * sz;
      for (c[0] = 0; c[0] <= r.i1[0] - r.i0[0]; ++c[0])
        add(row + c[0], c);
    }
  if (!block) return 0;
  // The level block: each index's factor from its source, the block from the first index along
  // each axis that has an entry.
  if (live || memo.mixed) return -1;
  if (!mask) return 0;
  unsigned any[D];
  double fw[D][4], fg[D][4];
  for (int a = 0; a < D; ++a) {
    if (regularAt[a] & ownAt[a]) return -1; // (an index with both: not a tensor product)
    any[a] = regularAt[a] | ownAt[a];
    for (int c = 0; c < 4; ++c) {
      const bool own = (ownAt[a] >> c) & 1u;
      fw[a][c] = own ? memo.w[a][c] : c <= r.i1[a] - r.i0[a] ? rw[a][c] : 0.0;
      fg[a][c] = own ? memo.g[a][c] : c <= r.i1[a] - r.i0[a] ? rg[a][c] : 0.0;
    }
  }
  setLevelBlock<D>(*block, mask, base, sy, sz, any, fw, fg);
  return 1;
}

template <int D>
int Grid<D>::regularCornerEntries(const double *c, PetscInt *node, double *cw) const {
  // buildCpdiStencils' entries where every corner lies in one level's box among regular nodes
  // (active, zone h on every side) that no finer level reaches: pointShapes gives each corner
  // the nodes of levelReach's candidates (at most two per axis) with the tents of zones h, and
  // nothing on other levels. The same entries, order and values as the general path; each 1D
  // tent is evaluated once per index and the union of the corners' nodes is kept locally.
  constexpr int nc = 1 << D;
  double lo[D], hi[D];
  for (int a = 0; a < D; ++a) {
    lo[a] = hi[a] = c[a];
    for (int q = 1; q < nc; ++q) {
      lo[a] = std::min(lo[a], c[D * q + a]);
      hi[a] = std::max(hi[a], c[D * q + a]);
    }
  }
  double mid[D], half[D];
  for (int a = 0; a < D; ++a) {
    mid[a] = 0.5 * (lo[a] + hi[a]);
    half[a] = 0.5 * (hi[a] - lo[a]);
  }
  const int lev = coarsestReaching(mid, half);
  const Level<D> &L = levels[lev];
  // No finer level reaches a corner (soleBlock's test on the corners' box), so each corner's
  // coarsestReaching is lev and levelReach finds no candidate on the finer levels.
  for (int f = lev + 1; f < static_cast<int>(levels.size()); ++f) {
    const Level<D> &F = levels[f];
    const double Zf = std::max(F.h, outwardReach_[f]) + 0.5 * F.h;
    bool misses = false;
    for (int a = 0; a < D; ++a)
      misses = misses || hi[a] + Zf < F.box[a] || lo[a] - Zf > F.box[D + a];
    if (!misses) return -1;
  }
  // Each corner's candidates along each axis (levelReach with l = 0, the corner inside the box:
  // reach h), at most two, and their tents.
  PetscInt i0[nc][D], n[nc][D], u0[D], u1[D];
  double t[nc][D][2];
  const double *coord[3] = {X.data(), Y.data(), Z.data()};
  for (int a = 0; a < D; ++a) {
    if (!(lo[a] >= L.box[a] && hi[a] <= L.box[D + a])) return -1;
    u0[a] = L.w1[a];
    u1[a] = L.w0[a] - 1;
    for (int q = 0; q < nc; ++q) {
      const double x = c[D * q + a];
      PetscInt first, last;
      candidates(L, a, x - L.h, x + L.h, first, last);
      if (first < L.w0[a] || last > L.w1[a] - 1 || last < first || last - first > 1) return -1;
      i0[q][a] = first;
      n[q][a] = last - first + 1;
      u0[a] = std::min(u0[a], first);
      u1[a] = std::max(u1[a], last);
    }
    if (u1[a] - u0[a] > 2) return -1;
  }
  const PetscInt sy = L.wn(0), sz = D == 3 ? sy * L.wn(1) : 0;
  const PetscInt stride[3] = {1, sy, sz};
  auto slotOf = [&](const PetscInt *i) {
    PetscInt nd = L.offset;
    for (int a = 0; a < D; ++a)
      nd += (i[a] - L.w0[a]) * stride[a];
    return nd;
  };
  { // every node of the corners' candidate box active and regular
    const PetscInt base = slotOf(u0);
    for (PetscInt k = 0; k <= (D == 3 ? u1[D - 1] - u0[D - 1] : 0); ++k)
      for (PetscInt j = 0; j <= u1[1] - u0[1]; ++j)
        for (PetscInt i = 0; i <= u1[0] - u0[0]; ++i)
          if (flags_[base + k * sz + j * sy + i] != (kActive | kRegular)) return -1;
  }
  // The tents: tent(s, h, h) is max(0, 1 - |s| / h) to the bit (also at s = 0 and |s| >= h).
  for (int q = 0; q < nc; ++q)
    for (int a = 0; a < D; ++a) {
      PetscInt ia[D];
      for (int b = 0; b < D; ++b)
        ia[b] = i0[q][b];
      for (PetscInt i = 0; i < 2; ++i) {
        ia[a] = i0[q][a] + std::min<PetscInt>(i, n[q][a] - 1);
        t[q][a][i] = std::max(0.0, 1.0 - std::fabs(c[D * q + a] - coord[a][slotOf(ia)]) / L.h);
      }
    }
  // pointShapes' entries corner by corner (x fastest), a node's first appearance its place: the
  // place of each node of the 3^D box, -1 until a corner gives it a weight.
  int at[27];
  for (int b = 0; b < 27; ++b)
    at[b] = -1;
  const PetscInt base = slotOf(u0);
  int m = 0;
  for (int q = 0; q < nc; ++q) {
    PetscInt o[3] = {0, 0, 0};
    for (int a = 0; a < D; ++a)
      o[a] = i0[q][a] - u0[a];
    for (PetscInt k = 0; k < (D == 3 ? n[q][D - 1] : 1); ++k)
      for (PetscInt j = 0; j < n[q][1]; ++j)
        for (PetscInt i = 0; i < n[q][0]; ++i) {
          double N = 1.0;
          N *= t[q][0][i];
          N *= t[q][1][j];
          if constexpr (D == 3) N *= t[q][2][k];
          if (N <= 0) continue;
          const PetscInt bi = o[0] + i, bj = o[1] + j, bk = o[2] + k;
          const int b = static_cast<int>(bi + 3 * (bj + 3 * bk));
          if (at[b] < 0) {
            at[b] = m;
            node[m] = base + bk * sz + bj * sy + bi;
            for (int r = 0; r < nc; ++r)
              cw[nc * m + r] = 0;
            ++m;
          }
          cw[nc * at[b] + q] = N;
        }
  }
  return m;
}

template <int D>
double Grid<D>::pointShapes(const double *x, std::vector<std::pair<PetscInt, double>> &out) const {
  double sum = 0;
  const double zero[D] = {};
  const double *coord[3] = {X.data(), Y.data(), Z.data()};
  for (int q = coarsestReaching(x, zero); q < static_cast<int>(levels.size()); ++q) {
    // levelReach's candidates for a point (l = 0), without its block flags
    const Level<D> &L = levels[q];
    PetscInt i0[3] = {0, 0, 0}, i1[3] = {0, 0, 0};
    bool none = false;
    for (int a = 0; a < D && !none; ++a) {
      const bool within = x[a] >= L.box[a] && x[a] <= L.box[D + a];
      const double Zr = within ? L.h : outwardReach_[q];
      PetscInt first, last;
      candidates(L, a, x[a] - Zr, x[a] + Zr, first, last);
      i0[a] = std::max(first, L.w0[a]);
      i1[a] = std::min(last, L.w1[a] - 1);
      none = L.w1[a] <= L.w0[a] || i1[a] < i0[a];
    }
    if (none) continue;
    const double eps = 1e-9 * L.h;
    const PetscInt sy = L.wn(0), sz = D == 3 ? sy * L.wn(1) : 0;
    for (PetscInt k = i0[2]; k <= i1[2]; ++k)
      for (PetscInt j = i0[1]; j <= i1[1]; ++j) {
        PetscInt nd = L.offset + (j - L.w0[1]) * sy + (i0[0] - L.w0[0]);
        if constexpr (D == 3) nd += (k - L.w0[2]) * sz;
        for (PetscInt i = i0[0]; i <= i1[0]; ++i, ++nd) {
          if (!(flags_[nd] & kActive)) continue;
          const double *z = &zone[2 * D * nd];
          double N = 1.0;
          for (int a = 0; a < D; ++a)
            N *= pointTent(x[a] - coord[a][nd], z[2 * a], z[2 * a + 1], eps);
          if (N <= 0) continue;
          out.emplace_back(nd, N);
          sum += N;
        }
      }
  }
  return sum;
}

template <int D>
const char *Grid<D>::buildCpdiStencils(PetscInt n, const double *corners, Stencils<D> &s) const {
  constexpr int nc = 1 << D;                   // corners per particle
  constexpr int kMaxRegular = D == 2 ? 9 : 27; // regularCornerEntries: a 3^D box at most
  s.start.resize(static_cast<size_t>(n) + 1);
  s.general = true;
  s.compact = false;
  size_t m = 0;
  s.reserveGeneral(size_t{1 << (2 * D)} * static_cast<size_t>(n));
  std::vector<std::pair<PetscInt, double>> pts;
  for (PetscInt k = 0; k < n; ++k) {
    s.start[k] = static_cast<PetscInt>(m);
    const double *c = &corners[D * nc * k];
    double w[nc], G[D * nc];
    const double A = cellIntegrals<D>(c, w, G);
    if (!(A > 0)) {
      s.start[k + 1] = static_cast<PetscInt>(m);
      return "a particle's CPDI domain is inverted or collapsed (its corners cross)";
    }
    const size_t first = m;
    PetscInt rn[kMaxRegular];
    double rcw[nc * kMaxRegular];
    const int regular = regularCornerEntries(c, rn, rcw);
    if (regular >= 0) {
      s.reserveGeneral(m + static_cast<size_t>(regular));
      for (int e = 0; e < regular; ++e, ++m) {
        s.node[m] = rn[e];
        for (int q = 0; q < nc; ++q)
          s.cw[nc * m + q] = rcw[nc * e + q];
      }
    }
    for (int q = 0; q < nc && regular < 0; ++q) {
      pts.clear();
      const double sum = pointShapes(&c[D * q], pts);
      if (!(std::fabs(sum - 1.0) < 1e-9)) {
        s.start[k + 1] = static_cast<PetscInt>(m);
        return "a particle's corner lies outside the grid or this rank's window";
      }
      for (const auto &[nd, N] : pts) {
        size_t e = first;
        while (e < m && s.node[e] != nd)
          ++e;
        if (e == m) { // a new node of this particle
          s.reserveGeneral(m + 1);
          s.node[m] = nd;
          for (int r = 0; r < nc; ++r)
            s.cw[nc * m + r] = 0;
          ++m;
        }
        s.cw[nc * e + q] = N;
      }
    }
    const double iA = 1.0 / A;
    for (size_t e = first; e < m; ++e) {
      double S = 0, g[D] = {};
      for (int q = 0; q < nc; ++q) {
        const double N = s.cw[nc * e + q];
        S += w[q] * N;
        for (int a = 0; a < D; ++a)
          g[a] += G[D * q + a] * N;
      }
      s.sw[e] = S * iA;
      for (int a = 0; a < D; ++a)
        s.sg[a][e] = g[a] * iA;
    }
  }
  s.start[n] = static_cast<PetscInt>(m);
  return nullptr;
}

template int Grid<2>::appendThreeNodeBlock(int, const Reach &, const double *, const double *,
                                           Stencils<2> &, size_t &, LevelBlock<2> *) const;
template int Grid<3>::appendThreeNodeBlock(int, const Reach &, const double *, const double *,
                                           Stencils<3> &, size_t &, LevelBlock<3> *) const;
template const Grid<2>::NodePattern &Grid<2>::patternOf(int, const Reach &, PatternCache &) const;
template const Grid<3>::NodePattern &Grid<3>::patternOf(int, const Reach &, PatternCache &) const;
template int Grid<2>::appendFromPattern(const NodePattern &, int, const Reach &, const double *,
                                        const double *, Stencils<2> &, size_t &,
                                        LevelBlock<2> *) const;
template int Grid<3>::appendFromPattern(const NodePattern &, int, const Reach &, const double *,
                                        const double *, Stencils<3> &, size_t &,
                                        LevelBlock<3> *) const;
template int Grid<2>::appendNodes(int, const Reach &, const double *, const double *, double *,
                                  PetscInt, Stencils<2> &, size_t &, LevelBlock<2> *,
                                  PatternCache *) const;
template int Grid<3>::appendNodes(int, const Reach &, const double *, const double *, double *,
                                  PetscInt, Stencils<3> &, size_t &, LevelBlock<3> *,
                                  PatternCache *) const;
template int Grid<2>::regularCornerEntries(const double *, PetscInt *, double *) const;
template int Grid<3>::regularCornerEntries(const double *, PetscInt *, double *) const;
template double Grid<2>::pointShapes(const double *,
                                     std::vector<std::pair<PetscInt, double>> &) const;
template double Grid<3>::pointShapes(const double *,
                                     std::vector<std::pair<PetscInt, double>> &) const;
template const char *Grid<2>::buildCpdiStencils(PetscInt, const double *, Stencils<2> &) const;
template const char *Grid<3>::buildCpdiStencils(PetscInt, const double *, Stencils<3> &) const;

} // namespace gimp
