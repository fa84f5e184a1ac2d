#include "gimp/cracks/fields.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gimp::cracks {

namespace {

/// Where a cracked node lies against its nearest crack, as the release's test reads it: 2D, the
/// node and its distance to the crack; 3D, the crack's index and the node's nearest point on it.
template <int D> struct NodeOnCrack;
template <> struct NodeOnCrack<2> {
  std::array<double, 2> x;
  double dist;
  NodeOnCrack(const Crack &, size_t, const double *X, double d) : x{X[0], X[1]}, dist(d) {}
};
template <> struct NodeOnCrack<3> {
  size_t crack;
  std::array<double, 3> nearest;
  NodeOnCrack(const CrackSurface &c, size_t q, const double *X, double)
      : crack(q), nearest(nearestPoint(c, X)) {}
};

/// Whether the increment r newly cut the node (2D): its nearest point on the crack lies on r's
/// segment, at or beyond the tip before it (a node at that tip was not cut before: the crack
/// ended there).
bool newlyCut(const Release<2> &r, const NodeOnCrack<2> &at) {
  const double e[2] = {r.to[0] - r.from[0], r.to[1] - r.from[1]};
  const double L2 = e[0] * e[0] + e[1] * e[1];
  if ((at.x[0] - r.from[0]) * e[0] + (at.x[1] - r.from[1]) * e[1] < -1e-9 * L2) return false;
  return segmentDistance(r.from, r.to, at.x, at.x) <= at.dist + 1e-9 * std::sqrt(L2);
}

/// Whether the advance r newly cut the node (3D): r grew the node's nearest crack, and the node's
/// nearest point on it is not behind the front of the polygon before r (it lies on what r added,
/// or on the front before it: a node there was not cut before, the crack ended there).
bool newlyCut(const Release<3> &r, const NodeOnCrack<3> &at) {
  return static_cast<size_t>(r.crack) == at.crack &&
         !behindFront(r.before, at.nearest.data(), 1e-9 * r.before.span);
}

} // namespace

template <int D>
void Contact<D>::setup(const Grid<D> &g, const std::vector<CrackOf<D>> &cracks,
                       const std::vector<Release<D>> &releasing, double releaseTime) {
  dir_.assign(D * static_cast<size_t>(g.nSlots - g.nWindow), 0.0);
  release_ = releaseTime;
  bondFrom_.assign(releaseTime > 0 ? static_cast<size_t>(g.nSlots - g.nWindow) : 0,
                   -std::numeric_limits<double>::infinity());
  for (PetscInt s = g.nWindow; s < g.nSlots; ++s) {
    const PetscInt n = g.slotNode[s];
    double X[D];
    for (int a = 0; a < D; ++a)
      X[a] = g.coordinates(a)[n];
    size_t best = 0;
    double dist = 1e300;
    for (size_t q = 0; q < cracks.size(); ++q) {
      const double r = distance(cracks[q], X);
      if (r < dist) {
        dist = r;
        best = q;
      }
    }
    double nrm[D];
    const int seg = normalAt(cracks[best], X, nrm);
    // A node on the crack counts as on its left (normal's) side, as in crossing().
    const double side = sideOf(cracks[best], seg, X);
    for (int a = 0; a < D; ++a)
      dir_[D * (s - g.nWindow) + a] = -side * nrm[a];
    if (bondFrom_.empty() || releasing.empty()) continue;
    const NodeOnCrack<D> at(cracks[best], best, X, dist);
    for (const Release<D> &r : releasing)
      if (newlyCut(r, at)) {
        double &from = bondFrom_[static_cast<size_t>(s - g.nWindow)];
        from = std::max(from, r.t0);
      }
  }
}

template <int D>
void Contact<D>::faces(const Grid<D> &g, const Stencils<D> &st, PetscInt n, const double *x,
                       const double *X0, const double *m, double *face) {
  fresh_ = true;
  for (PetscInt s = 0; s < g.nSlots; ++s)
    face[D * s] = 0.0;
  if (g.nSlots == g.nWindow) return;
  for (PetscInt k = 0; k < n; ++k) {
    // A block holds no live cracked node (Grid::markLiveCracks), and a cracked node that is not
    // live has no second-field mass, so contact never acts there: blocks add nothing it reads.
    if (st.isBlock(k) || st.isBlock4(k)) continue;
    double u[D];
    for (int a = 0; a < D; ++a)
      u[a] = m[k] * (x[D * k + a] - X0[D * k + a]);
    st.forEach(k, [&](PetscInt s, double w, const Vector<D> &) {
      const PetscInt c = s >= g.nWindow ? s : g.crackSlot[s];
      if (c < 0) return;
      const double *d = &dir_[D * (c - g.nWindow)];
      double ud = 0;
      for (int a = 0; a < D; ++a)
        ud += u[a] * d[a];
      face[D * s] += w * ud;
    });
  }
}

template <int D>
PetscInt Contact<D>::apply(const Grid<D> &g, double cut, double dt, const double *mass,
                           const double *face, double *vel, double *acc, double t) {
  PetscInt touching = 0;
  if (fresh_) touch_.assign(static_cast<size_t>(g.nSlots - g.nWindow), 0);
  for (PetscInt s = g.nWindow; s < g.nSlots; ++s) {
    const PetscInt n = g.slotNode[s];
    const double m1 = mass[D * n], m2 = mass[D * s];
    if (!(m1 > cut && m2 > cut)) continue;
    // The opening: field 2's displacement along d minus field 1's, each the mass-weighted mean
    // of its particles' (the fields' nodal displacements). It starts at zero (the faces are
    // together) and, unlike particle extents, does not move when particles change size.
    const double gap = face[D * s] / m2 - face[D * n] / m1;
    const double *d = &dir_[D * (s - g.nWindow)];
    double *v1 = &vel[D * n], *v2 = &vel[D * s];
    // (an increment being released: both fields toward their common velocity by the bond)
    const double bond =
        bondFrom_.empty()
            ? 0.0
            : std::min(1.0, 1.0 - (t - bondFrom_[static_cast<size_t>(s - g.nWindow)]) / release_);
    if (bond > 0)
      for (int c = 0; c < D; ++c) {
        const double common = (m1 * v1[c] + m2 * v2[c]) / (m1 + m2);
        const double dv1 = bond * (common - v1[c]), dv2 = bond * (common - v2[c]);
        v1[c] += dv1;
        v2[c] += dv2;
        if (!acc) continue;
        acc[D * n + c] += dv1 / dt;
        acc[D * s + c] += dv2 / dt;
      }
    double v1n = 0, v2n = 0, approach = 0, zone = 0;
    for (int a = 0; a < D; ++a) {
      v1n += v1[a] * d[a];
      v2n += v2[a] * d[a];
      approach += (v1[a] - v2[a]) * d[a];
      zone += g.zone[2 * D * n + 2 * a + 1];
    }
    char &touch = touch_[static_cast<size_t>(s - g.nWindow)];
    if (fresh_) touch = gap <= std::fabs(approach) * dt + 1e-12 * zone;
    if (!touch || !(approach > 0)) continue; // apart, or separating or sliding: free
    ++touching;
    const double vn = (m1 * v1n + m2 * v2n) / (m1 + m2);
    const double dv1 = vn - v1n, dv2 = vn - v2n;
    for (int c = 0; c < D; ++c) {
      vel[D * n + c] += dv1 * d[c];
      vel[D * s + c] += dv2 * d[c];
      if (!acc) continue;
      acc[D * n + c] += dv1 * d[c] / dt;
      acc[D * s + c] += dv2 * d[c] / dt;
    }
  }
  fresh_ = false;
  return touching;
}

template class Contact<2>;
template class Contact<3>;

} // namespace gimp::cracks
