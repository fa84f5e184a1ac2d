// Particle domain tracking (paper section 2.3): what a particle's domain chi_p of Eq. 10 is
// after it deforms. none: the initial square; strain: (1 + eps) l0 with eps the accumulated
// axial strain increments; stretch: the stretches of F times l0 (the default); corners: the
// paper's tracked corners, the domain being the axis-aligned rectangle they span; cpdi: the
// parallelogram x_p +- F r1^0 +- F r2^0 (Sadeghirad et al. 2011); cpdi2: the quadrilateral of
// the tracked corners (Sadeghirad et al. 2013). With cpdi and cpdi2 the half-sizes l are the
// largest distances of a corner from the material point along x and y (what the checks, the
// crack reach and the output read), the weights come from the corners (Grid::buildCpdiStencils).
#pragma once

#include "gimp/core/pair.hpp"
#include "gimp/geometry/crack.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"
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

/// The CPDI parallelogram of particle k: corners x_p - r1 - r2, x_p + r1 - r2, x_p + r1 + r2,
/// x_p - r1 + r2 (counter-clockwise) with r_a = F r_a^0, r_a^0 = l0_a e_a, into c (8 values).
inline void cpdiParallelogram(const ParticleView<2> &p, PetscInt k, double *c) {
  const auto F = tensorAt<2>(p.F, k);
  const double r1[2] = {F(0, 0) * p.l0[2 * k], F(1, 0) * p.l0[2 * k]};
  const double r2[2] = {F(0, 1) * p.l0[2 * k + 1], F(1, 1) * p.l0[2 * k + 1]};
  static const double s1[4] = {-1, 1, 1, -1}, s2[4] = {-1, -1, 1, 1};
  for (int q = 0; q < 4; ++q)
    for (int d = 0; d < 2; ++d)
      c[2 * q + d] = p.x[2 * k + d] + s1[q] * r1[d] + s2[q] * r2[d];
}

/// Half-sizes of a CPDI particle: the largest distance of a corner from x_p along each axis.
inline void cornerReach(ParticleView<2> &p, PetscInt k, const double *c) {
  for (int d = 0; d < 2; ++d)
    p.l[2 * k + d] =
        std::max({std::fabs(c[d] - p.x[2 * k + d]), std::fabs(c[d + 2] - p.x[2 * k + d]),
                  std::fabs(c[d + 4] - p.x[2 * k + d]), std::fabs(c[d + 6] - p.x[2 * k + d])});
}

/// Area of the quadrilateral of four corners (counter-clockwise, shoelace).
inline double quadArea(const double *c) {
  return 0.5 * ((c[0] * c[3] - c[2] * c[1]) + (c[2] * c[5] - c[4] * c[3]) +
                (c[4] * c[7] - c[6] * c[5]) + (c[6] * c[1] - c[0] * c[7]));
}

/// The volume of a particle whose corners span c: V0 times the quadrilateral's area over the
/// initial rectangle's, 4 l0_x l0_y (a cut cell's domain may be larger than its volume).
inline double volumeOfCorners(const ParticleView<2> &p, PetscInt k, const double *c) {
  return p.V0[k] * quadArea(c) / (4.0 * p.l0[2 * k] * p.l0[2 * k + 1]);
}

/// The CPDI domains' corners of every particle: the parallelograms of F (cpdi, into `scratch`)
/// or the tracked corners (cpdi2).
const double *cpdiCorners(const Scene<2> &sc, const ParticleView<2> &p,
                          std::vector<double> &scratch);

/// Particle k's domain by cpdi, cpdi2 or corner tracking (updateDomain's other cases).
void updateTrackedDomain(const Scene<2> &sc, ParticleView<2> &p, PetscInt k, const Tensor<2> &L,
                         double dt);

/// Particle k's domain after its deformation gradient F (already updated) and velocity
/// gradient L over dt: half-sizes l, and with corners also the volume.
inline void updateDomain(const Scene<2> &sc, ParticleView<2> &p, PetscInt k, const Tensor<2> &L,
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
  case Tracking::Stretch: { // l_a = |F e_a| l0_a, both axes at once
    using simd::Pair;
    const Pair r0 = simd::load(&p.F[4 * k]), r1 = simd::load(&p.F[4 * k + 2]); // F's rows
    simd::store(&p.l[2 * k], simd::sqrt(r0 * r0 + r1 * r1) * simd::load(&p.l0[2 * k]));
    return;
  }
  default:
    updateTrackedDomain(sc, p, k, L, dt);
  }
}

/// Where each particle's weights are centred: the material point, or with corner tracking the
/// centre of its corners' rectangle (into `centre`, which then is returned). With cpdi and cpdi2
/// the material point (the crack side of a particle is its material point's).
const double *domainCentres(const ParticleView<2> &p, std::vector<double> &centre, Tracking t);

/// Moves the tracked corners with the grid velocity interpolated at each corner, as a particle
/// of the fictitious size -gimp_corner_size times the particle's (cornerSize 0: with the grid's
/// point shape functions, cpdi2's corner update of Sadeghirad et al. 2013), renormalised over the
/// nodes that carry mass. Neighbours' shared corners get the same velocity and stay together. At a
/// cracked node a corner takes the field of its particle's side (the side of the segment from
/// the material point to the node): a face's corners lie on the crack line, where the corner's
/// own position would give both faces' corners one side, and the lower face's corners would
/// follow the upper face.
class CornerMotion {
public:
  /// vWindow: nodal velocity on the window; mWindow: nodal mass there (component 0). False when
  /// a corner's stencil cannot be built (a particle larger than a level-0 cell).
  bool move(const Grid<2> &g, const std::vector<Crack> &cracks, double cornerSize, double cut,
            double dt, const double *vWindow, const double *mWindow, ParticleView<2> &p);

private:
  Stencils<2> st_;
  std::vector<double> size_;
  std::vector<double> owner_; // each corner's material point, for the crack fields
};

} // namespace gimp::tracking
