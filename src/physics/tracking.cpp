#include "gimp/physics/tracking.hpp"

#include "gimp/cracks/fields.hpp"

namespace gimp::tracking {

const double *domainCentres(const ParticleView &p, std::vector<double> &centre, Tracking t) {
  if (!p.hasCorners || usesCpdi(t)) return p.x;
  // With corner tracking the particle's domain (chi_p of Eq. 10) is the rectangle its corners
  // span: the weights integrate over that rectangle, whose centre may differ from the material
  // point's position by a fraction of its size.
  centre.resize(2 * static_cast<size_t>(p.n));
  for (PetscInt k = 0; k < p.n; ++k) {
    centre[2 * k] = cornerBoxCentre(&p.corners[8 * k], 0);
    centre[2 * k + 1] = cornerBoxCentre(&p.corners[8 * k], 1);
  }
  return centre.data();
}

const double *cpdiCorners(const Scene &sc, const ParticleView &p, std::vector<double> &scratch) {
  if (sc.tracking == Tracking::Cpdi2) return p.corners;
  scratch.resize(8 * static_cast<size_t>(p.n));
  for (PetscInt k = 0; k < p.n; ++k)
    cpdiParallelogram(p, k, &scratch[8 * k]);
  return scratch.data();
}

bool CornerMotion::move(const Grid &g, const std::vector<Crack> &cracks, double cornerSize,
                        double cut, double dt, const double *vg, const double *mg,
                        ParticleView &p) {
  const size_t n4 = 4 * static_cast<size_t>(p.n);
  if (cornerSize == 0) { // the grid's point shape functions at the corners (cpdi2)
    if (!g.buildPointStencils(static_cast<PetscInt>(n4), p.corners, st_)) return false;
  } else {
    size_.resize(2 * n4);
    for (PetscInt k = 0; k < p.n; ++k)
      for (int q = 0; q < 4; ++q) {
        size_[8 * k + 2 * q] = cornerSize * p.l0[2 * k];
        size_[8 * k + 2 * q + 1] = cornerSize * p.l0[2 * k + 1];
      }
    if (!g.buildStencils(static_cast<PetscInt>(n4), p.corners, size_.data(), st_)) return false;
  }
  if (!cracks.empty()) {
    owner_.resize(2 * n4);
    for (PetscInt k = 0; k < p.n; ++k)
      for (int q = 0; q < 4; ++q) {
        owner_[8 * k + 2 * q] = p.x[2 * k];
        owner_[8 * k + 2 * q + 1] = p.x[2 * k + 1];
      }
    cracks::assignFields(g, cracks, static_cast<PetscInt>(n4), owner_.data(), st_);
  }
  const PetscInt *start = st_.start.data(), *node = st_.node.data();
  for (size_t c = 0; c < n4; ++c) {
    double vx = 0, vy = 0, wsum = 0;
    for (PetscInt e = start[c]; e < start[c + 1]; ++e) {
      if (!(mg[2 * node[e]] > cut)) continue;
      const double w = st_.weight(e);
      vx += w * vg[2 * node[e]];
      vy += w * vg[2 * node[e] + 1];
      wsum += w;
    }
    if (wsum > 0) {
      p.corners[2 * c] += dt * vx / wsum;
      p.corners[2 * c + 1] += dt * vy / wsum;
    }
  }
  return true;
}

} // namespace gimp::tracking
