#include "gimp/cracks/front_fields.hpp"

#include <algorithm>
#include <cmath>

namespace gimp::cracks {

namespace {

using P3 = std::array<double, 3>;

P3 cross(const P3 &a, const P3 &b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// The unit auxiliary field of `mode` at local (x1, x2) and its derivatives along x1 and x2
/// (fourth-order central differences with step hs, which stays on x2's side of the crack's plane
/// behind the front): f[0] the value, f[1] d/dx1, f[2] d/dx2, for the stress (S) and the
/// displacement gradient (G), local axes.
void localField(int mode, const TipElastic &el, double x1, double x2, double hs, double S[3][3][3],
                double G[3][3][3]) {
  frontField(mode, std::hypot(x1, x2), std::atan2(x2, x1), el, S[0], G[0]);
  const double w[4] = {1.0, -8.0, 8.0, -1.0}, o[4] = {-2.0, -1.0, 1.0, 2.0};
  for (int dir = 1; dir <= 2; ++dir)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        S[dir][i][j] = G[dir][i][j] = 0.0;
  for (int dir = 1; dir <= 2; ++dir)
    for (int k = 0; k < 4; ++k) {
      const double y1 = x1 + (dir == 1 ? o[k] * hs : 0.0), y2 = x2 + (dir == 2 ? o[k] * hs : 0.0);
      double s[3][3], g[3][3];
      frontField(mode, std::hypot(y1, y2), std::atan2(y2, y1), el, s, g);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          S[dir][i][j] += w[k] * s[i][j] / (12.0 * hs);
          G[dir][i][j] += w[k] * g[i][j] / (12.0 * hs);
        }
    }
}

/// The global derivatives dF_ik/dx_j of an auxiliary field F = sum_ab f_ab e_a e_b^T carried by
/// the smooth front that the polygon stands for: x1 and x2 change along e1 and e2, and the frame
/// turns with the arc length s, de1/ds = c (the front's curvature vector, in its plane), de2/ds =
/// 0, de3/ds = c x n, ds/dx = t / (1 + kappa x1), kappa = c . t (the curvature's sign: positive
/// where the front is convex, its centre of curvature behind it). curv = c t^T.
void globalDerivative(const double f[3][3][3], const P3 e[3], const double curv[3][3],
                      double metric, double dF[3][3][3]) {
  for (int j = 0; j < 3; ++j) {
    // de_a/dx_j
    P3 de[3];
    de[0] = {curv[0][j] * metric, curv[1][j] * metric, curv[2][j] * metric};
    de[1] = {0, 0, 0};
    de[2] = cross(de[0], e[1]);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        double v = 0;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) {
            const double df = f[1][a][b] * e[0][static_cast<size_t>(j)] +
                              f[2][a][b] * e[1][static_cast<size_t>(j)];
            v += df * e[a][static_cast<size_t>(i)] * e[b][static_cast<size_t>(k)] +
                 f[0][a][b] * (de[a][static_cast<size_t>(i)] * e[b][static_cast<size_t>(k)] +
                               e[a][static_cast<size_t>(i)] * de[b][static_cast<size_t>(k)]);
          }
        dF[i][k][j] = v;
      }
  }
}

} // namespace

void frontAuxGlobal(int mode, const TipElastic &el, double x1, double x2, const P3 &e1,
                    const P3 &e2, const P3 &e3, double S[3][3], double G[3][3]) {
  double sl[3][3], gl[3][3];
  frontField(mode, std::hypot(x1, x2), std::atan2(x2, x1), el, sl, gl);
  const P3 B[3] = {e1, e2, e3}; // B[a][i]: local axis a's global component i
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s = 0, g = 0;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          s += B[a][i] * sl[a][b] * B[b][j];
          g += B[a][i] * gl[a][b] * B[b][j];
        }
      S[i][j] = s;
      G[i][j] = g;
    }
}

bool curvatureIntegrand(const TipElastic &el, double x1, double x2, const P3 e[3],
                        const double curv[3][3], const Tensor<3> &sigma, const Tensor<3> &H,
                        double t[3]) {
  const double rho = std::hypot(x1, x2);
  if (rho <= 0 || (x1 < 0 && x2 == 0)) return false;
  const double hs = x1 < 0 ? std::min(1e-3 * rho, 0.25 * std::fabs(x2)) : 1e-3 * rho;
  const double kappa = curv[0][0] + curv[1][1] + curv[2][2];
  if (1.0 + kappa * x1 <= 0) return false;
  const double metric = 1.0 / (1.0 + kappa * x1);
  for (int m = 0; m < 3; ++m) {
    double S[3][3][3], G[3][3][3], dS[3][3][3], dG[3][3][3]; // dS[i][k][j] = dS_ik/dx_j
    localField(m + 1, el, x1, x2, hs, S, G);
    globalDerivative(S, e, curv, metric, dS);
    globalDerivative(G, e, curv, metric, dG);
    double divS[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        divS[i] += dS[i][j][j];
    double tm = 0;
    for (int k = 0; k < 3; ++k) {
      double tk = 0;
      for (int i = 0; i < 3; ++i) {
        tk += divS[i] * H(i, k);
        for (int j = 0; j < 3; ++j)
          tk += sigma(i, j) * (dG[i][k][j] - dG[i][j][k]);
      }
      tm += e[0][static_cast<size_t>(k)] * tk;
    }
    t[m] = tm;
  }
  return true;
}

} // namespace gimp::cracks
