#include "gimp/cracks/fields.hpp"

#include <algorithm>
#include <cmath>

namespace gimp::cracks {

void Contact::setup(const Grid<2> &g, const std::vector<Crack> &cracks) {
  dir_.assign(2 * static_cast<size_t>(g.nSlots - g.nWindow), 0.0);
  for (PetscInt s = g.nWindow; s < g.nSlots; ++s) {
    const PetscInt n = g.slotNode[s];
    const double X = g.X[n], Y = g.Y[n];
    size_t best = 0;
    double dist = 1e300;
    for (size_t q = 0; q < cracks.size(); ++q) {
      const double r = distance(cracks[q], X, Y);
      if (r < dist) {
        dist = r;
        best = q;
      }
    }
    double nrm[2];
    const int seg = normalAt(cracks[best], X, Y, nrm);
    // A node on the crack line counts as on its left, as in crossing().
    const double side = sideOf(cracks[best], seg, X, Y);
    dir_[2 * (s - g.nWindow)] = -side * nrm[0];
    dir_[2 * (s - g.nWindow) + 1] = -side * nrm[1];
  }
}

void Contact::faces(const Grid<2> &g, const Stencils<2> &st, PetscInt n, const double *x,
                    const double *X0, const double *m, double *face) {
  fresh_ = true;
  for (PetscInt s = 0; s < g.nSlots; ++s)
    face[2 * s] = 0.0;
  if (g.nSlots == g.nWindow) return;
  for (PetscInt k = 0; k < n; ++k) {
    const double ux = m[k] * (x[2 * k] - X0[2 * k]), uy = m[k] * (x[2 * k + 1] - X0[2 * k + 1]);
    st.forEach(k, [&](PetscInt s, double w, const Vector<2> &) {
      const PetscInt c = s >= g.nWindow ? s : g.crackSlot[s];
      if (c < 0) return;
      const double *d = &dir_[2 * (c - g.nWindow)];
      face[2 * s] += w * (ux * d[0] + uy * d[1]);
    });
  }
}

PetscInt Contact::apply(const Grid<2> &g, double cut, double dt, const double *mass,
                        const double *face, double *vel, double *acc) {
  PetscInt touching = 0;
  if (fresh_) touch_.assign(static_cast<size_t>(g.nSlots - g.nWindow), 0);
  for (PetscInt s = g.nWindow; s < g.nSlots; ++s) {
    const PetscInt n = g.slotNode[s];
    const double m1 = mass[2 * n], m2 = mass[2 * s];
    if (!(m1 > cut && m2 > cut)) continue;
    // The opening: field 2's displacement along d minus field 1's, each the mass-weighted mean
    // of its particles' (the fields' nodal displacements). It starts at zero (the faces are
    // together) and, unlike particle extents, does not move when particles change size.
    const double gap = face[2 * s] / m2 - face[2 * n] / m1;
    const double *d = &dir_[2 * (s - g.nWindow)];
    double *v1 = &vel[2 * n], *v2 = &vel[2 * s];
    const double approach = (v1[0] - v2[0]) * d[0] + (v1[1] - v2[1]) * d[1];
    char &touch = touch_[static_cast<size_t>(s - g.nWindow)];
    if (fresh_)
      touch = gap <= std::fabs(approach) * dt + 1e-12 * (g.zone[4 * n + 1] + g.zone[4 * n + 3]);
    if (!touch || !(approach > 0)) continue; // apart, or separating or sliding: free
    ++touching;
    const double vn =
        (m1 * (v1[0] * d[0] + v1[1] * d[1]) + m2 * (v2[0] * d[0] + v2[1] * d[1])) / (m1 + m2);
    const double dv1 = vn - (v1[0] * d[0] + v1[1] * d[1]);
    const double dv2 = vn - (v2[0] * d[0] + v2[1] * d[1]);
    for (int c = 0; c < 2; ++c) {
      vel[2 * n + c] += dv1 * d[c];
      vel[2 * s + c] += dv2 * d[c];
      if (!acc) continue;
      acc[2 * n + c] += dv1 * d[c] / dt;
      acc[2 * s + c] += dv2 * d[c] / dt;
    }
  }
  fresh_ = false;
  return touching;
}

} // namespace gimp::cracks
