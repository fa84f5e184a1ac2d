// Estimate of the run's size from the scene, and the refusal of what cannot fit.
#include "gimp/input/problem_size.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace gimp {

namespace {

/// The area (2D) or volume (3D) two boxes share.
template <int D> long double overlap(const BoxOf<D> &a, const BoxOf<D> &b) {
  long double v = 1;
  for (int d = 0; d < D; ++d) {
    const long double w =
        std::min<long double>(a[D + d], b[D + d]) - std::max<long double>(a[d], b[d]);
    if (!(w > 0)) return 0;
    v *= w;
  }
  return v;
}

std::string approx(long double v) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.3Lg", v);
  return b;
}

std::string gigabytes(long double bytes) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.3Lg GB", bytes / 1e9L);
  return b;
}

template <int D> std::string boxText(const BoxOf<D> &b) {
  std::string r;
  for (int i = 0; i < 2 * D; ++i)
    r += (i ? "," : "") + formatNumber(b[i]);
  return r;
}

/// The largest particles per cell of a body (also the hole band's).
template <int D> int largestPpc(const Body<D> &b) {
  return std::max(b.ppc, b.holePpc);
}

/// The particles a body adds in the bands around its holes at hole_ppc, on the finest cells (an
/// upper bound).
long double holeBands(const Body<2> &body, long double h) {
  long double n = 0;
  for (const Hole &c : body.holes) {
    const long double band = body.holeBand > 0 ? body.holeBand : h;
    const long double area = M_PI * ((c.r + band) * (c.r + band) - c.r * c.r);
    n += area / (h * h) * std::max(body.holePpc - body.ppc, 0);
  }
  return n;
}
long double holeBands(const Body<3> &body, long double h) {
  long double n = 0;
  const long double band = body.holeBand > 0 ? body.holeBand : h;
  for (const Solid &s : body.holes) {
    const long double r = s.r, R = r + band;
    long double shell = 0; // the band's volume
    if (s.kind == Solid::Sphere) shell = 4.0L / 3 * M_PI * (R * R * R - r * r * r);
    if (s.kind == Solid::Cylinder) // through the body: its box's extent along the axis
      shell = M_PI * (R * R - r * r) * (body.box[3 + s.axis] - body.box[s.axis]);
    n += shell / (h * h * h) * std::max(body.holePpc - body.ppc, 0);
  }
  return n;
}

/// The particles of a body from a particle file, or -1.
template <int D> long double fileParticles(const Body<D> &b) {
  return b.file.empty() ? -1 : static_cast<long double>(b.fromFile.particles.size());
}

/// Physical memory of the nodes the ranks run on: each rank adds its node's memory divided by
/// the ranks sharing that node.
PetscErrorCode physicalMemory(MPI_Comm comm, long double &bytes) {
  MPI_Comm node;
  PetscMPIInt local = 1;
  PetscCallMPI(MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node));
  PetscCallMPI(MPI_Comm_size(node, &local));
  PetscCallMPI(MPI_Comm_free(&node));
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  double mine = pages > 0 && page > 0 ? static_cast<double>(pages) * page / local : 0, all = 0;
  PetscCallMPI(MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_SUM, comm));
  bytes = all;
  return PETSC_SUCCESS;
}

/// The option most likely to be wrong when the estimate is too large, with its value.
template <int D>
std::string culprit(const Scene<D> &sc, const SizeEstimate &e, const ItemBytes &cost) {
  const auto nodeMax = std::max_element(e.levelNodes.begin(), e.levelNodes.end());
  const auto bodyMax = std::max_element(e.bodyParticles.begin(), e.bodyParticles.end());
  if (e.nodes * cost.node >= e.particles * cost.particle) {
    const size_t k = static_cast<size_t>(nodeMax - e.levelNodes.begin());
    if (k > 0) return "-gimp_level" + std::to_string(k) + "_box " + boxText<D>(sc.levels[k].box);
    if (sc.domainGiven) return "-gimp_domain " + boxText<D>(sc.domain);
    double widest = 0;
    for (int d = 0; d < D; ++d)
      widest = std::max(widest, sc.domain[D + d] - sc.domain[d]);
    if (static_cast<long double>(sc.pad) * sc.h > 0.25L * widest)
      return "-gimp_pad " + std::to_string(sc.pad);
    return "-gimp_h " + formatNumber(sc.h);
  }
  const size_t b = static_cast<size_t>(bodyMax - e.bodyParticles.begin());
  const Body<D> &body = sc.bodies[b];
  const std::string p = "-gimp_body" + std::to_string(b) + "_";
  if (largestPpc(body) >= 256)
    return largestPpc(body) > body.ppc ? p + "hole_ppc " + std::to_string(largestPpc(body))
                                       : p + "ppc " + std::to_string(body.ppc);
  double longest = 0, shortest = 1e300;
  for (int d = 0; d < D; ++d) {
    longest = std::max(longest, body.box[D + d] - body.box[d]);
    shortest = std::min(shortest, body.box[D + d] - body.box[d]);
  }
  if (longest > 1000 * shortest) return p + body.shapeOption + " " + boxText<D>(body.box);
  return "-gimp_h " + formatNumber(sc.h);
}

} // namespace

template <int D> SizeEstimate estimateSize(const Scene<D> &sc, const ItemBytes &cost) {
  SizeEstimate e;
  const size_t K = sc.levels.size();
  std::vector<long double> h(K), cell(K);
  for (size_t k = 0; k < K; ++k) {
    h[k] = k ? h[k - 1] / sc.levels[k].ratio : static_cast<long double>(sc.h);
    cell[k] = h[k];
    for (int d = 1; d < D; ++d)
      cell[k] *= h[k];
    const BoxOf<D> &b = k ? sc.levels[k].box : sc.domain;
    std::vector<long double> axes(D);
    long double nodes = 1;
    for (int d = 0; d < D; ++d) {
      axes[d] = std::round((static_cast<long double>(b[D + d]) - b[d]) / h[k]) + 1;
      nodes *= axes[d];
    }
    e.levelAxes.push_back(axes);
    e.levelNodes.push_back(nodes);
    e.nodes += nodes;
  }
  for (const Body<D> &body : sc.bodies) {
    if (const long double file = fileParticles(body); file >= 0) { // a particle file's
      e.bodyParticles.push_back(file);
      e.particles += file;
      continue;
    }
    // Each level seeds the part of the body's box it covers and no finer level does.
    long double n = 0;
    for (size_t k = 0; k < K; ++k) {
      const long double here = overlap<D>(body.box, k ? sc.levels[k].box : sc.domain);
      const long double finer = k + 1 < K ? overlap<D>(body.box, sc.levels[k + 1].box) : 0;
      n += std::max<long double>(here - finer, 0) / cell[k] * body.ppc;
    }
    n += holeBands(body, h[K - 1]);
    e.bodyParticles.push_back(n);
    e.particles += n;
  }
  e.bytes = e.nodes * cost.node + e.particles * cost.particle;
  return e;
}

template <int D>
PetscErrorCode checkProblemSize(MPI_Comm comm, const Scene<D> &sc, const ItemBytes &cost) {
  const SizeEstimate e = estimateSize(sc, cost);
  PetscMPIInt size = 1;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  const long double maxInt = static_cast<long double>(PETSC_MAX_INT);
  const std::string what = "the scene needs about " + approx(e.particles) + " particles and " +
                           approx(e.nodes) + " grid nodes";
  for (size_t k = 0; k < e.levelNodes.size(); ++k) {
    if (!(D * e.levelNodes[k] > maxInt)) continue;
    std::string axes;
    for (int d = 0; d < D; ++d)
      axes += (d ? " x " : "") + approx(e.levelAxes[k][d]);
    throw InputError("option " + culprit(sc, e, cost) + ": " + what + " (level " +
                     std::to_string(k) + ": " + axes + "), more than PetscInt can index (" +
                     approx(maxInt) +
                     " values per level); use a coarser grid or a smaller "
                     "domain");
  }
  // The composite vector of all levels (D values a node), the swarm's global count and each
  // rank's stencil entries (kStencil nodes a particle) are PetscInts too.
  constexpr long double kStencil = D == 2 ? 16 : 27;
  if (D * e.nodes > maxInt)
    throw InputError("option " + culprit(sc, e, cost) + ": " + what + " (" + approx(D * e.nodes) +
                     " values in the composite vector of the levels), " +
                     "more than PetscInt can index (" + approx(maxInt) +
                     "); use a coarser grid or a smaller domain");
  if (e.particles > maxInt)
    throw InputError("option " + culprit(sc, e, cost) + ": " + what +
                     ", more than the particle swarm counts in a PetscInt (" + approx(maxInt) +
                     "); use fewer particles");
  long double limit = sc.memoryLimit;
  if (!(limit > 0)) PetscCall(physicalMemory(comm, limit));
  if (limit > 0 && e.bytes > limit)
    throw InputError("option " + culprit(sc, e, cost) + ": " + what + ", about " +
                     gigabytes(e.bytes) + " of memory, more than the " + gigabytes(limit) +
                     (sc.memoryLimit > 0 ? " of -gimp_memory_limit"
                                         : " of physical memory (-gimp_memory_limit)") +
                     "; use a coarser grid, fewer particles per cell or smaller bodies");
  // A run the memory allows (or a limit raised above it) still needs its stencil index.
  if (e.particles / size > maxInt / kStencil)
    throw InputError("option " + culprit(sc, e, cost) + ": " + what + ", about " +
                     approx(e.particles / size * kStencil) +
                     " stencil entries per rank, more than PetscInt counts (" + approx(maxInt) +
                     "); use fewer particles or more ranks");
  return PETSC_SUCCESS;
}

template SizeEstimate estimateSize<2>(const Scene<2> &, const ItemBytes &);
template SizeEstimate estimateSize<3>(const Scene<3> &, const ItemBytes &);
template PetscErrorCode checkProblemSize<2>(MPI_Comm, const Scene<2> &, const ItemBytes &);
template PetscErrorCode checkProblemSize<3>(MPI_Comm, const Scene<3> &, const ItemBytes &);

} // namespace gimp
