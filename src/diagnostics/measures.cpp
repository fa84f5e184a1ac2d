#include "gimp/diagnostics/measures.hpp"
#include "gimp/geometry/crack.hpp"

#include "gimp/diagnostics/gather.hpp"
#include "gimp/particles/swarm.hpp"
#include "gimp/physics/mms.hpp"
#include "gimp/physics/tracking.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <utility>

namespace gimp {

template <> const std::vector<const char *> &stressComponents<2>() {
  static const std::vector<const char *> c = {"xx", "yy", "xy", "zz"};
  return c;
}
template <> const std::vector<const char *> &stressComponents<3>() {
  static const std::vector<const char *> c = {"xx", "yy", "zz", "yz", "xz", "xy"};
  return c;
}

template <int D> void stressOf(const ParticleView<D> &p, PetscInt k, double *out) {
  // The stored entries are in this order already (Voigt); 2D adds the out-of-plane stress.
  std::copy(p.s + kStress<D> * k, p.s + kStress<D> * (k + 1), out);
  if constexpr (D == 2) out[kStress<2>] = p.szz[k];
}
template void stressOf<2>(const ParticleView<2> &, PetscInt, double *);
template void stressOf<3>(const ParticleView<3> &, PetscInt, double *);

template <int D>
PetscErrorCode findProbes(MPI_Comm comm, const Scene<D> &sc, DM sw, std::vector<PetscInt64> &ids) {
  // The particle nearest each point (the smallest id among equals), fixed for the run.
  ParticleView<D> p;
  PetscCall(p.get(sw));
  ids.clear();
  for (const Probe<D> &pr : sc.probes) {
    double best = 1e300;
    PetscInt64 bestId = INT64_MAX;
    for (PetscInt k = 0; k < p.n; ++k) {
      double d2 = 0;
      for (int a = 0; a < D; ++a)
        d2 += (p.X0[D * k + a] - pr.x[a]) * (p.X0[D * k + a] - pr.x[a]);
      if (d2 < best || (d2 == best && p.id[k] < bestId)) {
        best = d2;
        bestId = p.id[k];
      }
    }
    double gbest = 0;
    PetscCallMPI(MPI_Allreduce(&best, &gbest, 1, MPI_DOUBLE, MPI_MIN, comm));
    PetscInt64 mine = best == gbest ? bestId : INT64_MAX, gid = 0;
    PetscCallMPI(MPI_Allreduce(&mine, &gid, 1, MPI_INT64_T, MPI_MIN, comm));
    ids.push_back(gid);
  }
  PetscCall(p.restore(sw));
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode probeStates(MPI_Comm comm, DM sw, const std::vector<PetscInt64> &ids,
                           std::vector<ProbeState> &out) {
  ParticleView<D> p;
  PetscCall(p.get(sw));
  const int ns = static_cast<int>(stressComponents<D>().size()), cols = 2 * D + ns;
  std::vector<double> loc(ids.size() * cols, 0.0), glob(ids.size() * cols, 0.0);
  for (PetscInt k = 0; k < p.n; ++k)
    for (size_t q = 0; q < ids.size(); ++q)
      if (p.id[k] == ids[q]) {
        double *r = &loc[cols * q];
        for (int a = 0; a < D; ++a) {
          r[a] = p.X0[D * k + a];
          r[D + a] = p.x[D * k + a] - p.X0[D * k + a];
        }
        stressOf<D>(p, k, r + 2 * D);
      }
  PetscCall(p.restore(sw));
  PetscCallMPI(MPI_Allreduce(loc.data(), glob.data(), static_cast<int>(loc.size()), MPI_DOUBLE,
                             MPI_SUM, comm));
  out.assign(ids.size(), ProbeState{});
  for (size_t q = 0; q < ids.size(); ++q) {
    const double *r = &glob[cols * q];
    out[q].id = ids[q];
    std::copy(r, r + D, out[q].X0);
    std::copy(r + D, r + 2 * D, out[q].u);
    std::copy(r + 2 * D, r + cols, out[q].stress);
  }
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode mmsErrors(MPI_Comm comm, const Scene<D> &sc, DM sw, double t, double &linf,
                         double &rms) {
  // The displacement error against the manufactured solution: largest and volume-weighted RMS
  // over the particles (the displacement across x is exactly 0).
  linf = rms = 0;
  if (sc.mms == Mms::None) return PETSC_SUCCESS;
  const mms::AxialWave ex(sc);
  ParticleView<D> p;
  PetscCall(p.get(sw));
  double loc[3] = {0, 0, 0}, glob[3];
  for (PetscInt k = 0; k < p.n; ++k) {
    const double X = p.X0[D * k];
    double e2 = 0;
    for (int a = 0; a < D; ++a) {
      const double e = p.x[D * k + a] - p.X0[D * k + a] - (a == 0 ? ex.u(X, t) : 0.0);
      e2 += e * e;
    }
    loc[0] = std::max(loc[0], std::sqrt(e2));
    loc[1] += e2 * p.V0[k];
    loc[2] += p.V0[k];
  }
  PetscCall(p.restore(sw));
  PetscCallMPI(MPI_Allreduce(&loc[0], &glob[0], 1, MPI_DOUBLE, MPI_MAX, comm));
  PetscCallMPI(MPI_Allreduce(&loc[1], &glob[1], 2, MPI_DOUBLE, MPI_SUM, comm));
  linf = glob[0];
  rms = std::sqrt(glob[1] / glob[2]);
  return PETSC_SUCCESS;
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template PetscErrorCode findProbes<D>(MPI_Comm, const Scene<D> &, DM,                            \
                                        std::vector<PetscInt64> &);                                \
  template PetscErrorCode probeStates<D>(MPI_Comm, DM, const std::vector<PetscInt64> &,            \
                                         std::vector<ProbeState> &);                               \
  template PetscErrorCode mmsErrors<D>(MPI_Comm, const Scene<D> &, DM, double, double &, double &);
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

namespace {

// A particle's row for the separation measure: X0, the domain's centre, l, l0 (D each).
template <int D> constexpr int kCols = 4 * D;
using Key = std::array<long long, 3>; // lattice indices z, y, x (z = 0 in 2D)

/// Rows read from a particle view (this rank's particles) or from a packed array (the rows
/// gathered on rank 0).
template <int D> struct Rows {
  const ParticleView<D> *p = nullptr;
  const double *packed = nullptr;
  size_t n = 0;
  void row(size_t i, double r[kCols<D>]) const {
    if (packed) {
      std::copy_n(&packed[i * kCols<D>], kCols<D>, r);
      return;
    }
    const ParticleView<D> &v = *p;
    const double *corners = v.hasCorners ? &v.corners[D * (1 << D) * i] : nullptr;
    for (int d = 0; d < D; ++d) {
      // The particle's domain: centred on the material point, or the corners' box.
      r[d] = v.X0[D * i + d];
      r[D + d] = corners ? tracking::cornerBoxCentre<D>(corners, d) : v.x[D * i + d];
      r[2 * D + d] = v.l[D * i + d];
      r[3 * D + d] = v.l0[D * i + d];
    }
  }
};

/// std::llround(v) (halves away from zero) without the library call: exact for |v| < 2^52, where
/// v - trunc(v) is exact; elsewhere (and for NaN) the library's.
inline long long roundKey(double v) {
  if (!(std::fabs(v) < 4503599627370496.0)) return std::llround(v);
  const long long t = static_cast<long long>(v);
  const double f = v - static_cast<double>(t);
  return t + (f >= 0.5) - (f <= -0.5);
}

/// A lattice point's key (step q): the last axis first, so that rows of the lattice are runs of
/// the keys, as the particles are stored (by cell, x fastest).
template <int D> inline Key keyOf(const double *x, double q) {
  Key k = {0, 0, 0};
  for (int d = 0; d < D; ++d)
    k[2 - d] = roundKey(x[d] / q);
  return k;
}

/// The rows sorted by their X0 lattice key (step q), for lookups: (key, row) in key order, rows
/// of equal keys in row order. When the keys' ranges multiply to less than 2^62 (a key step is a
/// 512th of the finest cell: up to about 3,000 finest cells along each axis in 3D, 4 million in
/// 2D), the keys are packed into one integer that orders them alike, ((z - z_lo) R_y + (y -
/// y_lo)) R_x + (x - x_lo), and sorted by a stable radix sort of 11 bits a pass: time linear in
/// the rows (a history row's measure; a comparison sort grew as N log N). Otherwise a comparison
/// sort gives the same order.
template <int D> std::vector<std::pair<Key, size_t>> keyed(const Rows<D> &rows, double q) {
  const size_t n = rows.n;
  std::vector<std::pair<Key, size_t>> at(n);
  Key lo = {LLONG_MAX, LLONG_MAX, LLONG_MAX}, hi = {LLONG_MIN, LLONG_MIN, LLONG_MIN};
  double r[kCols<D>];
  for (size_t i = 0; i < n; ++i) {
    rows.row(i, r);
    at[i] = {keyOf<D>(r, q), i};
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], at[i].first[c]);
      hi[c] = std::max(hi[c], at[i].first[c]);
    }
  }
  double range[3] = {1, 1, 1}; // (in doubles: hi - lo may not fit a long long)
  for (int c = 0; c < 3 && n > 0; ++c)
    range[c] = static_cast<double>(hi[c]) - static_cast<double>(lo[c]) + 1.0;
  if (!(range[0] * range[1] * range[2] < 0x1p62)) {
    std::sort(at.begin(), at.end());
    return at;
  }
  const std::uint64_t R1 = static_cast<std::uint64_t>(range[1]),
                      R2 = static_cast<std::uint64_t>(range[2]);
  std::vector<std::pair<std::uint64_t, size_t>> a(n), b(n);
  std::uint64_t top = 0;
  for (size_t i = 0; i < n; ++i) {
    const Key &k = at[i].first;
    const auto off = [&](int c) { return static_cast<std::uint64_t>(k[c] - lo[c]); };
    a[i] = {(off(0) * R1 + off(1)) * R2 + off(2), i};
    top = std::max(top, a[i].first);
  }
  constexpr int kBits = 11;
  constexpr size_t kBuckets = size_t{1} << kBits;
  std::vector<size_t> count(kBuckets);
  for (int shift = 0; shift < 64 && (top >> shift) != 0; shift += kBits) {
    std::fill(count.begin(), count.end(), 0);
    for (const auto &e : a)
      ++count[(e.first >> shift) & (kBuckets - 1)];
    size_t sum = 0;
    for (size_t &c : count)
      sum += std::exchange(c, sum);
    for (const auto &e : a)
      b[count[(e.first >> shift) & (kBuckets - 1)]++] = e;
    a.swap(b);
  }
  std::vector<std::pair<Key, size_t>> sorted(n);
  for (size_t j = 0; j < n; ++j)
    sorted[j] = at[a[j].second];
  return sorted;
}

/// The position in `at` of the first row whose X0 is at x, or -1. The position `hint` is tried
/// first: on a lattice, walking the rows in key order, each neighbour lies one past the previous
/// row's (the same answer as a search, in one comparison).
template <int D>
long long findAt(const std::vector<std::pair<Key, size_t>> &at, double q, const double *x,
                 size_t hint) {
  const Key k = keyOf<D>(x, q);
  // (element by element: std::array's == is a library memcmp call here)
  const auto same = [&](size_t i) {
    const Key &o = at[i].first;
    return o[0] == k[0] && o[1] == k[1] && o[2] == k[2];
  };
  if (hint < at.size() && same(hint) && (hint == 0 || !same(hint - 1)))
    return static_cast<long long>(hint);
  const auto it = std::lower_bound(at.begin(), at.end(), std::make_pair(k, size_t{0}));
  return it != at.end() && it->first == k ? static_cast<long long>(it - at.begin()) : -1;
}

/// The cracks' bounding boxes (lows, then highs; D each) and 1-norm sizes, for crackBetween.
template <int D> struct CrackBoxes {
  std::vector<std::array<double, 2 * D>> box;
  std::vector<double> size;
  explicit CrackBoxes(const std::vector<CrackOf<D>> &cracks) {
    for (const CrackOf<D> &c : cracks) {
      box.push_back(cracks::bounds<D>(c));
      double n = 0;
      for (int a = 0; a < D; ++a)
        n += box.back()[D + a] - box.back()[a];
      size.push_back(n);
    }
  }
};

/// Whether a crack lies between two initial positions. A crack whose bounding box misses the
/// pair's by more than a millionth of their sizes is not asked: crossing() tests each segment's
/// box with a margin of kCrackTol (1e-9) times such sizes, so the answer is the same.
template <int D>
bool crackBetween(const std::vector<CrackOf<D>> &cracks, const CrackBoxes<D> &boxes,
                  const double *a, const double *b) {
  double len = 0;
  for (int d = 0; d < D; ++d)
    len += std::fabs(b[d] - a[d]);
  for (size_t k = 0; k < cracks.size(); ++k) {
    const auto &B = boxes.box[k];
    const double margin = 1e-6 * (len + boxes.size[k]);
    bool misses = false;
    for (int d = 0; d < D; ++d)
      misses = misses || std::min(a[d], b[d]) > B[D + d] + margin ||
               std::max(a[d], b[d]) < B[d] - margin;
    if (!misses && cracks::crossing(cracks[k], a, b) != 0) return true;
  }
  return false;
}

/// Over the rows: the largest gap between a particle and its former neighbour on the + side of
/// each axis found among the same rows (into worst); with `open`, which rows miss a neighbour on
/// some side (a neighbour that may be another rank's particle). The rows are visited in key
/// order, so that each lookup starts where the previous row's found its neighbour.
template <int D>
void gapsOfRows(const Rows<D> &rows, double q, const std::vector<CrackOf<D>> &cracks, double &worst,
                std::vector<char> *open) {
  constexpr int C = kCols<D>;
  const auto at = keyed(rows, q);
  const CrackBoxes<D> boxes(cracks);
  if (open) open->assign(rows.n, 0);
  double r[C], o[C];
  size_t last[D][2] = {}; // [axis][side]: where the previous row's neighbour was
  double w = worst;       // (in a register, not through the reference)
  for (size_t s = 0; s < at.size(); ++s) {
    const size_t i = at[s].second;
    rows.row(i, r);
    for (int d = 0; d < D; ++d)
      for (int side = -1; side <= 1; side += 2) {
        if (side < 0 && !open) continue; // only `open` needs the lower neighbours
        size_t &hint = last[d][side > 0];
        double x[D];
        for (int e = 0; e < D; ++e)
          x[e] = r[e] + (d == e) * side * 2 * r[3 * D + e];
        const long long js = findAt<D>(at, q, x, hint + 1);
        if (js < 0) {
          if (open) (*open)[i] = 1;
          continue;
        }
        hint = static_cast<size_t>(js);
        if (side < 0) continue; // each pair once: from its lower particle
        rows.row(at[hint].second, o);
        if (o[3 * D + d] != r[3 * D + d]) continue; // neighbours of another size (another level)
        if (crackBetween<D>(cracks, boxes, r, o)) continue; // a crack between them
        w = std::max(w, ((o[D + d] - o[2 * D + d]) - (r[D + d] + r[2 * D + d])) /
                            (2.0 * r[3 * D + d]));
      }
  }
  worst = w;
}

} // namespace

template <int D>
PetscErrorCode separation(MPI_Comm comm, const Lattice<D> &grid, DM sw,
                          const std::vector<CrackOf<D>> &cracks, double &gap, double &strain) {
  // Each rank measures the pairs it holds; the particles missing a neighbour on some side (at a
  // rank's border, or on a body's edge) go to rank 0, which measures the pairs among them. The
  // memory and the work on rank 0 grow with the rank borders and body edges, not with the
  // particles.
  constexpr int C = kCols<D>;
  ParticleView<D> p;
  PetscCall(p.get(sw));
  const Rows<D> mine{&p, nullptr, static_cast<size_t>(p.n)};
  // Initial positions lie on a lattice of step unit / 512.
  const double q = grid.unit / 512.0;
  double worst = 0;
  std::vector<char> open;
  gapsOfRows(mine, q, cracks, worst, &open);
  double ext[4] = {1e300, 1e300, 1e300, 1e300}; // min of lo, -hi, lo0, -hi0 along x
  std::vector<double> loc;
  double r[C];
  for (size_t i = 0; i < mine.n; ++i) {
    mine.row(i, r);
    ext[0] = std::min(ext[0], r[D] - r[2 * D]);
    ext[1] = std::min(ext[1], -(r[D] + r[2 * D]));
    ext[2] = std::min(ext[2], r[0] - r[3 * D]);
    ext[3] = std::min(ext[3], -(r[0] + r[3 * D]));
    if (open[i]) loc.insert(loc.end(), r, r + C);
  }
  PetscCall(p.restore(sw));
  std::vector<double> all;
  PetscCall(gatherToRoot(comm, loc, all));
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0)
    gapsOfRows(Rows<D>{nullptr, all.data(), all.size() / C}, q, cracks, worst, nullptr);
  double red[5] = {-worst, ext[0], ext[1], ext[2], ext[3]}, res[5];
  PetscCallMPI(MPI_Allreduce(red, res, 5, MPI_DOUBLE, MPI_MIN, comm));
  gap = -res[0];
  strain = (-res[2] - res[1]) / (-res[4] - res[3]) - 1.0;
  return PETSC_SUCCESS;
}

template PetscErrorCode separation<2>(MPI_Comm, const Lattice<2> &, DM,
                                      const std::vector<CrackOf<2>> &, double &, double &);
template PetscErrorCode separation<3>(MPI_Comm, const Lattice<3> &, DM,
                                      const std::vector<CrackOf<3>> &, double &, double &);

} // namespace gimp
