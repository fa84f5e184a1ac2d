#include "gimp/physics/tracking.hpp"

#include "gimp/grid/crack_fields.hpp"

namespace gimp::tracking {

template <int D>
const double *domainCentres(const ParticleView<D> &p, std::vector<double> &centre, Tracking t) {
  if (!p.hasCorners || usesCpdi(t)) return p.x;
  // With corner tracking the particle's domain (chi_p of Eq. 10) is the box its corners span:
  // the weights integrate over that box, whose centre may differ from the material point's
  // position by a fraction of its size.
  centre.resize(D * static_cast<size_t>(p.n));
  for (PetscInt k = 0; k < p.n; ++k)
    for (int d = 0; d < D; ++d)
      centre[D * k + d] = cornerBoxCentre<D>(&p.corners[D * kCorners<D> * k], d);
  return centre.data();
}

template <int D>
const double *cpdiCorners(const Scene<D> &sc, const ParticleView<D> &p,
                          std::vector<double> &scratch) {
  if (sc.tracking == Tracking::Cpdi2) return p.corners;
  constexpr size_t m = D * kCorners<D>;
  scratch.resize(m * static_cast<size_t>(p.n));
  for (PetscInt k = 0; k < p.n; ++k)
    cpdiParallelogram<D>(p, k, &scratch[m * k]);
  return scratch.data();
}

template <int D>
bool CornerMotion<D>::move(const Grid<D> &g, const std::vector<CrackOf<D>> &cracks,
                           double cornerSize, double cut, double dt, const double *vg,
                           const double *mg, const Stencils<D> &particles, ParticleView<D> &p) {
  constexpr int nc = kCorners<D>;
  const size_t nCorners = nc * static_cast<size_t>(p.n);
  if (cornerSize == 0) {
    // cpdi2: the grid's point shape functions at the corners are the particles' own corner
    // weights (Grid::buildCpdiStencils built this step's stencils from these corners), on the
    // nodes the particle's crack fields chose from its material point.
    const PetscInt *start = particles.start.data(), *node = particles.node.data();
    const double *cw = particles.cw.data();
    for (PetscInt k = 0; k < p.n; ++k) {
      double v[nc][D] = {}, wsum[nc] = {};
      for (PetscInt e = start[k]; e < start[k + 1]; ++e) {
        if (!(mg[D * node[e]] > cut)) continue;
        const double *u = &vg[D * node[e]];
        for (int q = 0; q < nc; ++q) { // (a corner the node misses adds 0)
          const double w = cw[nc * e + q];
          for (int a = 0; a < D; ++a)
            v[q][a] += w * u[a];
          wsum[q] += w;
        }
      }
      for (int q = 0; q < nc; ++q)
        if (wsum[q] > 0)
          for (int a = 0; a < D; ++a)
            p.corners[D * (nc * k + q) + a] += dt * v[q][a] / wsum[q];
    }
    return true;
  }
  size_.resize(D * nCorners);
  for (PetscInt k = 0; k < p.n; ++k)
    for (int q = 0; q < nc; ++q)
      for (int a = 0; a < D; ++a)
        size_[D * (nc * k + q) + a] = cornerSize * p.l0[D * k + a];
  if (!g.buildStencils(static_cast<PetscInt>(nCorners), p.corners, size_.data(), st_)) return false;
  if (!cracks.empty()) {
    owner_.resize(D * nCorners);
    for (PetscInt k = 0; k < p.n; ++k)
      for (int q = 0; q < nc; ++q)
        for (int a = 0; a < D; ++a)
          owner_[D * (nc * k + q) + a] = p.x[D * k + a];
    cracks::assignFields<D>(g, cracks, static_cast<PetscInt>(nCorners), owner_.data(), st_);
  }
  const PetscInt *start = st_.start.data(), *node = st_.node.data();
  for (size_t c = 0; c < nCorners; ++c) {
    double v[D] = {}, wsum = 0;
    for (PetscInt e = start[c]; e < start[c + 1]; ++e) {
      if (!(mg[D * node[e]] > cut)) continue;
      const double w = st_.weight(e);
      for (int a = 0; a < D; ++a)
        v[a] += w * vg[D * node[e] + a];
      wsum += w;
    }
    if (wsum > 0)
      for (int a = 0; a < D; ++a)
        p.corners[D * c + a] += dt * v[a] / wsum;
  }
  return true;
}

namespace {

/// Corner tracking (the paper's section 4.1): the domain is the axis-aligned box the corners
/// span, the volume the cell's (quadrilateral's, hexahedron's).
template <int D>
void updateCornerBox(const Scene<D> &sc, ParticleView<D> &p, PetscInt k, const Tensor<D> &L,
                     double dt) {
  constexpr int nc = kCorners<D>;
  for (int a = 0; a < D; ++a)
    p.eps[D * k + a] += dt * L(a, a);
  double *c = &p.corners[D * nc * k];
  // Exterior corners of a particle on a loaded face follow its strain (the paper, 4.2).
  for (int a = 0; a < D && p.trac; ++a) {
    if (p.trac[D * k + a] < 0) continue;
    const double n = sc.tractions[p.trac[D * k + a]].normal();
    for (int q = 0; q < nc; ++q) {
      if (cpdi::cornerSign<D>(q, a) != n) continue;
      for (int d = 0; d < D; ++d)
        c[D * q + d] =
            p.x[D * k + d] + cpdi::cornerSign<D>(q, d) * (1.0 + p.eps[D * k + d]) * p.l0[D * k + d];
    }
  }
  for (int d = 0; d < D; ++d) {
    double lo = c[d], hi = c[d];
    for (int q = 1; q < nc; ++q) {
      lo = std::min(lo, c[D * q + d]);
      hi = std::max(hi, c[D * q + d]);
    }
    p.l[D * k + d] = 0.5 * (hi - lo);
  }
  p.V[k] = volumeOfCorners<D>(p, k, c);
}

} // namespace

template <int D>
void updateTrackedDomain(const Scene<D> &sc, ParticleView<D> &p, PetscInt k, const Tensor<D> &L,
                         double dt) {
  constexpr size_t m = D * kCorners<D>;
  switch (sc.tracking) {
  case Tracking::None:
  case Tracking::Strain:
  case Tracking::Stretch:
    return updateDomain(sc, p, k, L, dt);
  case Tracking::Cpdi: { // the volume stays det(F) V0
    double c[m];
    cpdiParallelogram<D>(p, k, c);
    cornerReach<D>(p, k, c);
    return;
  }
  case Tracking::Cpdi2: // the corners moved in G2P; the volume follows the cell's
    cornerReach<D>(p, k, &p.corners[m * k]);
    p.V[k] = volumeOfCorners<D>(p, k, &p.corners[m * k]);
    return;
  case Tracking::Corners:
    updateCornerBox(sc, p, k, L, dt);
    return;
  }
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template const double *domainCentres<D>(const ParticleView<D> &, std::vector<double> &,          \
                                          Tracking);                                               \
  template const double *cpdiCorners<D>(const Scene<D> &, const ParticleView<D> &,                 \
                                        std::vector<double> &);                                    \
  template void updateTrackedDomain<D>(const Scene<D> &, ParticleView<D> &, PetscInt,              \
                                       const Tensor<D> &, double);                                 \
  template class CornerMotion<D>;
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp::tracking
