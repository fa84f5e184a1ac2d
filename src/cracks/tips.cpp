#include "gimp/cracks/tips.hpp"

#include "gimp/cracks/williams.hpp"
#include "gimp/grid/shape.hpp"
#include "gimp/physics/material.hpp"

#include <cmath>
#include <limits>

namespace gimp::cracks {

std::vector<TipMeasure> tipsOf(const Scene<2> &sc) {
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
        if (out.size() < sc.jDomain.size()) {
          m.jRadius = sc.jDomain[out.size()].radius;
          m.jClipped = sc.jDomain[out.size()].clipped;
        }
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

/// Particle k's terms of the domain integrals at tip-frame position (along, across), distance
/// rr < R, with q = (1 - r^2 / R^2)^2, added to out: J = sum_p V_p (sigma_ij du_i/dx_1 - W
/// delta_1j) dq/dx_j, and the interaction integrals with the unit mode I and mode II tip fields,
/// I_m = sum_p V_p (sigma_ij du^m_i/dx_1 + sigma^m_ij du_i/dx_1 - sigma^m_ij eps_ij delta_1j)
/// dq/dx_j, all in the tip frame (t, n).
void domainTerms(const Material &mat, const TipElastic &el, const ParticleView<2> &p, PetscInt k,
                 const double t[2], const double n[2], double along, double across, double rr,
                 double R, double out[3]) {
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
  const double W = material::strainEnergy(mat, s, p.szz[k], F, p.V0[k], p.V[k]) / p.V[k];
  // q = (1 - r^2 / R^2)^2: its gradient vanishes at the tip and at R, so the particle sum of
  // the integrand (bounded, continuous) has no O(h / R) quadrature error from either end.
  const double fall = -4.0 / (R * R) * (1.0 - rr * rr / (R * R));
  const double dq[2] = {fall * along, fall * across};
  double j = 0;
  for (int b = 0; b < 2; ++b)
    j += (sp[0][b] * hp[0][0] + sp[1][b] * hp[1][0] - (b == 0 ? W : 0.0)) * dq[b];
  out[0] += p.V[k] * j;
  const double theta = std::atan2(across, along);
  const double eps[3] = {hp[0][0], hp[1][1], 0.5 * (hp[0][1] + hp[1][0])};
  for (int mode = 1; mode <= 2; ++mode) {
    double sa[3], ua[2];
    williamsField(mode, rr, theta, el, sa, ua);
    const double S[2][2] = {{sa[0], sa[2]}, {sa[2], sa[1]}};
    const double Wint = sa[0] * eps[0] + sa[1] * eps[1] + 2.0 * sa[2] * eps[2];
    double m = 0;
    for (int b = 0; b < 2; ++b)
      m += (sp[0][b] * ua[0] + sp[1][b] * ua[1] + S[0][b] * hp[0][0] + S[1][b] * hp[1][0] -
            (b == 0 ? Wint : 0.0)) *
           dq[b];
    out[mode] += p.V[k] * m;
  }
}

/// GIMP weight and gradient (d/dx_p) of a regular node of cell h at (X, Y) for particle k: the
/// grid's own kernel (Eq. 15) moved to a point that need not be a grid node.
double pointKernel(const ParticleView<2> &p, PetscInt k, double X, double Y, double h,
                   double grad[2]) {
  double wx, gx, wy, gy;
  shape::weightAndGradient(p.x[2 * k] - X, p.l[2 * k], h, h, wx, gx);
  shape::weightAndGradient(p.x[2 * k + 1] - Y, p.l[2 * k + 1], h, h, wy, gy);
  grad[0] = gx * wy;
  grad[1] = wx * gy;
  return wx * wy;
}

// The reduced row of one tip: the n side's force on the tip point (2); J and the mode I and II
// interaction integrals, times thickness (3); then sum m w u and sum m w of each side at the
// point one cell behind the tip (3 + 3).
constexpr int kForce = 0, kJ = 2, kPlus = 5, kMinus = 8, kRow = 11;

/// G and K of one tip from its reduced row r; h the cell at the tip.
void finishTip(const Scene<2> &sc, const double *r, double h, TipMeasure &m) {
  double t[2], n[2];
  tipFrame(sc.cracks[m.crack], m.end, t, n);
  const Material &mat = sc.materialAt(m.tip);
  const double Ep = modulus(mat), th = sc.material.thickness;
  const double *up = &r[kPlus], *dn = &r[kMinus];
  double dux = 0, duy = 0;
  if (up[2] > 0 && dn[2] > 0) {
    dux = up[0] / up[2] - dn[0] / dn[2];
    duy = up[1] / up[2] - dn[1] / dn[2];
  }
  const double dun = dux * n[0] + duy * n[1], dut = dux * t[0] + duy * t[1];
  const double Fn = r[kForce] * n[0] + r[kForce + 1] * n[1],
               Ft = r[kForce] * t[0] + r[kForce + 1] * t[1];
  m.h = h;
  m.opening[0] = dun;
  m.opening[1] = dut;
  m.G_vcct = Fn * dun / (2.0 * th * h);
  m.GII_vcct = Ft * dut / (2.0 * th * h);
  const double none = m.jRadius > 0 ? 1.0 : std::numeric_limits<double>::quiet_NaN();
  m.G_J = none * r[kJ] / th;
  m.KI_vcct = std::copysign(std::sqrt(std::fabs(m.G_vcct) * Ep), m.G_vcct);
  m.KII_vcct = std::copysign(std::sqrt(std::fabs(m.GII_vcct) * Ep), dut);
  // The interaction integrals with the unit tip fields: I_m = 2 K_m / E'.
  m.KI_J = none * 0.5 * Ep * r[kJ + 1] / th;
  m.KII_J = none * 0.5 * Ep * r[kJ + 2] / th;
}

} // namespace

TipElastic tipElastic(const Material &m) {
  TipElastic e;
  e.mu = m.E / (2.0 * (1.0 + m.nu));
  e.kappa = m.planeStrain ? 3.0 - 4.0 * m.nu : (3.0 - m.nu) / (1.0 + m.nu);
  return e;
}

void addDomainIntegrals(const Material &mat, const ParticleView<2> &p, const double tip[2],
                        const double t[2], double R, double out[3]) {
  const TipElastic el = tipElastic(mat);
  const double n[2] = {-t[1], t[0]};
  for (PetscInt k = 0; k < p.n; ++k) {
    const double rx = p.x[2 * k] - tip[0], ry = p.x[2 * k + 1] - tip[1];
    const double rr = std::hypot(rx, ry);
    if (rr < R && rr > 0)
      domainTerms(mat, el, p, k, t, n, rx * t[0] + ry * t[1], rx * n[0] + ry * n[1], rr, R, out);
  }
}

PetscErrorCode measureTips(MPI_Comm comm, const Scene<2> &sc, const Grid<2> &g,
                           const ParticleView<2> &p, std::vector<TipMeasure> &tips) {
  tips = tipsOf(sc);
  const size_t T = tips.size();
  if (T == 0) return PETSC_SUCCESS;
  std::vector<double> local(kRow * T, 0.0), global(kRow * T);
  std::vector<double> cell(T);
  for (size_t q = 0; q < T; ++q) {
    const TipMeasure &m = tips[q];
    const Crack &crack = sc.cracks[m.crack];
    double t[2], n[2];
    tipFrame(crack, m.end, t, n);
    const double h = cell[q] = g.levels[g.leafLevelAt(m.tip[0], m.tip[1])].h;
    // The point one cell behind the tip, on the crack line; a particle is on the side of the
    // crack's left normal there unless the segment to the point crosses the crack.
    const double bx = m.tip[0] - h * t[0], by = m.tip[1] - h * t[1];
    double nl[2];
    normalAt(crack, bx, by, nl);
    const bool plusIsLeft = nl[0] * n[0] + nl[1] * n[1] > 0;
    double *r = &local[kRow * q];
    for (PetscInt k = 0; k < p.n; ++k) {
      const double rx = p.x[2 * k] - m.tip[0], ry = p.x[2 * k + 1] - m.tip[1];
      const double across = rx * n[0] + ry * n[1];
      double grad[2];
      // One side's grip on the tip: the n-side particles' internal force on a node at the tip.
      if (across > 0 && pointKernel(p, k, m.tip[0], m.tip[1], h, grad) > 0) {
        const auto s = tensorAt<2>(p.s, k);
        for (int c = 0; c < 2; ++c)
          r[kForce + c] -= p.V[k] * (s(c, 0) * grad[0] + s(c, 1) * grad[1]);
      }
      // Each side's displacement at the point one cell behind the tip (mass projection).
      const double w = pointKernel(p, k, bx, by, h, grad);
      if (w > 0) {
        const bool left = crossing(crack, p.x[2 * k], p.x[2 * k + 1], bx, by) == 0;
        double *o = &r[left == plusIsLeft ? kPlus : kMinus];
        o[0] += p.m[k] * w * (p.x[2 * k] - p.X0[2 * k]);
        o[1] += p.m[k] * w * (p.x[2 * k + 1] - p.X0[2 * k + 1]);
        o[2] += p.m[k] * w;
      }
    }
    if (m.jRadius > 0) addDomainIntegrals(sc.materialAt(m.tip), p, m.tip, t, m.jRadius, &r[kJ]);
  }
  PetscCallMPI(MPI_Allreduce(local.data(), global.data(), static_cast<int>(local.size()),
                             MPI_DOUBLE, MPI_SUM, comm));
  for (size_t q = 0; q < T; ++q)
    finishTip(sc, &global[kRow * q], cell[q], tips[q]);
  return PETSC_SUCCESS;
}

} // namespace gimp::cracks
