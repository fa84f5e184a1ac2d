// Particle files (see include/gimp/input/particle_file.hpp).
#include "gimp/input/particle_file.hpp"
#include "gimp/core/errors.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace gimp {

namespace {

std::string trim(const std::string &s) {
  const size_t a = s.find_first_not_of(" \t\r"), b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

std::vector<std::string> split(const std::string &line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string f;
  while (std::getline(ss, f, ','))
    out.push_back(trim(f));
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

/// Parses the file; returns "" or why it cannot be used.
std::string parse(const std::string &path, double thickness, ParticleFile &out) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return "is a directory, not a file";
  std::ifstream in(path);
  if (!in) return "cannot open the file";
  std::string line;
  if (!std::getline(in, line)) return "the file is empty (a header line x,y,... is needed)";
  const std::vector<std::string> cols = split(line);
  std::map<std::string, size_t> at;
  const char *ignored[] = {"id", "sxx", "syy", "sxy", "szz"};
  for (size_t c = 0; c < cols.size(); ++c) {
    bool known = false;
    for (const char *k : {"x", "y", "lx", "ly", "V", "vx", "vy"})
      known |= cols[c] == k;
    bool skip = false;
    for (const char *k : ignored)
      skip |= cols[c] == k;
    if (!known && !skip)
      return "unknown column '" + cols[c] + "' (columns: x, y, lx, ly, V, vx, vy)";
    if (at.count(cols[c])) return "column '" + cols[c] + "' appears twice";
    at[cols[c]] = c;
  }
  if (!at.count("x") || !at.count("y")) return "needs the columns x and y";
  if (at.count("lx") != at.count("ly")) return "needs both lx and ly, or neither";
  if (at.count("vx") != at.count("vy")) return "needs both vx and vy, or neither";
  if (!at.count("lx") && !at.count("V")) return "needs lx, ly (half-sizes) or V (volume)";
  out.hasVelocity = at.count("vx") > 0;
  size_t row = 1;
  while (std::getline(in, line)) {
    ++row;
    if (trim(line).empty()) continue;
    const std::vector<std::string> f = split(line);
    const std::string where = "line " + std::to_string(row);
    if (f.size() != cols.size())
      return where + " has " + std::to_string(f.size()) + " values for " +
             std::to_string(cols.size()) + " columns";
    std::vector<double> v(f.size());
    for (size_t c = 0; c < f.size(); ++c) {
      char *end = nullptr;
      v[c] = std::strtod(f[c].c_str(), &end);
      if (f[c].empty() || *end != '\0') return where + ": '" + f[c] + "' is not a number";
      if (!std::isfinite(v[c])) return where + ": the values must be finite numbers";
    }
    FileParticle p;
    p.x = v[at["x"]];
    p.y = v[at["y"]];
    if (at.count("V")) {
      if (!(v[at["V"]] > 0)) return where + ": V must be > 0";
      p.area = v[at["V"]] / thickness;
    }
    if (at.count("lx")) {
      p.lx = v[at["lx"]];
      p.ly = v[at["ly"]];
      if (!(p.lx > 0) || !(p.ly > 0)) return where + ": lx and ly must be > 0";
      if (!at.count("V")) p.area = 4.0 * p.lx * p.ly;
    } else {
      p.lx = p.ly = 0.5 * std::sqrt(p.area);
    }
    // A size so small that its area or a half-size is not a normal double (below 2.2e-308)
    // would give the particle no mass, and the run would fail later for another reason.
    if (!std::isnormal(p.area) || !std::isnormal(p.lx) || !std::isnormal(p.ly))
      return where + ": the particle's size is too small to represent (its area " +
             formatNumber(p.area) + " m^2 or a half-size is below 2.2e-308)";
    if (out.hasVelocity) {
      p.vx = v[at["vx"]];
      p.vy = v[at["vy"]];
    }
    out.particles.push_back(p);
  }
  if (out.particles.empty()) return "holds no particle";
  return "";
}

} // namespace

PetscErrorCode readParticleFile(MPI_Comm comm, const std::string &opt, const std::string &path,
                                double thickness, ParticleFile &out) {
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::string why;
  out = ParticleFile{};
  if (rank == 0) why = parse(path, thickness, out);
  // Every rank learns the same outcome: the error text, then the particles.
  long long sizes[3] = {static_cast<long long>(why.size()),
                        static_cast<long long>(out.particles.size()), out.hasVelocity ? 1 : 0};
  PetscCallMPI(MPI_Bcast(sizes, 3, MPI_LONG_LONG, 0, comm));
  why.resize(static_cast<size_t>(sizes[0]));
  if (sizes[0]) PetscCallMPI(MPI_Bcast(why.data(), static_cast<int>(sizes[0]), MPI_CHAR, 0, comm));
  if (!why.empty()) throw InputError("option " + opt + " " + path + ": " + why);
  out.particles.resize(static_cast<size_t>(sizes[1]));
  out.hasVelocity = sizes[2] != 0;
  static_assert(sizeof(FileParticle) == 7 * sizeof(double), "FileParticle is 7 doubles");
  PetscCallMPI(
      MPI_Bcast(out.particles.data(), static_cast<int>(7 * sizes[1]), MPI_DOUBLE, 0, comm));
  return PETSC_SUCCESS;
}

} // namespace gimp
