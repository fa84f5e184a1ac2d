#include "gimp/diagnostics/gather.hpp"
#include "gimp/io/checked.hpp"
#include "gimp/io/output.hpp"
#include "gimp/particles/swarm.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace gimp {

namespace {

/// "option -OPTION FILE: cannot WHAT the file (reason)".
std::string fileError(const std::string &option, const std::string &file, const char *what,
                      const std::string &reason) {
  return "option -" + option + " " + file + ": cannot " + what + " the file (" + reason + ")";
}

} // namespace

PetscErrorCode writeParticleDump(MPI_Comm comm, DM sw, const std::string &file) {
  // Gather id and state on rank 0, sorted by id: rank-independent for comparisons.
  constexpr int kCols = 12;
  ParticleView p;
  PetscCall(p.get(sw));
  std::vector<double> loc(static_cast<size_t>(p.n) * kCols);
  for (PetscInt k = 0; k < p.n; ++k) {
    const auto s = tensorAt<2>(p.s, k);
    const double row[kCols] = {static_cast<double>(p.id[k]),
                               p.x[2 * k],
                               p.x[2 * k + 1],
                               p.v[2 * k],
                               p.v[2 * k + 1],
                               s(0, 0),
                               s(1, 1),
                               s(0, 1),
                               p.szz[k],
                               p.V[k],
                               p.l[2 * k],
                               p.l[2 * k + 1]};
    std::copy(row, row + kCols, &loc[static_cast<size_t>(k) * kCols]);
  }
  PetscCall(p.restore(sw));
  std::vector<double> all;
  PetscCall(gatherToRoot(comm, loc, all));
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  FILE *f = rank == 0 ? std::fopen(file.c_str(), "w") : nullptr;
  PetscCall(agree(comm, rank == 0 && !f
                            ? fileError("gimp_particle_dump", file, "open", std::strerror(errno))
                            : std::string()));
  if (rank != 0) return agree(comm, "");
  const size_t n = all.size() / kCols;
  std::vector<size_t> order(n);
  for (size_t i = 0; i < n; ++i)
    order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return all[a * kCols] < all[b * kCols]; });
  std::fprintf(f, "id,x,y,vx,vy,sxx,syy,sxy,szz,V,lx,ly\n");
  for (size_t i : order) {
    const double *r = &all[i * kCols];
    std::fprintf(f, "%.0f", r[0]);
    for (int c = 1; c < kCols; ++c)
      std::fprintf(f, ",%.17g", r[c]);
    std::fprintf(f, "\n");
  }
  const std::string reason = closeChecked(f);
  std::error_code ec; // remove a partial dump, never a device or other special file
  if (!reason.empty() && std::filesystem::is_regular_file(file, ec))
    std::filesystem::remove(file, ec);
  PetscCall(
      agree(comm, reason.empty() ? "" : fileError("gimp_particle_dump", file, "write", reason)));
  return PETSC_SUCCESS;
}

} // namespace gimp
