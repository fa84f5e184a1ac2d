#include "gimp/cracks/tips.hpp"

#include "gimp/cracks/williams.hpp"
#include "gimp/grid/shape.hpp"
#include "gimp/physics/material.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

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

/// The crack seen from a tip, as the auxiliary fields' branch cut: its points behind the tip in
/// the tip frame, each with its angle unwrapped continuously along the crack from pi (the tip
/// segment's). On a kinked crack the straight fields' cut (theta = +-pi) would lie in the material
/// past the kink, where their displacement jumps; with theta unwrapped to (cut(r) - 2 pi, cut(r)],
/// cut(r) the crack's angle where it meets the circle of radius r, the jump lies on the crack's
/// faces, and the fields are smooth in the material (their tractions on the faces that are not
/// along x1 are the face terms, addFaceTerms). A straight crack's cut is pi: theta unchanged.
struct BranchCut {
  std::vector<std::array<double, 2>> pts; // tip frame (along, across); pts[0] the tip
  std::vector<double> ang;                // unwrapped angle of pts[i], i >= 1

  BranchCut() = default; // a straight crack's: the line behind the tip
  BranchCut(const Crack &c, int end, const double tip[2], const double t[2]) {
    const size_t np = c.points.size();
    const double n[2] = {-t[1], t[0]};
    for (size_t i = 0; i < np; ++i) {
      const auto &q = end == 0 ? c.points[i] : c.points[np - 1 - i];
      const double dx = q[0] - tip[0], dy = q[1] - tip[1];
      pts.push_back({dx * t[0] + dy * t[1], dx * n[0] + dy * n[1]});
      if (i == 0) {
        ang.push_back(M_PI);
      } else if (i == 1) {
        ang.push_back(M_PI); // the tip segment lies on theta = pi
      } else {
        const double a = std::atan2(pts[i][1], pts[i][0]);
        ang.push_back(ang[i - 1] + std::remainder(a - ang[i - 1], 2.0 * M_PI));
      }
    }
  }
  /// The crack's angle where it first meets the circle of radius r (the last point's beyond it).
  double at(double r) const {
    if (pts.size() < 3 || r <= std::hypot(pts[1][0], pts[1][1])) return M_PI; // the tip segment
    for (size_t i = 1; i + 1 < pts.size(); ++i) {
      const auto &a = pts[i], &b = pts[i + 1];
      if (std::hypot(b[0], b[1]) < r) continue;
      // a + s (b - a) on the circle, the root past a (a is inside it).
      const double dx = b[0] - a[0], dy = b[1] - a[1];
      const double A = dx * dx + dy * dy, B = 2.0 * (a[0] * dx + a[1] * dy),
                   C = a[0] * a[0] + a[1] * a[1] - r * r;
      const double sr = (-B + std::sqrt(std::max(B * B - 4.0 * A * C, 0.0))) / (2.0 * A);
      const double x = a[0] + sr * dx, y = a[1] + sr * dy;
      return ang[i] + std::remainder(std::atan2(y, x) - ang[i], 2.0 * M_PI);
    }
    return ang.back();
  }
  /// theta in (cut - 2 pi, cut].
  static double unwrap(double theta, double cut) {
    while (theta > cut)
      theta -= 2.0 * M_PI;
    while (theta <= cut - 2.0 * M_PI)
      theta += 2.0 * M_PI;
    return theta;
  }
};

/// Particle k's stress sp and displacement gradient hp (F - I) in the tip frame (t, n), and its
/// strain energy density W.
struct TipState {
  double sp[2][2] = {}, hp[2][2] = {};
  double W = 0;
};

TipState tipState(const Material &mat, const ParticleView<2> &p, PetscInt k, const double t[2],
                  const double n[2]) {
  const Tensor<2> s = stressAt<2>(p.s, k);
  const auto F = tensorAt<2>(p.F, k);
  const double H[2][2] = {{F(0, 0) - 1.0, F(0, 1)}, {F(1, 0), F(1, 1) - 1.0}};
  const double Q[2][2] = {{t[0], t[1]}, {n[0], n[1]}};
  TipState st;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c)
        for (int d = 0; d < 2; ++d) {
          st.sp[a][b] += Q[a][c] * s(c, d) * Q[b][d];
          st.hp[a][b] += Q[a][c] * H[c][d] * Q[b][d];
        }
  st.W = material::strainEnergy(mat, s, p.szz[k], F, p.V0[k], p.V[k]) / p.V[k];
  return st;
}

/// Particle k's terms of the domain integrals at tip-frame position (along, across), distance
/// rr < R, with q = (1 - r^2 / R^2)^2, added to out: J = sum_p V_p (sigma_ij du_i/dx_1 - W
/// delta_1j) dq/dx_j, and the interaction integrals with the unit mode I and mode II tip fields,
/// I_m = sum_p V_p (sigma_ij du^m_i/dx_1 + sigma^m_ij du_i/dx_1 - sigma^m_ij eps_ij delta_1j)
/// dq/dx_j, all in the tip frame (t, n).
void domainTerms(const Material &mat, const TipElastic &el, const ParticleView<2> &p, PetscInt k,
                 const double t[2], const double n[2], double along, double across, double rr,
                 double theta, double R, double out[3]) {
  const TipState st = tipState(mat, p, k, t, n);
  const auto &sp = st.sp, &hp = st.hp;
  const double W = st.W;
  // q = (1 - r^2 / R^2)^2: its gradient vanishes at the tip and at R, so the particle sum of
  // the integrand (bounded, continuous) has no O(h / R) quadrature error from either end.
  const double fall = -4.0 / (R * R) * (1.0 - rr * rr / (R * R));
  const double dq[2] = {fall * along, fall * across};
  double j = 0;
  for (int b = 0; b < 2; ++b)
    j += (sp[0][b] * hp[0][0] + sp[1][b] * hp[1][0] - (b == 0 ? W : 0.0)) * dq[b];
  out[0] += p.V[k] * j;
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
// interaction integrals, times thickness (3).
constexpr int kForce = 0, kJ = 2, kRow = 5;

/// The nodal displacements behind the tip, fitted to the particles' displacements on a lattice
/// of the tip's cell h centred on the point b one cell behind the tip: nodes b + (i h, j h),
/// |i|, |j| <= kFitHalf, each with the two fields of a cracked node.
constexpr int kFitHalf = 3, kFitSide = 2 * kFitHalf + 1, kFitNodes = kFitSide * kFitSide,
              kFitUnknowns = 2 * kFitNodes;
/// Its reduced sums: the normal matrix (kFitUnknowns^2), then the right-hand sides of the two
/// displacement components (2 kFitUnknowns).
constexpr int kFitRow = kFitUnknowns * kFitUnknowns + 2 * kFitUnknowns;

/// Adds particle k's terms to the fit of one tip (sums `fit`, lattice centred on (bx, by), cell
/// h): the mass-weighted least-squares fit of nodal displacements u_a to the particle's
/// displacement, u_p = sum_a S_ap u_a, the inverse of the grid's interpolation. u_p is the
/// displacement that goes with the particle's F (p.us: integrated from the velocity field that
/// updates the stress). The entry a of a node is the field the particle joins there (field 2
/// when the segment from the particle to the node crosses the crack, as the grid decides it).
/// Only particles whose every weight falls on the lattice.
void addFitTerms(const Crack &crack, const ParticleView<2> &p, PetscInt k, double bx, double by,
                 double h, double *fit) {
  const double dx = p.x[2 * k] - bx, dy = p.x[2 * k + 1] - by;
  if (std::fabs(dx) + p.l[2 * k] >= kFitHalf * h || std::fabs(dy) + p.l[2 * k + 1] >= kFitHalf * h)
    return;
  int idx[kFitNodes];
  double w[kFitNodes];
  int m = 0;
  const int i0 = std::max(-kFitHalf, static_cast<int>(std::floor(dx / h)) - 2),
            i1 = std::min(kFitHalf, static_cast<int>(std::ceil(dx / h)) + 2),
            j0 = std::max(-kFitHalf, static_cast<int>(std::floor(dy / h)) - 2),
            j1 = std::min(kFitHalf, static_cast<int>(std::ceil(dy / h)) + 2);
  for (int i = i0; i <= i1; ++i)
    for (int j = j0; j <= j1; ++j) {
      const double X = bx + i * h, Y = by + j * h;
      double grad[2];
      const double wa = pointKernel(p, k, X, Y, h, grad);
      if (wa <= 0) continue;
      const int field = crossing(crack, p.x[2 * k], p.x[2 * k + 1], X, Y) != 0 ? 1 : 0;
      idx[m] = 2 * ((i + kFitHalf) * kFitSide + (j + kFitHalf)) + field;
      w[m] = wa;
      ++m;
    }
  const double u[2] = {p.us ? p.us[2 * k] : p.x[2 * k] - p.X0[2 * k],
                       p.us ? p.us[2 * k + 1] : p.x[2 * k + 1] - p.X0[2 * k + 1]};
  const double mp = p.m[k];
  double *rhs = fit + kFitUnknowns * kFitUnknowns;
  for (int a = 0; a < m; ++a) {
    double *row = fit + static_cast<size_t>(idx[a]) * kFitUnknowns;
    for (int b = 0; b < m; ++b)
      row[idx[b]] += mp * w[a] * w[b];
    for (int c = 0; c < 2; ++c)
      rhs[c * kFitUnknowns + idx[a]] += mp * w[a] * u[c];
  }
}

/// Solves the fit's normal equations (reduced sums `fit`, the consistent mass matrix of the
/// lattice) and returns the displacement of the node b (the lattice's centre) in its two
/// fields, u[field][component]. A ridge of 1e-10 of the largest diagonal term gives a field no
/// particle joins zero.
void solveFit(const double *fit, double u[2][2]) {
  constexpr int n = kFitUnknowns;
  std::vector<double> A(fit, fit + static_cast<size_t>(n) * n), r(fit + n * n, fit + n * n + 2 * n);
  double top = 0;
  for (int a = 0; a < n; ++a)
    top = std::max(top, A[static_cast<size_t>(a) * n + a]);
  for (int a = 0; a < n; ++a)
    A[static_cast<size_t>(a) * n + a] += 1e-10 * top + std::numeric_limits<double>::min();
  // Gaussian elimination with partial pivoting, two right-hand sides (r[c * n + a]).
  for (int col = 0; col < n; ++col) {
    int piv = col;
    for (int a = col + 1; a < n; ++a)
      if (std::fabs(A[static_cast<size_t>(a) * n + col]) >
          std::fabs(A[static_cast<size_t>(piv) * n + col]))
        piv = a;
    if (piv != col) {
      for (int b = 0; b < n; ++b)
        std::swap(A[static_cast<size_t>(col) * n + b], A[static_cast<size_t>(piv) * n + b]);
      for (int c = 0; c < 2; ++c)
        std::swap(r[c * n + col], r[c * n + piv]);
    }
    const double d = A[static_cast<size_t>(col) * n + col];
    for (int a = col + 1; a < n; ++a) {
      const double f = A[static_cast<size_t>(a) * n + col] / d;
      if (f == 0) continue;
      for (int b = col; b < n; ++b)
        A[static_cast<size_t>(a) * n + b] -= f * A[static_cast<size_t>(col) * n + b];
      for (int c = 0; c < 2; ++c)
        r[c * n + a] -= f * r[c * n + col];
    }
  }
  for (int col = n - 1; col >= 0; --col)
    for (int c = 0; c < 2; ++c) {
      double v = r[c * n + col];
      for (int b = col + 1; b < n; ++b)
        v -= A[static_cast<size_t>(col) * n + b] * r[c * n + b];
      r[c * n + col] = v / A[static_cast<size_t>(col) * n + col];
    }
  const int centre = 2 * (kFitHalf * kFitSide + kFitHalf);
  for (int f = 0; f < 2; ++f)
    for (int c = 0; c < 2; ++c)
      u[f][c] = r[c * n + centre + f];
}

/// G and K of one tip from its reduced row r and fit sums; h the cell at the tip; plusIsField1:
/// the n side's particles join field 1 of the node one cell behind the tip.
void finishTip(const Scene<2> &sc, const double *r, const double *fit, bool plusIsField1, double h,
               TipMeasure &m) {
  double t[2], n[2];
  tipFrame(sc.cracks[m.crack], m.end, t, n);
  const Material &mat = sc.materialAt(m.tip);
  const double Ep = modulus(mat), th = sc.material.thickness;
  double u[2][2];
  solveFit(fit, u);
  const int up = plusIsField1 ? 0 : 1;
  const double dux = u[up][0] - u[1 - up][0], duy = u[up][1] - u[1 - up][1];
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
                        const double t[2], double R, double out[3], const Crack *crack, int end) {
  const TipElastic el = tipElastic(mat);
  const double n[2] = {-t[1], t[0]};
  const BranchCut cut = crack ? BranchCut(*crack, end, tip, t) : BranchCut();
  for (PetscInt k = 0; k < p.n; ++k) {
    const double rx = p.x[2 * k] - tip[0], ry = p.x[2 * k + 1] - tip[1];
    const double rr = std::hypot(rx, ry);
    if (!(rr < R && rr > 0)) continue;
    const double along = rx * t[0] + ry * t[1], across = rx * n[0] + ry * n[1];
    double theta = std::atan2(across, along);
    theta = BranchCut::unwrap(theta, cut.at(rr));
    domainTerms(mat, el, p, k, t, n, along, across, rr, theta, R, out);
  }
}

void addFaceTerms(const Material &mat, const ParticleView<2> &p, const Crack &crack, int end,
                  const double tip[2], const double t[2], double R, double out[3]) {
  const TipElastic el = tipElastic(mat);
  const double n[2] = {-t[1], t[0]};
  const size_t np = crack.points.size();
  // The segments behind the tip segment, walking from the tip, while they come within R of it.
  std::vector<std::array<double, 4>> segs; // a, b
  for (size_t s = 1; s + 1 < np; ++s) {
    const auto &a = end == 0 ? crack.points[s] : crack.points[np - 1 - s];
    const auto &b = end == 0 ? crack.points[s + 1] : crack.points[np - 2 - s];
    if (segmentDistance(a, b, {tip[0], tip[1]}, {tip[0], tip[1]}) >= R) break;
    segs.push_back({a[0], a[1], b[0], b[1]});
  }
  if (segs.empty()) return;
  const BranchCut cut(crack, end, tip, t);
  for (PetscInt k = 0; k < p.n; ++k) {
    const double *x = &p.x[2 * k];
    for (const auto &g : segs) {
      const double ex = g[2] - g[0], ey = g[3] - g[1], len = std::hypot(ex, ey);
      const double tx = ex / len, ty = ey / len, nlx = -ty, nly = tx; // the segment's left normal
      const double d = (x[0] - g[0]) * nlx + (x[1] - g[1]) * nly;
      const double lam = (x[0] - g[0]) * tx + (x[1] - g[1]) * ty;
      // The particle's width across the face: the band of the face on its side.
      const double w = 2.0 * (std::fabs(p.l[2 * k] * nlx) + std::fabs(p.l[2 * k + 1] * nly));
      if (d == 0 || std::fabs(d) >= w || lam < 0 || lam > len) continue;
      const double fx = g[0] + lam * tx - tip[0], fy = g[1] + lam * ty - tip[1];
      const double rf = std::hypot(fx, fy);
      if (rf >= R || rf <= 0) continue;
      const double qf = (1.0 - rf * rf / (R * R)) * (1.0 - rf * rf / (R * R));
      // The material's outward normal at its face (into the crack), in the tip frame.
      const double sg = d > 0 ? -1.0 : 1.0;
      const double no[2] = {sg * (nlx * t[0] + nly * t[1]), sg * (nlx * n[0] + nly * n[1])};
      const TipState ps = tipState(mat, p, k, t, n);
      const auto &hp = ps.hp;
      const double W = ps.W;
      const double ds = p.V[k] / w * qf; // the particle's share of the face, weighted by q
      out[0] += ds * W * no[0];
      const double eps[3] = {hp[0][0], hp[1][1], 0.5 * (hp[0][1] + hp[1][0])};
      // The auxiliary fields at the foot, from the particle's side of the branch cut (the crack).
      const double px = x[0] - tip[0], py = x[1] - tip[1];
      const double cf = cut.at(rf);
      const double tp = BranchCut::unwrap(std::atan2(px * n[0] + py * n[1], px * t[0] + py * t[1]),
                                          cut.at(std::hypot(px, py)));
      const double thf =
          std::fabs(tp - cf) < std::fabs(tp - (cf - 2.0 * M_PI)) ? cf : cf - 2.0 * M_PI;
      for (int mode = 1; mode <= 2; ++mode) {
        double sa[3], ua[2];
        williamsField(mode, rf, thf, el, sa, ua);
        const double tr[2] = {sa[0] * no[0] + sa[2] * no[1], sa[2] * no[0] + sa[1] * no[1]};
        const double Wint = sa[0] * eps[0] + sa[1] * eps[1] + 2.0 * sa[2] * eps[2];
        out[mode] -= ds * (tr[0] * hp[0][0] + tr[1] * hp[1][0] - Wint * no[0]);
      }
    }
  }
}

PetscErrorCode measureTips(MPI_Comm comm, const Scene<2> &sc, const Grid<2> &g,
                           const ParticleView<2> &p, std::vector<TipMeasure> &tips) {
  tips = tipsOf(sc);
  const size_t T = tips.size();
  if (T == 0) return PETSC_SUCCESS;
  const size_t row = kRow + kFitRow;
  std::vector<double> local(row * T, 0.0), global(row * T);
  std::vector<double> cell(T);
  std::vector<char> plusIsField1(T);
  for (size_t q = 0; q < T; ++q) {
    const TipMeasure &m = tips[q];
    const Crack &crack = sc.cracks[m.crack];
    double t[2], n[2];
    tipFrame(crack, m.end, t, n);
    const double h = cell[q] = g.levels[g.leafLevelAt(m.tip[0], m.tip[1])].h;
    // The point one cell behind the tip, on the crack line: a particle on the left of the crack
    // there joins field 1 of a node at that point (crossing: a point on the line is on the left).
    const double bx = m.tip[0] - h * t[0], by = m.tip[1] - h * t[1];
    double nl[2];
    normalAt(crack, bx, by, nl);
    plusIsField1[q] = nl[0] * n[0] + nl[1] * n[1] > 0;
    double *r = &local[row * q];
    for (PetscInt k = 0; k < p.n; ++k) {
      const double rx = p.x[2 * k] - m.tip[0], ry = p.x[2 * k + 1] - m.tip[1];
      const double across = rx * n[0] + ry * n[1];
      double grad[2];
      // One side's grip on the tip: the n-side particles' internal force on a node at the tip.
      if (across > 0 && pointKernel(p, k, m.tip[0], m.tip[1], h, grad) > 0) {
        const Tensor<2> s = stressAt<2>(p.s, k);
        for (int c = 0; c < 2; ++c)
          r[kForce + c] -= p.V[k] * (s(c, 0) * grad[0] + s(c, 1) * grad[1]);
      }
      // The nodal displacements behind the tip, fitted to the particles' displacements.
      addFitTerms(crack, p, k, bx, by, h, r + kRow);
    }
    if (m.jRadius > 0) {
      addDomainIntegrals(sc.materialAt(m.tip), p, m.tip, t, m.jRadius, &r[kJ], &crack, m.end);
      addFaceTerms(sc.materialAt(m.tip), p, crack, m.end, m.tip, t, m.jRadius, &r[kJ]);
    }
  }
  PetscCallMPI(MPI_Allreduce(local.data(), global.data(), static_cast<int>(local.size()),
                             MPI_DOUBLE, MPI_SUM, comm));
  for (size_t q = 0; q < T; ++q)
    finishTip(sc, &global[row * q], &global[row * q + kRow], plusIsField1[q], cell[q], tips[q]);
  return PETSC_SUCCESS;
}

} // namespace gimp::cracks
