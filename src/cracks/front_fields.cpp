#include "gimp/cracks/front_fields.hpp"

#include <algorithm>
#include <cmath>

namespace gimp::cracks {

namespace {

using P3 = std::array<double, 3>;

/// The unit auxiliary fields of the three modes at local (x1, x2) and their derivatives along x1
/// and x2 (fourth-order central differences with step hs, which stays on x2's side of the
/// crack's plane behind the front): f[m][0] mode m + 1's value, f[m][1] d/dx1, f[m][2] d/dx2, for
/// the stress (S) and the displacement gradient (G), local axes.
void localFields(const TipElastic &el, double x1, double x2, double hs, double S[3][3][3][3],
                 double G[3][3][3][3]) {
  double s0[3][3][3], g0[3][3][3];
  frontFields(std::hypot(x1, x2), std::atan2(x2, x1), el, s0, g0);
  const double w[4] = {1.0, -8.0, 8.0, -1.0}, o[4] = {-2.0, -1.0, 1.0, 2.0};
  for (int m = 0; m < 3; ++m) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        S[m][0][i][j] = s0[m][i][j];
        G[m][0][i][j] = g0[m][i][j];
      }
    for (int dir = 1; dir <= 2; ++dir)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          S[m][dir][i][j] = G[m][dir][i][j] = 0.0;
  }
  for (int dir = 1; dir <= 2; ++dir)
    for (int k = 0; k < 4; ++k) {
      const double y1 = x1 + (dir == 1 ? o[k] * hs : 0.0), y2 = x2 + (dir == 2 ? o[k] * hs : 0.0);
      double s[3][3][3], g[3][3][3];
      frontFields(std::hypot(y1, y2), std::atan2(y2, y1), el, s, g);
      for (int m = 0; m < 3; ++m)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            S[m][dir][i][j] += w[k] * s[m][i][j] / (12.0 * hs);
            G[m][dir][i][j] += w[k] * g[m][i][j] / (12.0 * hs);
          }
    }
}

} // namespace

void frontAuxGlobal(const TipElastic &el, double x1, double x2, const P3 &e1, const P3 &e2,
                    const P3 &e3, double S[3][3][3], double G[3][3][3]) {
  double sl[3][3][3], gl[3][3][3];
  frontFields(std::hypot(x1, x2), std::atan2(x2, x1), el, sl, gl);
  const P3 B[3] = {e1, e2, e3}; // B[a][i]: local axis a's global component i
  for (int m = 0; m < 3; ++m)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double s = 0, g = 0;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) {
            s += B[a][i] * sl[m][a][b] * B[b][j];
            g += B[a][i] * gl[m][a][b] * B[b][j];
          }
        S[m][i][j] = s;
        G[m][i][j] = g;
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
  // Everything in the frame (e1, e2, e3), where the integrand, a scalar, is cheapest. The
  // particle's stress and displacement gradient there: sl = B sigma B^T, hl = B H B^T.
  double sl[3][3], hl[3][3];
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double vs = 0, vh = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const double w = e[a][static_cast<size_t>(i)] * e[b][static_cast<size_t>(j)];
          vs += w * sigma(i, j);
          vh += w * H(i, j);
        }
      sl[a][b] = vs;
      hl[a][b] = vh;
    }
  // The frame turns in its plane: c = (e3 . c) e3, so de1/ds = g e3 and de3/ds = -g e1; along
  // frame axis k, ds/dx_k = metric (t . e_k), so d e_a/dx_k = turn[k] (W e)_a with W_13 = 1,
  // W_31 = -1 and turn[k] = metric (e3 . curv e_k), curv = c t^T.
  double turn[3];
  for (int k = 0; k < 3; ++k) {
    double v = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        v += e[2][static_cast<size_t>(i)] * curv[i][j] * e[k][static_cast<size_t>(j)];
    turn[k] = metric * v;
  }
  double SS[3][3][3][3], GG[3][3][3][3];
  localFields(el, x1, x2, hs, SS, GG);
  for (int m = 0; m < 3; ++m) {
    const double(&S)[3][3][3] = SS[m], (&G)[3][3][3] = GG[m];
    // d/dx_k of a field f in the frame: its own derivative along x1, x2 (none along x3), plus
    // turn[k] (W^T f + f W); (W^T f)_1j = -f_3j, (W^T f)_3j = f_1j, (f W)_i1 = -f_i3, (f W)_i3 =
    // f_i1.
    const auto derivative = [&](const double f[3][3][3], int i, int j, int k) {
      const double own = k < 2 ? f[k + 1][i][j] : 0.0;
      const double wtf = i == 0 ? -f[0][2][j] : (i == 2 ? f[0][0][j] : 0.0);
      const double fw = j == 0 ? -f[0][i][2] : (j == 2 ? f[0][i][0] : 0.0);
      return own + turn[k] * (wtf + fw);
    };
    double tm = 0;
    for (int i = 0; i < 3; ++i) {
      double divS = 0;
      for (int j = 0; j < 3; ++j)
        divS += derivative(S, i, j, j);
      tm += divS * hl[i][0];
      for (int j = 0; j < 3; ++j)
        tm += sl[i][j] * (derivative(G, i, 0, j) - derivative(G, i, j, 0));
    }
    t[m] = tm;
  }
  return true;
}

} // namespace gimp::cracks
