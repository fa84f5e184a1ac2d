// The hole measure: the hoop stress at a hole's edge as a curve over the angle, fitted from the
// particles next to the edge (see HoleMeasure in include/gimp/diagnostics/measures.hpp).
#include "gimp/diagnostics/gather.hpp"
#include "gimp/diagnostics/measures.hpp"
#include "gimp/particles/swarm.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace gimp {

namespace {

constexpr int kCols = 4;          // rows: angle [rad], distance to the centre, hoop / p, half-size
constexpr double kBinDeg = 5.0;   // the curve's angle step
constexpr double kWindowDeg = 10; // the fit window's half-width (at least kWindow sizes)
constexpr double kWindow = 4.0;   // ... in particle sizes along the edge
constexpr double kDepth = 0.5;    // the fit's depth over the radius (at least kLayers sizes)
constexpr double kLayers = 3.0;

/// Least-squares edge value at angle t0 [rad] from the particles in the window: with u =
/// (r / d)^2 - 1 (0 at the edge) and dt the angle from t0, hoop = c0 + c1 u + c2 u^2 + c3 dt +
/// c4 dt^2 + c5 u dt + c6 u dt^2 (fewer terms when few particles). A smooth field next to the
/// edge of a circle is a series in 1 / d^2 (Kirsch's field is quadratic in it at each angle),
/// so the window's depth adds no bias of its own: on Kirsch's exact field at the particles of
/// the a / 16 plate this fit is within 0.003 of the edge curve. Returns the value and the
/// particle count.
std::pair<double, int> edgeFit(const std::vector<double> &all, double r, double size, double t0) {
  std::vector<int> in;
  const double win = std::max(kWindowDeg * M_PI / 180.0, kWindow * size / r);
  const double depth = std::max(kDepth * r, kLayers * size);
  for (size_t i = 0; i < all.size() / kCols; ++i)
    if (std::fabs(all[kCols * i] - t0) <= win && all[kCols * i + 1] - r <= depth)
      in.push_back(static_cast<int>(i));
  const int n = static_cast<int>(in.size());
  if (n == 0) return {std::numeric_limits<double>::quiet_NaN(), 0};
  const int terms = n >= 21 ? 7 : n >= 15 ? 5 : n >= 6 ? 3 : 1;
  Eigen::MatrixXd A(n, terms);
  Eigen::VectorXd b(n);
  for (int k = 0; k < n; ++k) {
    const double *q = &all[kCols * in[k]];
    const double u = (r / q[1]) * (r / q[1]) - 1.0, dt = q[0] - t0;
    const double basis[7] = {1.0, u, dt, u * u, dt * dt, u * dt, u * dt * dt};
    for (int j = 0; j < terms; ++j)
      A(k, j) = basis[j];
    b(k) = q[2];
  }
  const Eigen::VectorXd c = A.colPivHouseholderQr().solve(b);
  return {c(0), n};
}

/// On rank 0: the measure from the gathered rows of the particles next to a hole of radius r.
void holeOfRows(const std::vector<double> &all, double r, HoleMeasure &out) {
  const size_t n = all.size() / kCols;
  // The particle size next to the edge: the median of the particles within 1.5 sizes of it.
  std::vector<double> sizes;
  for (size_t i = 0; i < n; ++i)
    if (all[kCols * i + 1] - r <= 3.0 * all[kCols * i + 3]) sizes.push_back(2 * all[kCols * i + 3]);
  if (sizes.empty()) return;
  std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
  const double size = sizes[sizes.size() / 2];
  // The first layer (hoop.csv) and the particle on the 90-degree ray nearest to the edge.
  std::vector<size_t> first;
  double nearest = 1e300;
  for (size_t i = 0; i < n; ++i) {
    const double *q = &all[kCols * i];
    if (q[1] - r <= 1.5 * q[3]) first.push_back(i);
    if (std::fabs(std::cos(q[0])) * q[1] <= 1.5 * q[3] && q[1] < nearest) {
      nearest = q[1];
      out.ktParticle = q[2];
    }
  }
  std::sort(first.begin(), first.end(),
            [&](size_t a, size_t b) { return all[kCols * a] < all[kCols * b]; });
  for (size_t i : first) {
    const double th = all[kCols * i], rr = all[kCols * i + 1], a2 = r * r / (rr * rr);
    const double kirsch = 0.5 * (1 + a2) - 0.5 * (1 + 3 * a2 * a2) * std::cos(2 * th);
    out.rows.push_back({th * 180.0 / M_PI, rr, all[kCols * i + 2], kirsch});
  }
  // The curve over the angles the particles cover, 5 degrees apart.
  double lo = 1e300, hi = -1e300;
  for (size_t i = 0; i < n; ++i) {
    lo = std::min(lo, all[kCols * i]);
    hi = std::max(hi, all[kCols * i]);
  }
  // Every bin whose window holds particles (a symmetry line's bin sees one side of it).
  const int a0 = static_cast<int>(std::floor(lo * 180.0 / M_PI / kBinDeg));
  const int a1 = static_cast<int>(std::ceil(hi * 180.0 / M_PI / kBinDeg));
  out.maxError = 0;
  for (int a = a0; a <= a1; ++a) {
    const double deg = a * kBinDeg, t = deg * M_PI / 180.0;
    const auto [value, count] = edgeFit(all, r, size, t);
    const double kirsch = 1.0 - 2.0 * std::cos(2 * t);
    out.curve.push_back({deg, value, kirsch, static_cast<double>(count)});
    if (std::isfinite(value)) out.maxError = std::max(out.maxError, std::fabs(value - kirsch));
    if (a == 18) out.kt = value;
    if (a >= 0 && a <= 18 && a % 3 == 0) out.hoopByAngle[a / 3] = value;
  }
}

/// Whether particle k is beyond the fits' reach of the hole's edge (in-plane distance d).
template <int D> bool beyondFits(const ParticleView<D> &p, PetscInt k, double d, double r) {
  const double l = std::max(p.l[D * k], p.l[D * k + 1]);
  return d - r > std::max(kDepth * r, 2.0 * kLayers * l);
}

/// The hole's layers (3D, a cylinder along z): the initial z of the particles the fits reach
/// spans [zlo, zhi]; the measure takes the particles whose initial centre lies within 1.5
/// half-sizes of its middle (two layers straddling it, or the one on it), whose hoop stress is
/// the surface's halfway through the body. In 2D every particle is in the plane.
template <int D> struct MidLayers {
  double mid = 0;
  PetscErrorCode find(MPI_Comm comm, const ParticleView<D> &p, const double *hole) {
    if constexpr (D == 3) {
      double lo = 1e300, hi = -1e300; // -min z, max z
      for (PetscInt k = 0; k < p.n; ++k) {
        const double d = std::hypot(p.x[3 * k] - hole[0], p.x[3 * k + 1] - hole[1]);
        if (beyondFits<3>(p, k, d, hole[2])) continue;
        lo = std::min(lo, p.X0[3 * k + 2] - p.l0[3 * k + 2]);
        hi = std::max(hi, p.X0[3 * k + 2] + p.l0[3 * k + 2]);
      }
      double span[2] = {-lo, hi};
      PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, span, 2, MPI_DOUBLE, MPI_MAX, comm));
      mid = 0.5 * (span[1] - span[0]);
    }
    return PETSC_SUCCESS;
  }
  bool holds(const ParticleView<D> &p, PetscInt k) const {
    if constexpr (D == 3) return std::fabs(p.X0[3 * k + 2] - mid) <= 1.5 * p.l0[3 * k + 2];
    return true;
  }
};

} // namespace

template <int D>
PetscErrorCode holeMeasure(MPI_Comm comm, const Scene<D> &sc, DM sw, HoleMeasure &out) {
  const double cx = sc.hole[0], cy = sc.hole[1], r = sc.hole[2], pload = sc.holeLoad;
  ParticleView<D> p;
  PetscCall(p.get(sw));
  MidLayers<D> layers;
  PetscCall(layers.find(comm, p, sc.hole));
  std::vector<double> loc;
  for (PetscInt k = 0; k < p.n; ++k) {
    const double dx = p.x[D * k] - cx, dy = p.x[D * k + 1] - cy, d = std::hypot(dx, dy);
    if (beyondFits<D>(p, k, d, r) || !layers.holds(p, k)) continue; // the fits' particles
    const double c = dx / d, s = dy / d;
    const Tensor<D> sg = stressAt<D>(p.s, k);
    const double hoop = sg(0, 0) * s * s - 2.0 * sg(0, 1) * s * c + sg(1, 1) * c * c;
    loc.insert(loc.end(),
               {std::atan2(dy, dx), d, hoop / pload, std::max(p.l[D * k], p.l[D * k + 1])});
  }
  PetscCall(p.restore(sw));
  std::vector<double> all;
  PetscCall(gatherToRoot(comm, loc, all));
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  out = HoleMeasure{};
  out.hoopByAngle.assign(HoleMeasure::kAngles, std::numeric_limits<double>::quiet_NaN());
  if (rank == 0 && !all.empty()) holeOfRows(all, r, out);
  double res[3] = {out.kt, out.ktParticle, out.maxError};
  PetscCallMPI(MPI_Bcast(res, 3, MPI_DOUBLE, 0, comm));
  PetscCallMPI(MPI_Bcast(out.hoopByAngle.data(), HoleMeasure::kAngles, MPI_DOUBLE, 0, comm));
  out.kt = res[0];
  out.ktParticle = res[1];
  out.maxError = res[2];
  return PETSC_SUCCESS;
}

template PetscErrorCode holeMeasure<2>(MPI_Comm, const Scene<2> &, DM, HoleMeasure &);
template PetscErrorCode holeMeasure<3>(MPI_Comm, const Scene<3> &, DM, HoleMeasure &);

} // namespace gimp
