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

template <int D> PetscErrorCode writeParticleDump(MPI_Comm comm, DM sw, const std::string &file) {
  // id, x, v, the stress components, V, l: 12 columns in 2D, 17 in 3D.
  static const char *const axes[] = {"x", "y", "z"};
  std::string header = "id";
  for (const char *what : {"", "v"})
    for (int a = 0; a < D; ++a)
      header += std::string(",") + what + axes[a];
  for (const char *c : stressComponents<D>())
    header += std::string(",s") + c;
  header += ",V";
  for (int a = 0; a < D; ++a)
    header += std::string(",l") + axes[a];
  const int ns = static_cast<int>(stressComponents<D>().size()), cols = 2 + 3 * D + ns;
  ParticleView<D> p;
  PetscCall(p.get(sw));
  std::vector<double> loc(static_cast<size_t>(p.n) * cols);
  for (PetscInt k = 0; k < p.n; ++k) {
    double *r = &loc[static_cast<size_t>(k) * cols];
    r[0] = static_cast<double>(p.id[k]);
    for (int a = 0; a < D; ++a) {
      r[1 + a] = p.x[D * k + a];
      r[1 + D + a] = p.v[D * k + a];
      r[2 + 2 * D + ns + a] = p.l[D * k + a];
    }
    stressOf<D>(p, k, r + 1 + 2 * D);
    r[1 + 2 * D + ns] = p.V[k];
  }
  PetscCall(p.restore(sw));
  return writeRowsById(comm, file, header.c_str(), cols, loc);
}

template PetscErrorCode writeParticleDump<2>(MPI_Comm, DM, const std::string &);
template PetscErrorCode writeParticleDump<3>(MPI_Comm, DM, const std::string &);

PetscErrorCode writeRowsById(MPI_Comm comm, const std::string &file, const char *header, int cols,
                             const std::vector<double> &loc) {
  // Gathered on rank 0 and sorted by id (column 0): rank-independent for comparisons.
  std::vector<double> all;
  PetscCall(gatherToRoot(comm, loc, all));
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  FILE *f = rank == 0 ? std::fopen(file.c_str(), "w") : nullptr;
  PetscCall(agree(comm, rank == 0 && !f
                            ? fileError("gimp_particle_dump", file, "open", std::strerror(errno))
                            : std::string()));
  if (rank != 0) return agree(comm, "");
  const size_t n = all.size() / static_cast<size_t>(cols);
  std::vector<size_t> order(n);
  for (size_t i = 0; i < n; ++i)
    order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return all[a * cols] < all[b * cols]; });
  std::fprintf(f, "%s\n", header);
  for (size_t i : order) {
    const double *r = &all[i * cols];
    std::fprintf(f, "%.0f", r[0]);
    for (int c = 1; c < cols; ++c)
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
