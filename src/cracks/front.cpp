#include "gimp/cracks/front.hpp"

#include "front_chain.hpp"
#include "gimp/cracks/front_fields.hpp"

#include "gimp/physics/material.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace gimp::cracks {

namespace {

using chain::Chain;
using chain::chainOf;
using chain::cross;
using chain::dot;
using chain::norm;
using chain::P3;
using chain::Place;
using chain::placeOf;
using chain::sub;

/// int of (1 - s^2 / L^2)^2 ds from -L to u, |u| <= L.
double qsIntegral(double u, double L) {
  const double v = u / L;
  return L * (v - 2.0 * v * v * v / 3.0 + v * v * v * v * v / 5.0 + 8.0 / 15.0);
}

/// What the integrands need of one particle (or of its mirror image): position, stress,
/// displacement gradient H = F - I, volume and strain energy density.
struct ParticleState {
  P3 x{};
  Tensor<3> sg, H;
  double V = 0, W = 0;
};

ParticleState stateOf(const Material &m, const ParticleView<3> &p, PetscInt k) {
  ParticleState st;
  st.x = {p.x[3 * k], p.x[3 * k + 1], p.x[3 * k + 2]};
  st.sg = stressAt<3>(p.s, k);
  const Tensor<3> F = tensorAt<3>(p.F, k);
  st.H = F - Tensor<3>::Identity();
  st.V = p.V[k];
  st.W = material::strainEnergy(m, st.sg, F, p.V0[k], p.V[k]) / p.V[k];
  return st;
}

/// A mirror image of the front across a symmetry plane that one end of the chain lies on: the
/// plane (axis, coordinate) and the end's arc length from P. The image continues the chain past
/// its end: the point at arc s' from P mirrors the chain's point at arc 2 sE - s'.
struct Image {
  int axis = 0;
  double coord = 0, sE = 0;
};

/// The images of f's chain: one per chain end that lies on a mirror plane (within tol) of a crack
/// whose plane the mirror maps to itself (the normal has no component along the plane's axis). A
/// closed chain has none.
std::vector<Image> imagesOf(const CrackSurface &c, const Chain &ch,
                            const std::vector<MirrorPlane> &planes, double tol) {
  std::vector<Image> out;
  if (ch.closed || ch.edges.empty()) return out;
  const size_t m = c.points.size();
  const P3 &start = c.points[static_cast<size_t>(ch.edges.front())];
  const P3 &end = c.points[(static_cast<size_t>(ch.edges.back()) + 1) % m];
  for (const MirrorPlane &pl : planes) {
    if (std::fabs(c.normal[static_cast<size_t>(pl.axis)]) > 1e-9) continue;
    if (std::fabs(start[static_cast<size_t>(pl.axis)] - pl.coord) <= tol)
      out.push_back({pl.axis, pl.coord, -ch.sP});
    if (std::fabs(end[static_cast<size_t>(pl.axis)] - pl.coord) <= tol)
      out.push_back({pl.axis, pl.coord, ch.length - ch.sP});
  }
  return out;
}

/// Where the chain ends are taken to lie on a mirror plane: within this fraction of R.
constexpr double kMirrorTol = 1e-6;

/// The mirror image across `im`'s plane of a place seen from the chain: y' = M y, a' = M a, da' =
/// M da M, s' = 2 sE - s, grad s' = -M grad s (M flips the plane's axis; the crack's normal n =
/// M n).
void mirrorPlace(const Image &im, const CrackSurface &c, Place &pl) {
  const int b = im.axis;
  const auto flip = [b](int i) { return i == b ? -1.0 : 1.0; };
  pl.y[static_cast<size_t>(b)] = 2.0 * im.coord - pl.y[static_cast<size_t>(b)];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      pl.dA[i][j] *= flip(i) * flip(j);
      pl.curv[i][j] *= flip(i) * flip(j);
    }
    pl.a[static_cast<size_t>(i)] *= flip(i);
    pl.gradS[static_cast<size_t>(i)] *= -flip(i);
  }
  pl.s = 2.0 * im.sE - pl.s;
  pl.x3 = cross(pl.a, c.normal);
}

/// The mirror image of a particle's state and of its place: x' = M x, sigma' = M sigma M, H' = M H
/// M, and the place as mirrorPlace.
void mirror(const Image &im, const CrackSurface &c, ParticleState &st, Place &pl) {
  const int b = im.axis;
  const auto flip = [b](int i) { return i == b ? -1.0 : 1.0; };
  st.x[static_cast<size_t>(b)] = 2.0 * im.coord - st.x[static_cast<size_t>(b)];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      st.sg(i, j) *= flip(i) * flip(j);
      st.H(i, j) *= flip(i) * flip(j);
    }
  mirrorPlace(im, c, pl);
}

/// What one evaluation of the integrands needs of the front point: P, its frame, the material,
/// the domain and the choice of auxiliary frame.
struct PointDomain {
  const Material *mat = nullptr;
  TipElastic el;
  P3 P{}, a{}, n{}, x3{};
  double R = 0, L = 0;
  AuxFrame aux = AuxFrame::Nearest;
};

/// The curvature terms of the interaction integrals at a particle (curvatureIntegrand, in the
/// frame of its nearest front point), times V q, added to out[1..3].
void curvatureTerms(const PointDomain &d, const ParticleState &st, const Place &pl, double q,
                    double out[4]) {
  const P3 r = sub(st.x, pl.y);
  const P3 e[3] = {pl.a, d.n, pl.x3};
  double t[3];
  if (!curvatureIntegrand(d.el, dot(r, e[0]), dot(r, e[1]), e, pl.curv, st.sg, st.H, t)) return;
  for (int m = 0; m < 3; ++m)
    out[m + 1] += st.V * q * t[m];
}

/// A particle's terms, at place pl (rho < R, |s| < L), added to out (see addFrontIntegrals).
void particleTerms(const PointDomain &d, const ParticleState &st, const Place &pl, double out[4]) {
  const Tensor<3> &sg = st.sg, &H = st.H;
  const P3 &x = st.x;
  const double R2 = d.R * d.R, L2 = d.L * d.L;
  const double qr = (1.0 - pl.rho * pl.rho / R2) * (1.0 - pl.rho * pl.rho / R2);
  const double qs = (1.0 - pl.s * pl.s / L2) * (1.0 - pl.s * pl.s / L2);
  const double dqr = -4.0 * pl.rho / R2 * (1.0 - pl.rho * pl.rho / R2);
  const double dqs = -4.0 * pl.s / L2 * (1.0 - pl.s * pl.s / L2);
  // The virtual advance v = q a (a the local ahead direction): dv_k/dx_j = a_k dq/dx_j + q
  // da_k/dx_j.
  const double q = qr * qs;
  double dq[3], dv[3][3];
  for (int j = 0; j < 3; ++j)
    dq[j] = dqr * qs * (x[j] - pl.y[j]) / pl.rho + qr * dqs * pl.gradS[j];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      dv[i][j] = pl.a[i] * dq[j] + q * pl.dA[i][j];
  const double W = st.W;
  double j0 = 0;
  for (int kk = 0; kk < 3; ++kk)
    for (int j = 0; j < 3; ++j) {
      double sH = -(kk == j ? W : 0.0);
      for (int i = 0; i < 3; ++i)
        sH += sg(i, j) * H(i, kk);
      j0 += sH * dv[kk][j];
    }
  out[0] += st.V * j0;
  // The auxiliary fields' frame and the particle's position in it.
  const bool atP = d.aux == AuxFrame::Point;
  const P3 r = sub(x, atP ? d.P : pl.y);
  const P3 &e1 = atP ? d.a : pl.a, &e3 = atP ? d.x3 : pl.x3;
  const double x1 = dot(r, e1), x2 = dot(r, d.n);
  if (std::hypot(x1, x2) <= 0) return;
  double SS[3][3][3], GG[3][3][3];
  frontAuxGlobal(d.el, x1, x2, e1, d.n, e3, SS, GG);
  for (int mode = 1; mode <= 3; ++mode) {
    const double(&S)[3][3] = SS[mode - 1], (&G)[3][3] = GG[mode - 1];
    double Wi = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        Wi += S[i][j] * 0.5 * (H(i, j) + H(j, i));
    double v = 0;
    for (int kk = 0; kk < 3; ++kk)
      for (int j = 0; j < 3; ++j) {
        double t = -(kk == j ? Wi : 0.0);
        for (int i = 0; i < 3; ++i)
          t += sg(i, j) * G[i][kk] + S[i][j] * H(i, kk);
        v += t * dv[kk][j];
      }
    out[mode] += st.V * v;
  }
  if (d.aux == AuxFrame::Nearest) curvatureTerms(d, st, pl, q, out);
}

/// The tube integrals at front points pts of one chain (each with its radius R and half length
/// L), their sums at out + 4 q: each particle's place on the chain and its state are found once
/// for all the points. placeOf's nearest point and frame do not depend on the point, its arc
/// length s is s0 + lambda - sP (wrapped on a closed chain), formed as for each point alone: an
/// open chain starts at its first edge whatever the point, a closed one at the point's edge, so a
/// closed chain takes one point at a time.
void tubeIntegrals(const Material &m, const ParticleView<3> &p, const CrackSurface &c,
                   const std::vector<FrontPoint> &pts, const std::vector<double> &R,
                   const std::vector<double> &L, AuxFrame aux,
                   const std::vector<MirrorPlane> &mirrors, double *out) {
  if (pts.empty()) return;
  Chain raw = chainOf(c, pts[0]);
  // (A closed chain stays closed, so that placeOf blends the wedge behind its first vertex too.)
  const bool closed = raw.closed;
  raw.sP = 0;
  struct Point {
    PointDomain d;
    double reach2 = 0, sP = 0;
    std::vector<Image> images;
    std::vector<P3> imageP;
  };
  std::vector<Point> at(pts.size());
  for (size_t q = 0; q < pts.size(); ++q) {
    const Chain ch = chainOf(c, pts[q]);
    Point &a = at[q];
    a.d.mat = &m;
    a.d.el = frontElastic(m);
    a.d.P = pts[q].x;
    a.d.a = pts[q].a;
    a.d.n = c.normal;
    a.d.x3 = cross(pts[q].a, c.normal);
    a.d.R = R[q];
    a.d.L = ch.closed ? std::min(L[q], 0.5 * ch.length) : L[q];
    a.d.aux = aux;
    a.reach2 = (R[q] + a.d.L) * (R[q] + a.d.L);
    a.sP = ch.sP;
    a.images = imagesOf(c, ch, mirrors, kMirrorTol * R[q]);
    for (const Image &im : a.images) {
      P3 y = a.d.P;
      y[static_cast<size_t>(im.axis)] = 2.0 * im.coord - y[static_cast<size_t>(im.axis)];
      a.imageP.push_back(y);
    }
  }
  // Each particle within reach of a point (or of its images): its place and state, found once.
  for (PetscInt k = 0; k < p.n; ++k) {
    const P3 x = {p.x[3 * k], p.x[3 * k + 1], p.x[3 * k + 2]};
    std::optional<Place> place;
    std::optional<ParticleState> state;
    for (size_t q = 0; q < at.size(); ++q) {
      const Point &a = at[q];
      const P3 r = sub(x, a.d.P);
      bool reached = dot(r, r) < a.reach2;
      for (const P3 &y : a.imageP) {
        const P3 ri = sub(x, y);
        reached = reached || dot(ri, ri) < a.reach2;
      }
      if (!reached) continue;
      if (!place) place = placeOf(c, raw, x);
      Place pl = *place;
      pl.s = pl.s - a.sP;
      if (closed && pl.s > 0.5 * raw.length) pl.s -= raw.length;
      if (closed && pl.s <= -0.5 * raw.length) pl.s += raw.length;
      if (!(pl.rho > 0 && pl.rho < a.d.R)) continue;
      if (!state) state = stateOf(m, p, k);
      double *o = out + 4 * q;
      if (dot(r, r) < a.reach2 && std::fabs(pl.s) < a.d.L) particleTerms(a.d, *state, pl, o);
      for (size_t i = 0; i < a.images.size(); ++i) {
        const P3 ri = sub(x, a.imageP[i]);
        if (dot(ri, ri) >= a.reach2) continue;
        Place pi = pl;
        ParticleState st = *state;
        mirror(a.images[i], c, st, pi);
        if (std::fabs(pi.s) < a.d.L) particleTerms(a.d, st, pi, o);
      }
    }
  }
}

} // namespace

TipElastic frontElastic(const Material &m) {
  TipElastic e;
  e.mu = m.E / (2.0 * (1.0 + m.nu));
  e.kappa = 3.0 - 4.0 * m.nu;
  return e;
}

double frontHalfLength(const CrackSurface &c, const FrontPoint &f, double L) {
  const Chain ch = chainOf(c, f);
  return ch.closed ? std::min(L, 0.5 * ch.length) : L;
}

double frontArea(const CrackSurface &c, const FrontPoint &f, double L, double R,
                 const std::vector<MirrorPlane> &mirrors) {
  const Chain ch = chainOf(c, f);
  const std::vector<Image> images = imagesOf(c, ch, mirrors, kMirrorTol * R);
  if (ch.closed) L = std::min(L, 0.5 * ch.length);
  const size_t m = c.points.size();
  double A = 0;
  for (size_t k = 0; k < ch.edges.size(); ++k) {
    const size_t e = static_cast<size_t>(ch.edges[k]);
    const double len = norm(sub(c.points[(e + 1) % m], c.points[e]));
    double a[3], n[3], t[3];
    frontFrame(c, ch.edges[k], a, n, t);
    const double cosine = 1.0; // the advance is along each edge's own a
    // The edge's arc interval from P, and on a closed chain its image one length back.
    for (int image = 0; image < (ch.closed ? 2 : 1); ++image) {
      const double u0 = ch.s0[k] - ch.sP - image * ch.length, u1 = u0 + len;
      const double lo = std::max(u0, -L), hi = std::min(u1, L);
      if (hi > lo) A += cosine * (qsIntegral(hi, L) - qsIntegral(lo, L));
    }
    for (const Image &im : images) { // the edge's image: arcs 2 sE - u1 .. 2 sE - u0
      const double u0 = ch.s0[k] - ch.sP, u1 = u0 + len;
      const double lo = std::max(2.0 * im.sE - u1, -L), hi = std::min(2.0 * im.sE - u0, L);
      if (hi > lo) A += qsIntegral(hi, L) - qsIntegral(lo, L);
    }
  }
  return A;
}

void addFrontIntegrals(const Material &m, const ParticleView<3> &p, const CrackSurface &c,
                       const FrontPoint &f, double R, double L, double out[4], AuxFrame aux,
                       const std::vector<MirrorPlane> &mirrors) {
  tubeIntegrals(m, p, c, {f}, {R}, {L}, aux, mirrors, out);
}

int openChainStart(const CrackSurface &c, const FrontPoint &f) {
  const Chain ch = chainOf(c, f);
  return ch.closed ? -1 : ch.edges.front();
}

void addChainIntegrals(const Material &m, const ParticleView<3> &p, const CrackSurface &c,
                       const std::vector<FrontPoint> &pts, const std::vector<double> &R,
                       double *out, const std::vector<MirrorPlane> &mirrors) {
  tubeIntegrals(m, p, c, pts, R, R, AuxFrame::Nearest, mirrors, out);
}

FrontMeasure finishFront(const Material &m, const CrackSurface &c, const FrontPoint &f, double R,
                         double L, const double sums[4], const std::vector<MirrorPlane> &mirrors) {
  FrontMeasure o;
  o.images = static_cast<int>(imagesOf(c, chainOf(c, f), mirrors, kMirrorTol * R).size());
  o.edge = f.edge;
  o.x = f.x;
  o.R = R;
  o.L = frontHalfLength(c, f, L);
  const double A = frontArea(c, f, L, R, mirrors);
  const double Ep = m.E / (1.0 - m.nu * m.nu), mu = m.E / (2.0 * (1.0 + m.nu));
  o.G = sums[0] / A;
  o.KI = 0.5 * Ep * sums[1] / A;
  o.KII = 0.5 * Ep * sums[2] / A;
  o.KIII = mu * sums[3] / A;
  return o;
}

} // namespace gimp::cracks
