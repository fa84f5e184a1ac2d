#include "gimp/cracks/tips.hpp"

#include "gimp/physics/material.hpp"

#include <cmath>
#include <limits>

namespace gimp::cracks {

std::vector<TipMeasure> tipsOf(const Scene &sc) {
  std::vector<TipMeasure> out;
  for (size_t k = 0; k < sc.cracks.size(); ++k)
    for (int e = 0; e < 2; ++e)
      if (sc.cracks[k].tip[e]) {
        TipMeasure m;
        m.crack = static_cast<int>(k);
        m.end = e;
        const auto &pt = e == 0 ? sc.cracks[k].points.front() : sc.cracks[k].points.back();
        m.tip[0] = pt[0];
        m.tip[1] = pt[1];
        out.push_back(m);
      }
  return out;
}

namespace {

/// The tip frame: t toward the tip along the last segment, n = its left normal (as the segment
/// runs toward the tip).
void tipFrame(const Crack &c, int end, double t[2], double n[2]) {
  const size_t m = c.points.size();
  const auto &a = end == 0 ? c.points[1] : c.points[m - 2];
  const auto &b = end == 0 ? c.points[0] : c.points[m - 1];
  const double dx = b[0] - a[0], dy = b[1] - a[1], len = std::hypot(dx, dy);
  t[0] = dx / len;
  t[1] = dy / len;
  n[0] = -t[1];
  n[1] = t[0];
}

double modulus(const Material &m) {
  return m.planeStrain ? m.E / (1.0 - m.nu * m.nu) : m.E;
}

/// Particle k's term of the J domain integral, V_p (sigma_ij du_i/dx_1 - W delta_1j) dq/dx_j
/// in the tip frame (t, n), at tip-frame position (along, across), distance rr < R.
double jIntegrand(const Scene &sc, const ParticleView &p, PetscInt k, const double t[2],
                  const double n[2], double along, double across, double rr, double R) {
  const auto s = tensorAt<2>(p.s, k);
  const auto F = tensorAt<2>(p.F, k);
  const double H[2][2] = {{F(0, 0) - 1.0, F(0, 1)}, {F(1, 0), F(1, 1) - 1.0}};
  const double Q[2][2] = {{t[0], t[1]}, {n[0], n[1]}};
  double sp[2][2] = {}, hp[2][2] = {}; // sigma and grad u in the tip frame
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c)
        for (int d = 0; d < 2; ++d) {
          sp[a][b] += Q[a][c] * s(c, d) * Q[b][d];
          hp[a][b] += Q[a][c] * H[c][d] * Q[b][d];
        }
  const double W = material::strainEnergy(sc.material, s, p.szz[k], F, p.V0[k], p.V[k]) / p.V[k];
  const double dq[2] = {-along / (rr * R), -across / (rr * R)};
  double integrand = 0;
  for (int j = 0; j < 2; ++j) {
    double term = -(j == 0 ? W : 0.0);
    for (int i = 0; i < 2; ++i)
      term += sp[i][j] * hp[i][0];
    integrand += term * dq[j];
  }
  return p.V[k] * integrand;
}

/// G and K of one tip from its reduced row: r[0..1] the n side's force on the tip node, r[2] J
/// times thickness, then the two particle pairs (ux, uy, distance behind the tip) from r[4] on;
/// h the cell behind the tip. Crack closure over one cell: the tip node's force times the
/// opening one cell behind the tip, interpolated between the two pairs.
void finishTip(const Scene &sc, const double *r, double h, TipMeasure &m) {
  constexpr int kPairs = 2;
  double t[2], n[2];
  tipFrame(sc.cracks[m.crack], m.end, t, n);
  const double Ep = modulus(sc.material), th = sc.material.thickness;
  double du[kPairs][2], behind[kPairs];
  for (int pair = 0; pair < kPairs; ++pair) {
    const double *a = &r[4 + 3 * (2 * pair)], *b = &r[4 + 3 * (2 * pair + 1)];
    du[pair][0] = a[0] - b[0];
    du[pair][1] = a[1] - b[1];
    behind[pair] = 0.5 * (a[2] + b[2]);
  }
  const double w = (h - behind[0]) / (behind[1] - behind[0]);
  const double dux = du[0][0] + w * (du[1][0] - du[0][0]),
               duy = du[0][1] + w * (du[1][1] - du[0][1]);
  const double dun = dux * n[0] + duy * n[1], dut = dux * t[0] + duy * t[1];
  const double Fn = r[0] * n[0] + r[1] * n[1], Ft = r[0] * t[0] + r[1] * t[1];
  m.G_vcct = Fn * dun / (2.0 * th * h);
  m.GII_vcct = Ft * dut / (2.0 * th * h);
  m.G_J = r[2] / th;
  m.KI_vcct = std::copysign(std::sqrt(std::fabs(m.G_vcct) * Ep), m.G_vcct);
  m.KII_vcct = std::copysign(std::sqrt(std::fabs(m.GII_vcct) * Ep), dut);
  m.KI_J = std::copysign(std::sqrt(std::fabs(m.G_J) * Ep), m.G_J);
}

} // namespace

PetscErrorCode measureTips(MPI_Comm comm, const Scene &sc, const Grid &g, const Stencils<kDim> &st,
                           const ParticleView &p, double jRadius, std::vector<TipMeasure> &tips) {
  tips = tipsOf(sc);
  const size_t T = tips.size();
  if (T == 0) return PETSC_SUCCESS;
  // Particles 1 and 2: smallest squared distance of X0 to their targets (min over ranks), then
  // their displacement and current position from the rank that has them.
  constexpr int kRow = 16, kPairs = 2;
  std::vector<double> dist(2 * kPairs * T, std::numeric_limits<double>::infinity()),
      gdist(2 * kPairs * T);
  std::vector<double> local(kRow * T, 0.0), global(kRow * T);
  for (size_t q = 0; q < T; ++q) {
    const TipMeasure &m = tips[q];
    double t[2], n[2];
    tipFrame(sc.cracks[m.crack], m.end, t, n);
    // The tip node: the window node nearest to the tip (the tip lies on a node in the scenes).
    // A rank whose window does not hold it finds none (its particles do not reach it).
    PetscInt tipNode = -1;
    for (PetscInt nd = 0; nd < g.nWindow; ++nd)
      if (g.active[nd] && std::hypot(g.X[nd] - m.tip[0], g.Y[nd] - m.tip[1]) <= 1e-9 * g.h0())
        tipNode = nd;
    const bool stencils = st.start.size() == static_cast<size_t>(p.n) + 1;
    double *r = &local[kRow * q];
    // The cell behind the tip: the tip node's zone on the side the crack comes from.
    if (tipNode >= 0) {
      const double *z = &g.zone[4 * tipNode];
      r[3] =
          std::fabs(t[0]) >= std::fabs(t[1]) ? (t[0] > 0 ? z[0] : z[1]) : (t[1] > 0 ? z[2] : z[3]);
    }
    for (PetscInt k = 0; k < p.n; ++k) {
      const double rx = p.x[2 * k] - m.tip[0], ry = p.x[2 * k + 1] - m.tip[1];
      const double along = rx * t[0] + ry * t[1], across = rx * n[0] + ry * n[1];
      const auto s = tensorAt<2>(p.s, k);
      // One side's internal force on the tip node (the n side of the crack line).
      if (across > 0 && tipNode >= 0 && stencils)
        for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
          if (g.slotNode[st.node[e]] != tipNode) continue;
          const Vector<2> grad = st.gradient(e);
          for (int c = 0; c < 2; ++c)
            r[c] -= p.V[k] * (s(c, 0) * grad[0] + s(c, 1) * grad[1]);
        }
      // The particle pairs whose centres started nearest to h - l0 and h + l0 behind the tip,
      // l0 from either side of the crack line (h: the cell behind the tip, from the reduction
      // below; here the particle's own l0 scales the targets: 3 l0 and 5 l0 for h = 4 l0).
      const double l0 = p.l0[2 * k];
      for (int pair = 0; pair < kPairs; ++pair)
        for (int side = 0; side < 2; ++side) {
          const double sgn = side == 0 ? 1.0 : -1.0, back = (pair == 0 ? 3.0 : 5.0) * l0;
          const double tx = m.tip[0] - back * t[0] + sgn * l0 * n[0],
                       ty = m.tip[1] - back * t[1] + sgn * l0 * n[1];
          const double d2 = (p.X0[2 * k] - tx) * (p.X0[2 * k] - tx) +
                            (p.X0[2 * k + 1] - ty) * (p.X0[2 * k + 1] - ty);
          const int j = 2 * pair + side;
          if (d2 < dist[2 * kPairs * q + j]) {
            dist[2 * kPairs * q + j] = d2;
            double *o = &r[4 + 3 * j]; // ux, uy, distance behind the tip along t
            o[0] = p.x[2 * k] - p.X0[2 * k];
            o[1] = p.x[2 * k + 1] - p.X0[2 * k + 1];
            o[2] = -along;
          }
        }
      // J: domain integral with q = 1 - r / R.
      const double rr = std::hypot(rx, ry);
      if (rr < jRadius && rr > 0) r[2] += jIntegrand(sc, p, k, t, n, along, across, rr, jRadius);
    }
  }
  PetscCallMPI(MPI_Allreduce(dist.data(), gdist.data(), static_cast<int>(dist.size()), MPI_DOUBLE,
                             MPI_MIN, comm));
  // The cell behind the tip comes from the ranks that hold the tip node (the same value).
  std::vector<double> hloc(T), hmax(T);
  for (size_t q = 0; q < T; ++q) {
    hloc[q] = local[kRow * q + 3];
    local[kRow * q + 3] = 0.0;
  }
  PetscCallMPI(
      MPI_Allreduce(hloc.data(), hmax.data(), static_cast<int>(T), MPI_DOUBLE, MPI_MAX, comm));
  // Keep particle data only on the rank that holds the nearest particle (ties: it is the same
  // particle, held once), so that the sum below picks it.
  for (size_t q = 0; q < T; ++q)
    for (int j = 0; j < 2 * kPairs; ++j)
      if (dist[2 * kPairs * q + j] != gdist[2 * kPairs * q + j])
        for (int c = 0; c < 3; ++c)
          local[kRow * q + 4 + 3 * j + c] = 0.0;
  PetscCallMPI(MPI_Allreduce(local.data(), global.data(), static_cast<int>(local.size()),
                             MPI_DOUBLE, MPI_SUM, comm));
  for (size_t q = 0; q < T; ++q) {
    finishTip(sc, &global[kRow * q], hmax[q], tips[q]);
  }
  return PETSC_SUCCESS;
}

} // namespace gimp::cracks
