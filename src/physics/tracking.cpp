#include "gimp/physics/tracking.hpp"

#include "gimp/grid/crack_fields.hpp"

namespace gimp::tracking {

const double *domainCentres(const ParticleView<2> &p, std::vector<double> &centre, Tracking t) {
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

const double *cpdiCorners(const Scene<2> &sc, const ParticleView<2> &p,
                          std::vector<double> &scratch) {
  if (sc.tracking == Tracking::Cpdi2) return p.corners;
  scratch.resize(8 * static_cast<size_t>(p.n));
  for (PetscInt k = 0; k < p.n; ++k)
    cpdiParallelogram(p, k, &scratch[8 * k]);
  return scratch.data();
}

bool CornerMotion::move(const Grid<2> &g, const std::vector<Crack> &cracks, double cornerSize,
                        double cut, double dt, const double *vg, const double *mg,
                        ParticleView<2> &p) {
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

void updateTrackedDomain(const Scene<2> &sc, ParticleView<2> &p, PetscInt k, const Tensor<2> &L,
                         double dt) {
  switch (sc.tracking) {
  case Tracking::None:
  case Tracking::Strain:
  case Tracking::Stretch:
    return updateDomain(sc, p, k, L, dt);
  case Tracking::Cpdi: { // the volume stays det(F) V0
    double c[8];
    cpdiParallelogram(p, k, c);
    cornerReach(p, k, c);
    return;
  }
  case Tracking::Cpdi2: // the corners moved in G2P; the volume follows the quad's area
    cornerReach(p, k, &p.corners[8 * k]);
    p.V[k] = volumeOfCorners(p, k, &p.corners[8 * k]);
    return;
  case Tracking::Corners:
    break;
  }
  p.eps[2 * k] += dt * L(0, 0);
  p.eps[2 * k + 1] += dt * L(1, 1);
  double *c = &p.corners[8 * k];
  // Exterior corners of a particle on a loaded edge follow its strain (the paper, 4.2).
  for (int a = 0; a < 2 && p.trac; ++a) {
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
  p.V[k] = volumeOfCorners(p, k, c);
}

} // namespace gimp::tracking
