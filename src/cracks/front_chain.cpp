#include "front_chain.hpp"

#include <algorithm>

namespace gimp::cracks::chain {

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

namespace {

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

} // namespace

/// The chain of consecutive front edges holding front point f, with the per-edge data placeOf
/// reads (fillChain).
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

/// The place of x: the chain's nearest point (the first edge's on a tie) and what follows from it.
/// The ahead direction is interpolated along an edge between its vertices' (vertexAhead):
/// a = A / |A|, A = (1 - lambda) a_0 + lambda a_1, lambda a fraction of the edge, and
/// da/dx = (I - a a) / |A| (a_1 - a_0) (grad s)^T / |edge| where lambda moves, 0 where it is held
/// at a vertex.
///
/// The arc length s and the advance q a must be continuous in x (the domain integral's q is):
/// - where x's foot on its nearest edge is interior and the foot on a neighbouring edge is too
///   (the wedge behind a vertex on the side the front turns towards), the two edges' arc lengths,
///   s_k = s_V - (|e_k| - u_k) and s_n = s_V + u_n (u the unclamped distances of the feet from each
///   edge's start, s_V the vertex's arc length), differ by 2 t on the plane that bisects them, t
///   the feet's distance from the vertex. There s = s_V - (|e_k| - u_k) + u_n, which is s_k where
///   the foot on n reaches the vertex (u_n = 0) and s_n where the foot on k does, with
///   grad s = t_k + t_n; lambda follows s (on k before the vertex, on n after it);
/// - elsewhere s = s_k with grad s = t_k, or, where the nearest point is held at a vertex (the
///   wedge on the other side), s = s_V with grad s = 0.
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
  // The edge ke and the distance along it (lame) that the ahead direction takes, s, grad s.
  size_t ke = kb;
  double lame = lamb, s = ch.s0[kb] + lamb;
  const bool interior = lamb > 0 && lamb < lenb;
  P3 gradS{};
  if (interior) {
    gradS = ch.t[kb];
    // A neighbouring edge whose foot is interior too (the nearer one if both are).
    double dn = -1, un = 0;
    size_t kn = kb;
    int side = 0;
    for (int sd = -1; sd <= 1; sd += 2) {
      size_t n = kb;
      if (sd < 0 && kb > 0)
        n = kb - 1;
      else if (sd < 0 && ch.closed)
        n = K - 1;
      else if (sd > 0 && kb + 1 < K)
        n = kb + 1;
      else if (sd > 0 && ch.closed)
        n = 0;
      if (n == kb) continue;
      const double len = ch.len[n], u = dot(sub(x, ch.start[n]), ch.vec[n]) / len;
      if (!(u > 0 && u < len)) continue;
      const P3 &e = ch.vec[n], &p = ch.start[n];
      const P3 y = {p[0] + u / len * e[0], p[1] + u / len * e[1], p[2] + u / len * e[2]};
      const double d = norm(sub(x, y));
      if (dn < 0 || d < dn) dn = d, un = u, kn = n, side = sd;
    }
    if (side > 0) { // the vertex at kb's end: s_V = s0[kb] + |e_kb|
      s = ch.s0[kb] + lamb + un;
      const P3 &tn = ch.t[kn];
      for (int i = 0; i < 3; ++i)
        gradS[i] += tn[i];
      if (lamb + un > lenb)
        ke = kn, lame = lamb + un - lenb;
      else
        lame = lamb + un;
    } else if (side < 0) { // the vertex at kb's start: s_V = s0[kb]
      const double lenp = ch.len[kn];
      s = ch.s0[kb] + lamb + un - lenp;
      const P3 &tp = ch.t[kn];
      for (int i = 0; i < 3; ++i)
        gradS[i] += tp[i];
      if (lamb + un < lenp)
        ke = kn, lame = lamb + un;
      else
        lame = lamb + un - lenp;
    }
  }
  best.s = s - ch.sP;
  if (ch.closed && best.s > 0.5 * ch.length) best.s -= ch.length;
  const double lene = ch.len[ke];
  const P3 &te = ch.t[ke];
  const P3 a0 = ch.ahead0[ke], a1 = ch.ahead1[ke];
  const double lam = std::clamp(lame / lene, 0.0, 1.0);
  const P3 A = {(1 - lam) * a0[0] + lam * a1[0], (1 - lam) * a0[1] + lam * a1[1],
                (1 - lam) * a0[2] + lam * a1[2]};
  const double An = norm(A);
  best.a = {A[0] / An, A[1] / An, A[2] / An};
  const P3 d = sub(a1, a0);
  for (int i = 0; i < 3; ++i) {
    double w = 0; // ((I - a a) d)_i / |A|
    for (int q = 0; q < 3; ++q)
      w += ((i == q ? 1.0 : 0.0) - best.a[i] * best.a[q]) * d[q];
    for (int j = 0; j < 3; ++j) {
      best.curv[i][j] = w / An * te[j] / lene;
      best.dA[i][j] = interior ? w / An * gradS[j] / lene : 0.0; // held at a vertex: 0
    }
  }
  best.gradS = gradS;
  best.x3 = cross(best.a, c.normal);
  return best;
}

} // namespace gimp::cracks::chain
