// Estimate of the run's size from the scene, and the refusal of what cannot fit.
#include "gimp/input/problem_size.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace gimp {

namespace {

long double overlap(const BoxOf<2> &a, const BoxOf<2> &b) {
  const long double w = std::min<long double>(a[2], b[2]) - std::max<long double>(a[0], b[0]);
  const long double h = std::min<long double>(a[3], b[3]) - std::max<long double>(a[1], b[1]);
  return w > 0 && h > 0 ? w * h : 0;
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

std::string boxText(const BoxOf<2> &b) {
  return formatNumber(b[0]) + "," + formatNumber(b[1]) + "," + formatNumber(b[2]) + "," +
         formatNumber(b[3]);
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
std::string culprit(const Scene<2> &sc, const SizeEstimate &e, const ItemBytes &cost) {
  const auto nodeMax = std::max_element(e.levelNodes.begin(), e.levelNodes.end());
  const auto bodyMax = std::max_element(e.bodyParticles.begin(), e.bodyParticles.end());
  if (e.nodes * cost.node >= e.particles * cost.particle) {
    const size_t k = static_cast<size_t>(nodeMax - e.levelNodes.begin());
    if (k > 0) return "-gimp_level" + std::to_string(k) + "_box " + boxText(sc.levels[k].box);
    if (sc.domainGiven) return "-gimp_domain " + boxText(sc.domain);
    if (static_cast<long double>(sc.pad) * sc.h >
        0.25L * std::max(sc.domain[2] - sc.domain[0], sc.domain[3] - sc.domain[1]))
      return "-gimp_pad " + std::to_string(sc.pad);
    return "-gimp_h " + formatNumber(sc.h);
  }
  const size_t b = static_cast<size_t>(bodyMax - e.bodyParticles.begin());
  const Body<2> &body = sc.bodies[b];
  const std::string p = "-gimp_body" + std::to_string(b) + "_";
  if (std::max(body.ppc, body.holePpc) >= 256)
    return body.holePpc > body.ppc ? p + "hole_ppc " + std::to_string(body.holePpc)
                                   : p + "ppc " + std::to_string(body.ppc);
  const double w = body.box[2] - body.box[0], h = body.box[3] - body.box[1];
  if (std::max(w, h) > 1000 * std::min(w, h)) return p + "box " + boxText(body.box);
  return "-gimp_h " + formatNumber(sc.h);
}

} // namespace

SizeEstimate estimateSize(const Scene<2> &sc, const ItemBytes &cost) {
  SizeEstimate e;
  const size_t K = sc.levels.size();
  std::vector<long double> h(K);
  for (size_t k = 0; k < K; ++k) {
    h[k] = k ? h[k - 1] / sc.levels[k].ratio : static_cast<long double>(sc.h);
    const BoxOf<2> &b = k ? sc.levels[k].box : sc.domain;
    e.levelM.push_back(std::round((static_cast<long double>(b[2]) - b[0]) / h[k]) + 1);
    e.levelN.push_back(std::round((static_cast<long double>(b[3]) - b[1]) / h[k]) + 1);
    e.levelNodes.push_back(e.levelM.back() * e.levelN.back());
    e.nodes += e.levelNodes.back();
  }
  for (const Body<2> &body : sc.bodies) {
    if (!body.file.empty()) { // a particle file: its particles
      e.bodyParticles.push_back(static_cast<long double>(body.fromFile.particles.size()));
      e.particles += e.bodyParticles.back();
      continue;
    }
    // Each level seeds the part of the body it covers and no finer level does.
    long double n = 0;
    for (size_t k = 0; k < K; ++k) {
      const long double here = overlap(body.box, k ? sc.levels[k].box : sc.domain);
      const long double finer = k + 1 < K ? overlap(body.box, sc.levels[k + 1].box) : 0;
      n += std::max<long double>(here - finer, 0) / (h[k] * h[k]) * body.ppc;
    }
    // The band around each hole at hole_ppc, on the finest cells (an upper bound).
    for (const Hole &c : body.holes) {
      const long double band = body.holeBand > 0 ? body.holeBand : h[K - 1];
      const long double area = M_PI * ((c.r + band) * (c.r + band) - c.r * c.r);
      n += area / (h[K - 1] * h[K - 1]) * std::max(body.holePpc - body.ppc, 0);
    }
    e.bodyParticles.push_back(n);
    e.particles += n;
  }
  e.bytes = e.nodes * cost.node + e.particles * cost.particle;
  return e;
}

PetscErrorCode checkProblemSize(MPI_Comm comm, const Scene<2> &sc, const ItemBytes &cost) {
  const SizeEstimate e = estimateSize(sc, cost);
  PetscMPIInt size = 1;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  const long double maxInt = static_cast<long double>(PETSC_MAX_INT);
  const std::string what = "the scene needs about " + approx(e.particles) + " particles and " +
                           approx(e.nodes) + " grid nodes";
  for (size_t k = 0; k < e.levelNodes.size(); ++k)
    if (2 * e.levelNodes[k] > maxInt)
      throw InputError("option " + culprit(sc, e, cost) + ": " + what + " (level " +
                       std::to_string(k) + ": " + approx(e.levelM[k]) + " x " +
                       approx(e.levelN[k]) + "), more than PetscInt can index (" + approx(maxInt) +
                       " values per level); use a coarser grid or a smaller "
                       "domain");
  if (e.particles / size > maxInt)
    throw InputError("option " + culprit(sc, e, cost) + ": " + what +
                     ", more per rank than "
                     "PetscInt counts (" +
                     approx(maxInt) + "); use fewer particles or more ranks");
  long double limit = sc.memoryLimit;
  if (!(limit > 0)) PetscCall(physicalMemory(comm, limit));
  if (limit > 0 && e.bytes > limit)
    throw InputError("option " + culprit(sc, e, cost) + ": " + what + ", about " +
                     gigabytes(e.bytes) + " of memory, more than the " + gigabytes(limit) +
                     (sc.memoryLimit > 0 ? " of -gimp_memory_limit"
                                         : " of physical memory (-gimp_memory_limit)") +
                     "; use a coarser grid, fewer particles per cell or smaller bodies");
  return PETSC_SUCCESS;
}

} // namespace gimp
