// Particle domain tracking (paper section 2.3): what a particle's domain chi_p of Eq. 10 is
// after it deforms, in 2D and 3D. none: the initial box; strain: (1 + eps) l0 with eps the
// accumulated axial strain increments; stretch: the stretches of F times l0 (the default);
// corners: the paper's tracked corners (4 of a square, 8 of a cube), the domain being the
// axis-aligned box they span; cpdi: the parallelogram (parallelepiped) x_p + sum_a +-F r_a^0
// (Sadeghirad et al. 2011); cpdi2: the quadrilateral (hexahedron) of the tracked corners
// (Sadeghirad et al. 2013). Corners are in the order of grid/cpdi_cells.hpp. With cpdi and cpdi2
// the half-sizes l are the largest distances of a corner from the material point along each
// axis (what the checks, the crack reach and the output read), the weights come from the corners
// (Grid::buildCpdiStencils).
#pragma once

#include "gimp/core/pair.hpp"
#include "gimp/geometry/crack.hpp"
#include "gimp/grid/cpdi_cells.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gimp::tracking {

/// Corners per particle.
template <int D> constexpr int kCorners = 1 << D;

/// Centre along axis d of the box spanned by a particle's 2^D corners (D values each).
template <int D> inline double cornerBoxCentre(const double *c, int d) {
  double lo = c[d], hi = c[d];
  for (int q = 1; q < kCorners<D>; ++q) {
    lo = std::min(lo, c[D * q + d]);
    hi = std::max(hi, c[D * q + d]);
  }
  return 0.5 * (lo + hi);
}

/// The CPDI parallelogram (parallelepiped) of particle k: corner q at x_p + sum_a s_a(q) r_a
/// with r_a = F r_a^0, r_a^0 = l0_a e_a, into c (D 2^D values).
template <int D> inline void cpdiParallelogram(const ParticleView<D> &p, PetscInt k, double *c) {
  const auto F = tensorAt<D>(p.F, k);
  double r[D][D]; // r[a]: F's column a times l0_a
  for (int a = 0; a < D; ++a)
    for (int d = 0; d < D; ++d)
      r[a][d] = F(d, a) * p.l0[D * k + a];
  for (int q = 0; q < kCorners<D>; ++q)
    for (int d = 0; d < D; ++d) {
      double x = p.x[D * k + d];
      for (int a = 0; a < D; ++a)
        x += cpdi::cornerSign<D>(q, a) * r[a][d];
      c[D * q + d] = x;
    }
}

/// Half-sizes of a CPDI particle: the largest distance of a corner from x_p along each axis.
template <int D> inline void cornerReach(ParticleView<D> &p, PetscInt k, const double *c) {
  for (int d = 0; d < D; ++d) {
    double reach = 0;
    for (int q = 0; q < kCorners<D>; ++q)
      reach = std::max(reach, std::fabs(c[D * q + d] - p.x[D * k + d]));
    p.l[D * k + d] = reach;
  }
}

/// Area of the quadrilateral of four corners (counter-clockwise, shoelace).
inline double quadArea(const double *c) {
  return 0.5 * ((c[0] * c[3] - c[2] * c[1]) + (c[2] * c[5] - c[4] * c[3]) +
                (c[4] * c[7] - c[6] * c[5]) + (c[6] * c[1] - c[0] * c[7]));
}

/// The volume of a particle whose corners span c: V0 times the cell's area (volume) over the
/// initial box's, 2^D prod l0 (a cut cell's domain may be larger than its volume).
template <int D>
inline double volumeOfCorners(const ParticleView<D> &p, PetscInt k, const double *c) {
  if constexpr (D == 2) {
    return p.V0[k] * quadArea(c) / (4.0 * p.l0[2 * k] * p.l0[2 * k + 1]);
  } else {
    const double *l0 = &p.l0[3 * k];
    return p.V0[k] * cpdi::hexVolume(c) / (8.0 * l0[0] * l0[1] * l0[2]);
  }
}

/// The CPDI domains' corners of every particle: the parallelograms of F (cpdi, into `scratch`)
/// or the tracked corners (cpdi2).
template <int D>
const double *cpdiCorners(const Scene<D> &sc, const ParticleView<D> &p,
                          std::vector<double> &scratch);

/// Particle k's domain by cpdi, cpdi2 or corner tracking (updateDomain's other cases).
template <int D>
void updateTrackedDomain(const Scene<D> &sc, ParticleView<D> &p, PetscInt k, const Tensor<D> &L,
                         double dt);

/// Particle k's domain after its deformation gradient F (already updated) and velocity
/// gradient L over dt: half-sizes l, and with corners also the volume.
template <int D>
inline void updateDomain(const Scene<D> &sc, ParticleView<D> &p, PetscInt k, const Tensor<D> &L,
                         double dt) {
  switch (sc.tracking) {
  case Tracking::None:
    return;
  case Tracking::Strain:
    for (int a = 0; a < D; ++a) {
      p.eps[D * k + a] += dt * L(a, a);
      p.l[D * k + a] = (1.0 + p.eps[D * k + a]) * p.l0[D * k + a];
    }
    return;
  case Tracking::Stretch:
    if constexpr (D == 2) { // l_a = |F e_a| l0_a, both axes at once
      using simd::Pair;
      const Pair r0 = simd::load(&p.F[4 * k]), r1 = simd::load(&p.F[4 * k + 2]); // F's rows
      simd::store(&p.l[2 * k], simd::sqrt(r0 * r0 + r1 * r1) * simd::load(&p.l0[2 * k]));
    } else {
      const auto F = tensorAt<D>(p.F, k);
      for (int a = 0; a < D; ++a)
        p.l[D * k + a] = F.col(a).norm() * p.l0[D * k + a];
    }
    return;
  default:
    updateTrackedDomain(sc, p, k, L, dt);
  }
}

/// Where each particle's weights are centred: the material point, or with corner tracking the
/// centre of its corners' box (into `centre`, which then is returned). With cpdi and cpdi2
/// the material point (the crack side of a particle is its material point's).
template <int D>
const double *domainCentres(const ParticleView<D> &p, std::vector<double> &centre, Tracking t);

/// Moves the tracked corners with the grid velocity interpolated at each corner, as a particle
/// of the fictitious size -gimp_corner_size times the particle's (cornerSize 0: with the grid's
/// point shape functions, cpdi2's corner update of Sadeghirad et al. 2013), renormalised over the
/// nodes that carry mass. Neighbours' shared corners get the same velocity and stay together. At a
/// cracked node a corner takes the field of its particle's side (the side of the segment
/// from the material point to the node): a face's corners lie on the crack line, where the
/// corner's own position would give both faces' corners one side, and the lower face's corners
/// would follow the upper face.
template <int D> class CornerMotion {
public:
  /// vWindow: nodal velocity on the window; mWindow: nodal mass there (component 0). False when
  /// a corner's stencil cannot be built (a particle larger than a level-0 cell).
  /// particles: this step's particle stencils; with cornerSize 0 (cpdi2) they were built from
  /// these corners, and their corner weights are the point shape functions used.
  bool move(const Grid<D> &g, const std::vector<CrackOf<D>> &cracks, double cornerSize, double cut,
            double dt, const double *vWindow, const double *mWindow, const Stencils<D> &particles,
            ParticleView<D> &p);

private:
  Stencils<D> st_;
  std::vector<double> size_;
  std::vector<double> owner_; // each corner's material point, for the crack fields
};

} // namespace gimp::tracking
