// Moments of a box cut by several curved surfaces: a round body and its holes (see
// boxRoundsMoments in include/gimp/geometry/cut_cell3d.hpp).
#include "gimp/geometry/cut_cell.hpp"
#include "gimp/geometry/cut_cell3d.hpp"
#include "slices.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gimp::cut {

namespace {

/// A solid's slice at t along axis s: empty, a disk (centre cp, cq, radius rho) or the
/// rectangle [p0, p1] x [q0, q1] of the in-plane axes p < q.
struct Piece {
  enum Kind { Empty, Disk, Rect } kind = Empty;
  double p0 = 0, q0 = 0, p1 = 0, q1 = 0, cp = 0, cq = 0, rho = 0;
};

/// Whether the solid's slices along axis s are disks.
bool isDisk(const Round &R, int s) {
  return R.ball || R.axis == s;
}

Piece sliceOf(const Round &R, int s, int p, int q, double t) {
  Piece x;
  const double d2 = R.r * R.r - (t - R.c[s]) * (t - R.c[s]);
  if (isDisk(R, s)) {
    const double rho2 = R.ball ? d2 : (t < R.lo || t > R.hi ? 0.0 : R.r * R.r);
    if (rho2 <= 0) return x;
    x = {Piece::Disk, 0, 0, 0, 0, R.c[p], R.c[q], std::sqrt(rho2)};
    return x;
  }
  if (d2 <= 0) return x;
  // A cylinder across the slices: a band of half-width w about its axis, lo to hi along it.
  const double w = std::sqrt(d2);
  double a[3], b[3];
  const int other = R.axis == p ? q : p;
  a[R.axis] = R.lo;
  b[R.axis] = R.hi;
  a[other] = R.c[other] - w;
  b[other] = R.c[other] + w;
  x = {Piece::Rect, a[p], a[q], b[p], b[q], 0, 0, 0};
  return x;
}

/// The plane moments {A, Sp, Sq, Spp, Sqq} of the rectangle r (p0, q0, p1, q1) cut by the
/// pieces (at most one disk).
std::array<double, 5> momentsOf(double r[4], const std::vector<const Piece *> &pieces) {
  const Piece *disk = nullptr;
  for (const Piece *x : pieces) {
    if (x->kind == Piece::Empty) return {};
    if (x->kind == Piece::Disk) {
      disk = x;
      continue;
    }
    r[0] = std::max(r[0], x->p0);
    r[1] = std::max(r[1], x->q0);
    r[2] = std::min(r[2], x->p1);
    r[3] = std::min(r[3], x->q1);
  }
  if (r[2] <= r[0] || r[3] <= r[1]) return {};
  if (disk) return rectDiskMoments(r[0], r[1], r[2], r[3], disk->cp, disk->cq, disk->rho);
  const double A = (r[2] - r[0]) * (r[3] - r[1]);
  return {A, A * 0.5 * (r[0] + r[2]), A * 0.5 * (r[1] + r[3]),
          A * (r[0] * r[0] + r[0] * r[2] + r[2] * r[2]) / 3,
          A * (r[1] * r[1] + r[1] * r[3] + r[3] * r[3]) / 3};
}

/// Where a solid's slice along s changes form in the box: it begins or ends, a band's edge
/// crosses a side of the box, a disk reaches a side or a corner.
void cutsOf(const Round &R, int s, int p, int q, const double *lo, const double *hi,
            std::vector<double> &cuts) {
  auto at = [&](double d2) { // t where r^2 - (t - c_s)^2 = d2
    if (d2 >= 0 && d2 < R.r * R.r)
      for (double sg : {-1.0, 1.0})
        cuts.push_back(R.c[s] + sg * std::sqrt(R.r * R.r - d2));
  };
  if (!R.ball && R.axis == s) {
    cuts.push_back(R.lo);
    cuts.push_back(R.hi);
    return;
  }
  at(0.0);
  if (!R.ball) { // a band across the slices: its edges against the box's sides
    const int o = R.axis == p ? q : p;
    for (double v : {lo[o], hi[o]})
      at((v - R.c[o]) * (v - R.c[o]));
    return;
  }
  for (double dp : {lo[p] - R.c[p], hi[p] - R.c[p], 0.0})
    for (double dq : {lo[q] - R.c[q], hi[q] - R.c[q], 0.0})
      at(dp * dp + dq * dq);
}

} // namespace

bool boxRoundsMoments(const double lo[3], const double hi[3], const Round *body,
                      const std::vector<Round> &holes, Raw3 &m) {
  std::vector<Round> all = holes;
  if (body) all.insert(all.begin(), *body);
  int s = -1;
  for (int a : {2, 0, 1}) {
    int disks = 0;
    for (const Round &R : all)
      disks += isDisk(R, a) ? 1 : 0;
    if (disks <= 1) {
      s = a;
      break;
    }
  }
  if (s < 0 || holes.size() > 8) return false;
  const int p = s == 0 ? 1 : 0, q = s == 2 ? 1 : 2;
  std::vector<double> cuts;
  for (const Round &R : all)
    cutsOf(R, s, p, q, lo, hi, cuts);
  const size_t nh = holes.size(), first = body ? 1 : 0;
  const auto region = slicing::slices([&](double t) {
    std::vector<Piece> pieces(all.size());
    for (size_t i = 0; i < all.size(); ++i)
      pieces[i] = sliceOf(all[i], s, p, q, t);
    std::array<double, 5> sum{};
    for (size_t set = 0; set < (size_t{1} << nh); ++set) { // inclusion-exclusion over holes
      std::vector<const Piece *> in;
      if (body) in.push_back(&pieces[0]);
      int sign = 1;
      for (size_t h = 0; h < nh; ++h)
        if (set >> h & 1) {
          in.push_back(&pieces[first + h]);
          sign = -sign;
        }
      double r[4] = {lo[p], lo[q], hi[p], hi[q]};
      const auto mo = momentsOf(r, in);
      for (int i = 0; i < 5; ++i)
        sum[i] += sign * mo[i];
    }
    return slicing::lift(sum, s, p, q, t);
  });
  std::vector<double> inside;
  for (double t : cuts)
    if (t > lo[s] && t < hi[s]) inside.push_back(t);
  m = region.over(lo[s], hi[s], inside, slicing::tolerances(lo, hi));
  return true;
}

} // namespace gimp::cut
