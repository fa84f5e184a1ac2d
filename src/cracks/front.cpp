#include "gimp/cracks/front.hpp"

#include "gimp/cracks/front_fields.hpp"

#include "gimp/physics/material.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace gimp::cracks {

namespace {

using P3 = std::array<double, 3>;

P3 sub(const P3 &a, const P3 &b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const P3 &a, const P3 &b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
P3 cross(const P3 &a, const P3 &b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const P3 &a) {
  return std::sqrt(dot(a, a));
}

/// The chain of consecutive front edges holding front point f's edge: its edges in order, the arc
/// length at each one's start, the chain's length, and the arc length of f from the chain's start
/// [m]. A closed chain (every edge a front edge) starts at f's edge.
struct Chain {
  std::vector<int> edges;
  std::vector<double> s0;
  double length = 0, sP = 0;
  bool closed = false;
  // Per edge, for placeOf: its start, its vector and length, its frame and its vertices' ahead
  // directions (vertexAhead).
  std::vector<P3> start, vec, a, t, ahead0, ahead1;
  std::vector<double> len;
};

/// The per-edge data placeOf reads (the chain's edges' starts, vectors, lengths, frames and
/// vertex ahead directions), filled once per chain.
void fillChain(const CrackSurface &c, Chain &ch);

Chain chainOf(const CrackSurface &c, const FrontPoint &f) {
  const int m = static_cast<int>(c.points.size());
  Chain ch;
  ch.closed = std::all_of(c.front.begin(), c.front.end(), [](char e) { return e != 0; });
  int first = f.edge;
  if (!ch.closed)
    while (c.front[static_cast<size_t>((first + m - 1) % m)])
      first = (first + m - 1) % m;
  for (int k = 0; k < m; ++k) {
    const int e = (first + k) % m;
    if (!c.front[static_cast<size_t>(e)]) break;
    const P3 &p = c.points[static_cast<size_t>(e)];
    if (e == f.edge) ch.sP = ch.length + norm(sub(f.x, p));
    ch.edges.push_back(e);
    ch.s0.push_back(ch.length);
    ch.length += norm(sub(c.points[static_cast<size_t>((e + 1) % m)], p));
  }
  fillChain(c, ch);
  return ch;
}

/// Where a point is seen from the front: rho, the nearest point y, its arc length s from P (in
/// (-length / 2, length / 2] on a closed chain), grad s (the edge's t, or 0 at a vertex), and the
/// local frame at y (a ahead, x3 = a x n).
struct Place {
  double rho = 0, s = 0;
  P3 y{}, gradS{}, a{}, x3{};
  double dA[3][3] = {};   // d a_k / d x_j (nonzero in a vertex's wedge, where a turns)
  double curv[3][3] = {}; // (da/ds) t^T of the nearest edge, also where y is held at a vertex
};

/// The ahead direction at polygon vertex v as the advance field takes it: the mean of its two
/// edges' ahead directions where both are front edges, or where a mouth edge continues the front
/// (turning by less than 45 degrees: a curved front that the polygon continues past a body's
/// surface or a symmetry plane, where the mean is the front's normal at the surface); otherwise
/// the front edge's own.
P3 vertexAhead(const CrackSurface &c, size_t v) {
  const size_t m = c.points.size(), ep = (v + m - 1) % m, en = v;
  double ap[3], an[3], n[3], tp[3], tn[3];
  frontFrame(c, static_cast<int>(ep), ap, n, tp);
  frontFrame(c, static_cast<int>(en), an, n, tn);
  const bool both = c.front[ep] && c.front[en];
  const bool continues = tp[0] * tn[0] + tp[1] * tn[1] + tp[2] * tn[2] > std::sqrt(0.5);
  if (!both && !continues) return c.front[ep] ? P3{ap[0], ap[1], ap[2]} : P3{an[0], an[1], an[2]};
  P3 a = {ap[0] + an[0], ap[1] + an[1], ap[2] + an[2]};
  const double len = norm(a);
  return {a[0] / len, a[1] / len, a[2] / len};
}

void fillChain(const CrackSurface &c, Chain &ch) {
  const size_t m = c.points.size();
  for (const int ei : ch.edges) {
    const size_t e = static_cast<size_t>(ei);
    const P3 &p = c.points[e];
    const P3 v = sub(c.points[(e + 1) % m], p);
    double a[3], n[3], t[3];
    frontFrame(c, ei, a, n, t);
    ch.start.push_back(p);
    ch.vec.push_back(v);
    ch.len.push_back(norm(v));
    ch.a.push_back({a[0], a[1], a[2]});
    ch.t.push_back({t[0], t[1], t[2]});
    ch.ahead0.push_back(vertexAhead(c, e));
    ch.ahead1.push_back(vertexAhead(c, (e + 1) % m));
  }
}

/// The place of x: the chain's nearest point (the first edge's on a tie) and what follows from it.
/// The ahead direction is interpolated along the nearest edge between its vertices' (vertexAhead):
/// a = A / |A|, A = (1 - lambda) a_0 + lambda a_1, lambda the nearest point's fraction of the edge,
/// so that the advance q a is continuous across the bisectors between edges on both sides of the
/// front; da/dx = (I - a a) / |A| (a_1 - a_0) t^T / |edge| where lambda moves, 0 where it is held
/// at a vertex.
Place placeOf(const CrackSurface &c, const Chain &ch, const P3 &x) {
  const size_t K = ch.edges.size();
  Place best;
  best.rho = -1;
  size_t kb = 0;
  double lamb = 0, lenb = 0;
  for (size_t k = 0; k < K; ++k) {
    const P3 &p = ch.start[k], &e = ch.vec[k];
    const double len = ch.len[k];
    const double lam = std::clamp(dot(sub(x, p), e) / len, 0.0, len);
    const P3 y = {p[0] + lam / len * e[0], p[1] + lam / len * e[1], p[2] + lam / len * e[2]};
    const double r = norm(sub(x, y));
    if (best.rho < 0 || r < best.rho) {
      best.rho = r;
      best.y = y;
      kb = k;
      lamb = lam;
      lenb = len;
    }
  }
  best.s = ch.s0[kb] + lamb - ch.sP;
  if (ch.closed && best.s > 0.5 * ch.length) best.s -= ch.length;
  const P3 &t = ch.t[kb];
  const P3 a0 = ch.ahead0[kb], a1 = ch.ahead1[kb];
  const double lam = lamb / lenb;
  const P3 A = {(1 - lam) * a0[0] + lam * a1[0], (1 - lam) * a0[1] + lam * a1[1],
                (1 - lam) * a0[2] + lam * a1[2]};
  const double An = norm(A);
  best.a = {A[0] / An, A[1] / An, A[2] / An};
  const P3 d = sub(a1, a0);
  for (int i = 0; i < 3; ++i) {
    double w = 0; // ((I - a a) d)_i / |A|
    for (int q = 0; q < 3; ++q)
      w += ((i == q ? 1.0 : 0.0) - best.a[i] * best.a[q]) * d[q];
    for (int j = 0; j < 3; ++j)
      best.curv[i][j] = w / An * t[j] / lenb;
  }
  if (lamb > 0 && lamb < lenb) { // a turns where lambda moves; held at a vertex
    best.gradS = {t[0], t[1], t[2]};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        best.dA[i][j] = best.curv[i][j];
  }
  best.x3 = cross(best.a, c.normal);
  return best;
}

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
  st.sg = tensorAt<3>(p.s, k);
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
  for (int mode = 1; mode <= 3; ++mode) {
    double S[3][3], G[3][3], Wi = 0;
    frontAuxGlobal(mode, d.el, x1, x2, e1, d.n, e3, S, G);
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
  const Chain ch = chainOf(c, f);
  PointDomain d;
  d.mat = &m;
  d.el = frontElastic(m);
  d.P = f.x;
  d.a = f.a;
  d.n = c.normal;
  d.x3 = cross(f.a, c.normal);
  d.R = R;
  d.L = ch.closed ? std::min(L, 0.5 * ch.length) : L;
  d.aux = aux;
  // A point of the tube is within R of the front and within L of P along it: within R + L of P.
  const double reach2 = (R + d.L) * (R + d.L);
  // The mirror images of the tube across symmetry planes the chain ends on: a particle's image is
  // in the tube at P when the particle is within R + L of P's image.
  const std::vector<Image> images = imagesOf(c, ch, mirrors, kMirrorTol * R);
  std::vector<P3> imageP;
  for (const Image &im : images) {
    P3 q = d.P;
    q[static_cast<size_t>(im.axis)] = 2.0 * im.coord - q[static_cast<size_t>(im.axis)];
    imageP.push_back(q);
  }
  for (PetscInt k = 0; k < p.n; ++k) {
    const P3 x = {p.x[3 * k], p.x[3 * k + 1], p.x[3 * k + 2]};
    // The particle's place and state, found once for P's tube and its images.
    std::optional<Place> place;
    std::optional<ParticleState> state;
    const auto placed = [&]() -> const Place & {
      if (!place) place = placeOf(c, ch, x);
      return *place;
    };
    const auto stated = [&]() -> const ParticleState & {
      if (!state) state = stateOf(m, p, k);
      return *state;
    };
    const P3 r = sub(x, d.P);
    if (dot(r, r) < reach2) {
      const Place &pl = placed();
      if (pl.rho > 0 && pl.rho < R && std::fabs(pl.s) < d.L) particleTerms(d, stated(), pl, out);
    }
    for (size_t i = 0; i < images.size(); ++i) {
      const P3 ri = sub(x, imageP[i]);
      if (dot(ri, ri) >= reach2) continue;
      Place pl = placed();
      if (!(pl.rho > 0 && pl.rho < R)) continue;
      ParticleState st = stated();
      mirror(images[i], c, st, pl);
      if (std::fabs(pl.s) < d.L) particleTerms(d, st, pl, out);
    }
  }
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
