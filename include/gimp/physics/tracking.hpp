// Particle domain tracking (paper section 2.3): what a particle's domain chi_p of Eq. 10 is
// after it deforms. none: the initial square; strain: (1 + eps) l0 with eps the accumulated
// axial strain increments; stretch: the stretches of F times l0 (the default); corners: the
// paper's tracked corners, the domain being the axis-aligned rectangle they span.
#pragma once

#include "gimp/cracks/geometry.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/particles/swarm.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gimp::tracking {

/// Centre along axis d of the rectangle spanned by a particle's four corners (x, y pairs).
inline double cornerBoxCentre(const double *c, int d) {
  return 0.5 * (std::min({c[d], c[d + 2], c[d + 4], c[d + 6]}) +
                std::max({c[d], c[d + 2], c[d + 4], c[d + 6]}));
}

/// Particle k's domain after its deformation gradient F (already updated) and velocity
/// gradient L over dt: half-sizes l, and with corners also the volume.
inline void updateDomain(const Scene &sc, ParticleView &p, PetscInt k, const Tensor<2> &L,
                         double dt) {
  switch (sc.tracking) {
  case Tracking::None:
    return;
  case Tracking::Strain:
    for (int a = 0; a < 2; ++a) {
      p.eps[2 * k + a] += dt * L(a, a);
      p.l[2 * k + a] = (1.0 + p.eps[2 * k + a]) * p.l0[2 * k + a];
    }
    return;
  case Tracking::Stretch: {
    const auto F = tensorAt<2>(p.F, k);
    for (int a = 0; a < 2; ++a)
      p.l[2 * k + a] = std::sqrt(F(0, a) * F(0, a) + F(1, a) * F(1, a)) * p.l0[2 * k + a];
    return;
  }
  case Tracking::Corners:
    break;
  }
  p.eps[2 * k] += dt * L(0, 0);
  p.eps[2 * k + 1] += dt * L(1, 1);
  double *c = &p.corners[8 * k];
  // Exterior corners of a particle on a loaded edge follow its strain (the paper, 4.2).
  for (int a = 0; a < 2; ++a) {
    if (p.trac[2 * k + a] < 0) continue;
    const double n = sc.tractions[p.trac[2 * k + a]].normal();
    for (int q = 0; q < 4; ++q) {
      const double sx = (q == 1 || q == 2) ? 1.0 : -1.0, sy = q >= 2 ? 1.0 : -1.0;
      if ((a == 0 ? sx : sy) != n) continue;
      c[2 * q] = p.x[2 * k] + sx * (1.0 + p.eps[2 * k]) * p.l0[2 * k];
      c[2 * q + 1] = p.x[2 * k + 1] + sy * (1.0 + p.eps[2 * k + 1]) * p.l0[2 * k + 1];
    }
  }
  // The particle is the axis-aligned rectangle spanned by its corners; its volume is the area
  // of the quadrilateral they form.
  const double xmin = std::min({c[0], c[2], c[4], c[6]}), xmax = std::max({c[0], c[2], c[4], c[6]});
  const double ymin = std::min({c[1], c[3], c[5], c[7]}), ymax = std::max({c[1], c[3], c[5], c[7]});
  p.l[2 * k] = 0.5 * (xmax - xmin);
  p.l[2 * k + 1] = 0.5 * (ymax - ymin);
  const double area = 0.5 * ((c[0] * c[3] - c[2] * c[1]) + (c[2] * c[5] - c[4] * c[3]) +
                             (c[4] * c[7] - c[6] * c[5]) + (c[6] * c[1] - c[0] * c[7]));
  p.V[k] = area * sc.material.thickness;
}

/// Where each particle's weights are centred: the material point, or with corner tracking the
/// centre of its corners' rectangle (into `centre`, which then is returned).
const double *domainCentres(const ParticleView &p, std::vector<double> &centre);

/// Moves the tracked corners with the grid velocity interpolated at each corner, as a particle
/// of the fictitious size -gimp_corner_size times the particle's, renormalised over the nodes
/// that carry mass. Neighbours' shared corners get the same velocity and stay together. At a
/// cracked node a corner takes the field of its particle's side (the side of the segment from
/// the material point to the node): a face's corners lie on the crack line, where the corner's
/// own position would give both faces' corners one side, and the lower face's corners would
/// follow the upper face.
class CornerMotion {
public:
  /// vWindow: nodal velocity on the window; mWindow: nodal mass there (component 0). False when
  /// a corner's stencil cannot be built (a particle larger than a level-0 cell).
  bool move(const Grid &g, const std::vector<Crack> &cracks, double cornerSize, double cut,
            double dt, const double *vWindow, const double *mWindow, ParticleView &p);

private:
  Stencils<2> st_;
  std::vector<double> size_;
  std::vector<double> owner_; // each corner's material point, for the crack fields
};

} // namespace gimp::tracking
